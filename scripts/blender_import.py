# blender_import.py - open a planetgen planet in Blender with true displacement
# (docs/export.md, "Blender"):
#
#   blender --python scripts/blender_import.py -- PLANET [options]
#   blender -b --python scripts/blender_import.py -- PLANET --render out.png
#
# PLANET is a planet.glb, or a planet directory: its planet.glb, else viewer/planet.glb,
# else, for a tiled planet (index.json, generate --output-layout tiled), the .glb of every
# tile that index.json lists (planet_F_TX_TY.glb), imported and joined into one globe,
# else (a tiled planet written with --no-glb) the globe that `planetgen view DIR`
# assembles from the tiles into DIR/viewer/planet.glb (planetgen from --planetgen or the
# PATH).
#
# What it does:
#  1. imports the .glb with Blender's own glTF importer;
#  2. puts every vertex back on the ellipsoid and wires each face's 16-bit height image
#     (the material extras: heightTexture, heightScale, heightOffset) into a
#     Displacement node, metres = heightOffset + heightScale * v, times the
#     exaggeration; Cycles dices the surface adaptively (about a pixel per
#     micropolygon) and displaces it, with bump mapping for what is finer;
#  3. adds the sea as its own surface at sea level (a copy of the base mesh);
#  4. sets up Cycles on the CPU without a denoiser (Debian's Blender has none), a camera
#     (the whole globe, or a close-up with --camera) and a sun.
# One Blender unit is one kilometre; the planet's centre is the origin, +Z north, +X
# towards longitude 0 (the .glb's ECEF frame).
import argparse
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile

import numpy

if not hasattr(numpy, "bool"):  # Debian's Blender 3.4 glTF importer uses numpy.bool
    numpy.bool = bool

import bmesh  # noqa: E402
import bpy  # noqa: E402
import mathutils  # noqa: E402

KM = 1e-3  # Blender units per metre


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="blender --python blender_import.py --",
        description="Import a planetgen planet into Blender with true displacement.")
    p.add_argument("planet", help="planet.glb, or a planet directory (also a tiled one)")
    p.add_argument("--exaggeration", type=float,
                   help="relief exaggeration of the displacement (default: the .glb's)")
    p.add_argument("--no-displacement", action="store_true",
                   help="the same scene on the bare ellipsoid, without displacement (to "
                        "compare with)")
    p.add_argument("--camera", default=None, metavar="LON,LAT,DIST_KM[,TILT[,HEADING]]",
                   help="look at LON,LAT from DIST_KM away, TILT degrees from the vertical, "
                        "from HEADING degrees (0: from the south); default: the whole globe")
    p.add_argument("--resolution", default="1280x720", metavar="WxH")
    p.add_argument("--samples", type=int, default=64)
    p.add_argument("--render", metavar="OUT.png", help="render a frame into OUT.png")
    p.add_argument("--save", metavar="OUT.blend", help="save the scene")
    p.add_argument("--planetgen", default="planetgen",
                   help="the planetgen command, for tiled planets (default: from the PATH)")
    return p.parse_args(argv)


def find_glbs(planet, planetgen):
    """The .glb files for a file or a planet directory (see the top of this file)."""
    if not os.path.isdir(planet):
        return [planet]
    for name in ("planet.glb", os.path.join("viewer", "planet.glb")):
        if os.path.isfile(os.path.join(planet, name)):
            return [os.path.join(planet, name)]
    index = os.path.join(planet, "index.json")
    if not os.path.isfile(index):
        sys.exit(f"{planet}: no planet.glb and not a tiled planet (no index.json)")
    with open(index) as f:
        tiles = json.load(f).get("tile_files", [])
    glbs = [os.path.join(planet, t["glb"]) for t in tiles if "glb" in t]
    if tiles and len(glbs) == len(tiles) and all(os.path.isfile(g) for g in glbs):
        return glbs
    if shutil.which(planetgen) is None:
        sys.exit(f"{planet}: a tiled planet without its .glb files; run `planetgen view "
                 f"{planet}` first, or give --planetgen PATH")
    subprocess.run([planetgen, "view", planet, "-q"], check=True)
    return [os.path.join(planet, "viewer", "planet.glb")]


def find_glb(planet, planetgen):
    """The one .glb of a planet (the first tile's for a tile set)."""
    return find_glbs(planet, planetgen)[0]


