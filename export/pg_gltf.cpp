// pg_gltf.cpp - the tinygltf adapter behind pg_gltf.h.
//
// Layout of the model: one buffer (the .glb's binary chunk) holding, in order, every
// distinct vertex/index array and then every embedded image; one buffer view per
// array or image; one accessor per distinct array (POSITION carries the exact
// min/max of its floats, as glTF requires); one sampler (linear mipmapped, clamped
// at the face edges so faces never bleed into each other); one texture per image
// used as a texture; one material per primitive; one mesh; one node; one scene.
// Debian's libtinygltf carries the implementation, so TINYGLTF_IMPLEMENTATION is
// not defined here, and its image writer is switched off: images arrive encoded.
#include "pg_gltf.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {

struct builder {
    tinygltf::Model m;
    std::map<const void *, int> accessor_of; // shared arrays -> accessor

    int add_view(const void *data, size_t bytes, int target) {
        std::vector<unsigned char> &buf = m.buffers[0].data;
        while (buf.size() % 4)
            buf.push_back(0); // 4-byte alignment for every view
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = buf.size();
        v.byteLength = bytes;
        v.target = target;
        const unsigned char *p = static_cast<const unsigned char *>(data);
        buf.insert(buf.end(), p, p + bytes);
        m.bufferViews.push_back(v);
        return (int)m.bufferViews.size() - 1;
    }

    int add_float_accessor(const float *a, uint32_t count, int ncomp, bool minmax) {
        auto it = accessor_of.find(a);
        if (it != accessor_of.end()) return it->second;
        tinygltf::Accessor acc;
        acc.bufferView =
            add_view(a, (size_t)count * ncomp * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
        acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        acc.count = count;
        acc.type = ncomp == 2   ? TINYGLTF_TYPE_VEC2
                   : ncomp == 3 ? TINYGLTF_TYPE_VEC3
                                : TINYGLTF_TYPE_VEC4;
        if (minmax) {
            acc.minValues.assign(ncomp, INFINITY);
            acc.maxValues.assign(ncomp, -INFINITY);
            for (uint32_t i = 0; i < count; i++)
                for (int c = 0; c < ncomp; c++) {
                    double v = a[(size_t)i * ncomp + c];
                    acc.minValues[c] = std::min(acc.minValues[c], v);
                    acc.maxValues[c] = std::max(acc.maxValues[c], v);
                }
        }
        m.accessors.push_back(acc);
        return accessor_of[a] = (int)m.accessors.size() - 1;
    }

    int add_index_accessor(const uint32_t *idx, uint32_t count) {
        auto it = accessor_of.find(idx);
        if (it != accessor_of.end()) return it->second;
        tinygltf::Accessor acc;
        acc.bufferView =
            add_view(idx, (size_t)count * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        acc.count = count;
        acc.type = TINYGLTF_TYPE_SCALAR;
        m.accessors.push_back(acc);
        return accessor_of[idx] = (int)m.accessors.size() - 1;
    }
};

tinygltf::Value extras_value(const pg_gltf_extra *e, int n) {
    tinygltf::Value::Object o;
    for (int i = 0; i < n; i++) {
        if (e[i].string)
            o[e[i].key] = tinygltf::Value(std::string(e[i].string));
        else if (e[i].is_int)
            o[e[i].key] = tinygltf::Value((int)e[i].number);
        else
            o[e[i].key] = tinygltf::Value(e[i].number);
    }
    return tinygltf::Value(o);
}

void add_images(builder &b, const pg_gltf_desc *d) {
    for (int i = 0; i < d->nimages; i++) {
        const pg_gltf_image &src = d->images[i];
        tinygltf::Image img;
        img.name = src.name ? src.name : "";
        if (src.uri) {
            img.uri = src.uri;
        } else {
            img.mimeType = src.mime;
            img.bufferView = b.add_view(src.bytes, src.size, 0);
        }
        b.m.images.push_back(img);
    }
}

// One texture per image that a material samples, all with the one sampler.
int texture_for(builder &b, std::map<int, int> &tex_of, int image) {
    auto it = tex_of.find(image);
    if (it != tex_of.end()) return it->second;
    tinygltf::Texture t;
    t.sampler = 0;
    t.source = image;
    b.m.textures.push_back(t);
    return tex_of[image] = (int)b.m.textures.size() - 1;
}

void add_primitive(builder &b, std::map<int, int> &tex_of, const pg_gltf_primitive &p,
                   tinygltf::Mesh &mesh) {
    tinygltf::Material mat;
    mat.name = p.material_name ? p.material_name : "";
    mat.pbrMetallicRoughness.baseColorTexture.index = texture_for(b, tex_of, p.base_color_image);
    mat.pbrMetallicRoughness.metallicFactor = 0.0;
    mat.pbrMetallicRoughness.roughnessFactor = 1.0;
    mat.normalTexture.index = texture_for(b, tex_of, p.normal_image);
    if (p.nextras) mat.extras = extras_value(p.extras, p.nextras);
    b.m.materials.push_back(mat);

    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = (int)b.m.materials.size() - 1;
    prim.attributes["POSITION"] = b.add_float_accessor(p.positions, p.nverts, 3, true);
    prim.attributes["NORMAL"] = b.add_float_accessor(p.normals, p.nverts, 3, false);
    prim.attributes["TANGENT"] = b.add_float_accessor(p.tangents, p.nverts, 4, false);
    prim.attributes["TEXCOORD_0"] = b.add_float_accessor(p.texcoords, p.nverts, 2, false);
    prim.indices = b.add_index_accessor(p.indices, p.nindices);
    mesh.primitives.push_back(prim);
}

void build(builder &b, const pg_gltf_desc *d) {
    b.m.asset.version = "2.0";
    b.m.asset.generator = d->generator ? d->generator : "planetgen";
    b.m.buffers.resize(1);
    tinygltf::Sampler s;
    s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    s.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    b.m.samplers.push_back(s);
    // Arrays first, images last: the big image bytes do not push vertex data around.
    tinygltf::Mesh mesh;
    mesh.name = d->mesh_name ? d->mesh_name : "planet";
    std::map<int, int> tex_of;
    for (int i = 0; i < d->nprims; i++)
        add_primitive(b, tex_of, d->prims[i], mesh);
    add_images(b, d);
    b.m.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = mesh.name;
    node.mesh = 0;
    if (d->node_rotation) node.rotation.assign(d->node_rotation, d->node_rotation + 4);
    b.m.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.name = mesh.name;
    scene.nodes.push_back(0);
    if (d->nscene_extras) scene.extras = extras_value(d->scene_extras, d->nscene_extras);
    b.m.scenes.push_back(scene);
    b.m.defaultScene = 0;
    while (b.m.buffers[0].data.size() % 4)
        b.m.buffers[0].data.push_back(0);
}

} // namespace

extern "C" pg_status pg_gltf_write_glb(const char *path, const pg_gltf_desc *d, pg_error *err) {
    try {
        builder b;
        build(b, d);
        tinygltf::TinyGLTF writer;
        writer.SetImageWriter(nullptr, nullptr); // images are already encoded
        if (!writer.WriteGltfSceneToFile(&b.m, path, false, true, false, true))
            return pg_error_set(err, PG_ERR_IO, "%s: cannot write the glTF binary", path);
    } catch (const std::bad_alloc &) {
        return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory building the glTF model", path);
    } catch (const std::exception &e) {
        return pg_error_set(err, PG_ERR_RUNTIME, "%s: glTF writer failed: %s", path, e.what());
    }
    return PG_OK;
}