def read_glb(path):
    """The glTF JSON and binary chunk of a .glb (glTF 2.0 spec, "Binary glTF Layout")."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, _ = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        sys.exit(f"{path}: not a binary glTF 2.0 file")
    gltf, binary, off = None, b"", 12
    while off + 8 <= len(data):
        length, kind = struct.unpack_from("<II", data, off)
        chunk = data[off + 8:off + 8 + length]
        if kind == 0x4E4F534A:
            gltf = json.loads(chunk)
        elif kind == 0x004E4942:
            binary = chunk
        off += 8 + length
    return gltf, binary


def load_height_image(gltf, binary, glb_dir, index, name, tmp):
    """glTF image `index` (the 16-bit height PNG) as a packed Blender image."""
    img = gltf["images"][index]
    if "uri" in img:  # --external-textures
        path = os.path.join(glb_dir, img["uri"])
    else:
        view = gltf["bufferViews"][img["bufferView"]]
        start = view.get("byteOffset", 0)
        path = os.path.join(tmp, name + ".png")
        with open(path, "wb") as f:
            f.write(binary[start:start + view["byteLength"]])
    image = bpy.data.images.load(path)
    image.name = name
    image.colorspace_settings.name = "Non-Color"  # heights, not colours
    image.pack()
    return image


def import_one(glb):
    """Import one .glb; its planet object with the transform baked into kilometres."""
    before = set(bpy.context.scene.objects)
    bpy.ops.import_scene.gltf(filepath=glb)
    meshes = [o for o in bpy.context.scene.objects
              if o not in before and o.type == "MESH"
              and any(m and "heightTexture" in m for m in o.data.materials)]
    if len(meshes) != 1:
        sys.exit(f"{glb}: not a planetgen globe (no material with a heightTexture)")
    obj = meshes[0]
    obj.data.transform(mathutils.Matrix.Scale(KM, 4) @ obj.matrix_world)
    obj.matrix_world = mathutils.Matrix.Identity(4)
    return obj


def import_globe(glb, each=None):
    """Import the .glb, or the tile set's .glb files (a list) joined into one object;
    each(obj, glb), if given, runs on every file's object before the join (its
    materials' heightTexture indices are that file's)."""
    objs = []
    for g in glb if isinstance(glb, list) else [glb]:
        objs.append(import_one(g))
        if each:
            each(objs[-1], g)
    obj = objs[0]
    if len(objs) > 1:
        bpy.ops.object.select_all(action="DESELECT")
        for o in objs:
            o.select_set(True)
        bpy.context.view_layer.objects.active = obj
        bpy.ops.object.join()
    mesh = obj.data
    # One connected surface with smooth vertex normals: the seam vertices of the faces
    # (and of the tiles) are bit-identical in the .glb files (docs/export.md,
    # "Watertight") and are merged here, and the importer's per-corner normals are
    # dropped. Displacement moves a vertex along its normal, so a vertex with two
    # normals, or two copies, would open a crack.
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-3)  # 1 m: two float ulps at 6400 km
    # the .glb's quads, split in two triangles, back to quads: Cycles dices quads as
    # whole patches
    bmesh.ops.join_triangles(bm, faces=bm.faces, angle_face_threshold=math.pi,
                             angle_shape_threshold=math.pi, cmp_materials=True, cmp_uvs=True)
    bm.to_mesh(mesh)
    bm.free()
    if mesh.has_custom_normals:
        mesh.free_normals_split()
        bpy.context.view_layer.objects.active = obj
        bpy.ops.mesh.customdata_custom_splitnormals_clear()
    mesh.use_auto_smooth = False
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.update()
    return obj


def ellipsoid_radius(co, a, b):
    """Distance from the centre to the ellipsoid along each row of co (n x 3)."""
    u = co / numpy.linalg.norm(co, axis=1, keepdims=True)
    return 1.0 / numpy.sqrt((u[:, 0] ** 2 + u[:, 1] ** 2) / a ** 2 + u[:, 2] ** 2 / b ** 2), u


def set_radius(mesh, a, b, lift):
    """Move every vertex radially to the ellipsoid plus `lift` (same units)."""
    co = numpy.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    r0, u = ellipsoid_radius(co, a, b)
    mesh.vertices.foreach_set("co", (u * (r0 + lift)[:, None]).ravel())
    mesh.update()


def wire_displacement(mat, image, offset, scale, exaggeration):
    """Height image -> Displacement -> Material Output, in object space (kilometres):
    displacement = (v - midlevel) * s with midlevel = -offset / scale and
    s = scale * exaggeration, i.e. (offset + scale * v) * exaggeration metres."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    out = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    tex = nodes.new("ShaderNodeTexImage")
    tex.name = tex.label = "planetgen height"
    tex.image = image
    tex.interpolation = "Cubic"
    tex.extension = "EXTEND"  # faces never sample their neighbours
    uv = next((n for n in nodes if n.type == "UVMAP"), None)
    if uv is not None:
        links.new(uv.outputs["UV"], tex.inputs["Vector"])
    disp = nodes.new("ShaderNodeDisplacement")
    disp.name = disp.label = "planetgen displacement"
    disp.space = "OBJECT"
    disp.inputs["Midlevel"].default_value = -offset / scale
    disp.inputs["Scale"].default_value = scale * exaggeration * KM
    links.new(tex.outputs["Color"], disp.inputs["Height"])
    links.new(disp.outputs["Displacement"], out.inputs["Displacement"])
    mat.cycles.displacement_method = "BOTH"


def add_sea(land, a, b, level):
    """The sea: a copy of the base mesh at sea level, with one water material."""
    sea = land.copy()
    sea.data = land.data.copy()
    sea.name = sea.data.name = "sea"
    set_radius(sea.data, a, b, level)
    sea.modifiers.clear()
    sea.cycles.use_adaptive_subdivision = False
    mat = bpy.data.materials.new("sea")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.01, 0.04, 0.12, 1)
    bsdf.inputs["Roughness"].default_value = 0.25
    sea.data.materials.clear()
    sea.data.materials.append(mat)
    for p in sea.data.polygons:
        p.material_index = 0
    bpy.context.scene.collection.objects.link(sea)
    return sea


def look_from(scene, target, eye, up_hint):
    cam = scene.camera
    cam.location = eye
    z = (eye - target).normalized()  # the camera looks down its -Z
    x = up_hint.cross(z)
    if x.length < 1e-9:
        x = mathutils.Vector((1, 0, 0)).cross(z)
    x.normalize()
    y = z.cross(x)
    cam.matrix_world = mathutils.Matrix((
        (x[0], y[0], z[0], eye[0]), (x[1], y[1], z[1], eye[1]),
        (x[2], y[2], z[2], eye[2]), (0, 0, 0, 1)))


def setup_camera_and_sun(scene, a, b, camera):
    cam_data = bpy.data.cameras.new("camera")
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    north = mathutils.Vector((0, 0, 1))
    if camera is None:  # the whole globe, from above 0 N 0 E
        target, eye = mathutils.Vector((0, 0, 0)), mathutils.Vector((4.2 * a, 0, 0))
        cam_data.lens = 50
        view_up = north
    else:
        v = [float(x) for x in camera.split(",")]
        lon, lat, dist = math.radians(v[0]), math.radians(v[1]), v[2]
        tilt = math.radians(v[3] if len(v) > 3 else 60)
        heading = math.radians(v[4] if len(v) > 4 else 0)
        up = mathutils.Vector((math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon),
                               math.sin(lat)))  # geocentric up, close enough to aim a camera
        r0 = 1 / math.sqrt((up.x ** 2 + up.y ** 2) / a ** 2 + up.z ** 2 / b ** 2)
        target = up * r0
        east = north.cross(up).normalized()
        toward_north = up.cross(east)
        # from the south (heading 0), tilted away from the vertical
        back = -(toward_north * math.cos(heading) + east * math.sin(heading))
        eye = target + (up * math.cos(tilt) + back * math.sin(tilt)) * dist
        view_up = up
        cam_data.lens = 35
    look_from(scene, target, eye, view_up)
    dist = (eye - target).length
    cam_data.clip_start = max(dist * 1e-4, 1e-3)
    cam_data.clip_end = dist + 2 * a
    sun_data = bpy.data.lights.new("sun", "SUN")
    sun_data.energy = 4.0
    sun_data.angle = math.radians(1.0)
    sun = bpy.data.objects.new("sun", sun_data)
    scene.collection.objects.link(sun)
    # light from the camera's upper left, low enough to shade the relief
    m = cam.matrix_world.to_3x3()
    light_dir = (m @ mathutils.Vector((-0.8, 0.5, 0.6))).normalized()  # towards the light
    sun.rotation_euler = light_dir.to_track_quat("Z", "Y").to_euler()


def setup_render(scene, resolution, samples, texels_per_quad):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.feature_set = "EXPERIMENTAL"  # adaptive subdivision
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
    scene.cycles.dicing_rate = 1.0  # micropolygons of about a pixel
    scene.cycles.offscreen_dicing_scale = 8.0
    # No finer than a quarter texel: the height images hold no more detail, and an
    # uncapped dicing of a whole globe takes gigabytes.
    scene.cycles.max_subdivisions = max(1, math.ceil(math.log2(max(texels_per_quad, 1))) + 2)
    w, h = (int(x) for x in resolution.split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("space")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.01, 0.01, 0.012, 1)
    scene.world = world


def build(args):
    """The whole scene; returns (land, figures) for scripts that drive this one."""
    glbs = find_glbs(args.planet, args.planetgen)
    glb = glbs[0] if len(glbs) == 1 else glbs
    gltf, binary = read_glb(glbs[0])
    extras = gltf.get("scenes", [{}])[gltf.get("scene", 0)].get("extras", {})
    a = float(extras["radius_m"]) * KM
    b = a * (1 - float(extras.get("flattening", 0)))
    e0 = float(extras.get("exaggeration", 0))
    exaggeration = e0 if args.exaggeration is None else args.exaggeration
    sea_level = float(extras.get("sea_level_m", 0))
    scene = bpy.context.scene
    wired = 0
    tmp = tempfile.mkdtemp(prefix="planetgen-heights-")

    def displace(obj, path):
        """Each material's height image (an index into this file's images) wired in."""
        nonlocal wired
        gl, bn = read_glb(path)
        for mat in obj.data.materials:
            name = mat.name if "tile_x" in mat else str(mat.get("face", mat.name))
            image = load_height_image(gl, bn, os.path.dirname(path), int(mat["heightTexture"]),
                                      "height " + name, tmp)
            wire_displacement(mat, image, float(mat["heightOffset"]), float(mat["heightScale"]),
                              exaggeration)
            wired += 1

    try:
        land = import_globe(glb, None if args.no_displacement else displace)
    finally:
        shutil.rmtree(tmp)
    land.name = "planet"
    set_radius(land.data, a, b, 0.0)  # the relief comes from the height images now
    if not args.no_displacement:
        mod = land.modifiers.new("planetgen dicing", "SUBSURF")
        mod.subdivision_type = "SIMPLE"  # the base mesh is already on the ellipsoid
        # Cycles dices each base quad itself; any level here would multiply the patches
        # first (level 2 took 7 GB for a 6 x 128^2 mesh, level 0 under 0.3 GB)
        mod.levels = mod.render_levels = 0
        land.cycles.use_adaptive_subdivision = True
    # Without displacement the land stays on the ellipsoid: the sea goes just below it.
    add_sea(land, a, b, sea_level * exaggeration * KM - (0.01 if args.no_displacement else 0))
    texels = int(extras.get("tiles", 1)) * int(extras.get("tile_size", 1))
    setup_render(scene, args.resolution, args.samples, texels / int(extras.get("mesh_res", texels)))
    setup_camera_and_sun(scene, a, b, args.camera)
    what = glbs[0] if len(glbs) == 1 else f"{len(glbs)} tile files"
    print(f"planetgen: {what}: radius {a:.0f} km, {wired} faces displaced at "
          f"{exaggeration:g}x, sea at {sea_level:g} m")
    return land, {"radius_km": a, "polar_km": b, "exaggeration": exaggeration,
                       "sea_level_m": sea_level, "faces_displaced": wired}


def frame_viewports(a):
    """In the interface, 3D views that see the whole globe (kilometres, not metres)."""
    screen = getattr(bpy.context, "screen", None)
    for area in (screen.areas if screen else []):
        if area.type != "VIEW_3D":
            continue
        space = area.spaces.active
        space.clip_start, space.clip_end = 0.1, 20 * a
        space.region_3d.view_location = (0, 0, 0)
        space.region_3d.view_distance = 3 * a


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    for o in list(bpy.data.objects):  # the default cube, camera and light
        bpy.data.objects.remove(o)
    land, fig = build(args)
    frame_viewports(fig["radius_km"])
    if args.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
    if args.render:
        scene = bpy.context.scene
        scene.render.image_settings.file_format = "PNG"
        scene.render.filepath = os.path.abspath(args.render)
        bpy.ops.render.render(write_still=True)
        print(f"planetgen: rendered {args.render}")


if __name__ == "__main__":
    main()
