# blender_check_displacement.py - run inside Blender (blender -b --python THIS -- SCRIPT
# GLB OUTDIR CAMERA): drive scripts/blender_import.py (SCRIPT) on a planet .glb and
# report what a user would get, for tests/test_export_blender.c.
#
# Prints lines the C test parses:
#   FACES n            materials of the globe (one per cube face)
#   DISPLACED n        materials whose Material Output Displacement is fed by a
#                      Displacement node whose Height is fed by an image texture holding
#                      a float (16-bit) N x N height image, N the face's texels
#   CALIBRATED n       of those, Midlevel = -heightOffset / heightScale and
#                      Scale = heightScale * exaggeration (kilometres), from the extras
#   ADAPTIVE 0|1       Cycles, experimental feature set, adaptive subdivision on the globe
#   SEA_ERROR_M x      largest distance of the sea surface's vertices from the ellipsoid
#                      at sea level, metres
#   HEIGHT_OFFSET x, HEIGHT_SCALE x   metres = offset + scale * v of the height pass
# and writes into OUTDIR: displaced.png (the close-up as the script sets it up),
# flat.png (the same with --no-displacement) and heights.exr (v of the height images as
# seen by the camera, on the flat globe: where the mountains are in the frame).
import importlib.util
import math
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's Blender 3.4 glTF importer uses numpy.bool
    numpy.bool = bool

import bpy  # noqa: E402

script, glb, outdir, camera = sys.argv[sys.argv.index("--") + 1:][:4]
spec = importlib.util.spec_from_file_location("blender_import", script)
bi = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bi)
common = [glb, "--camera", camera, "--resolution", "200x112", "--samples", "8"]


def fresh(extra):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bi.build(bi.parse_args(common + extra))


def render(path, fmt="PNG"):
    scene = bpy.context.scene
    scene.render.image_settings.file_format = fmt
    if fmt == "OPEN_EXR":
        scene.render.image_settings.color_depth = "32"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def feeding(sock, kind):
    if not sock.links:
        return None
    node = sock.links[0].from_node
    return node if node.type == kind else None


# --- the displaced scene, as blender_import.py builds it ---
land, fig = fresh([])
gltf, _ = bi.read_glb(glb)
extras = gltf["scenes"][gltf.get("scene", 0)]["extras"]
n = int(extras["tiles"]) * int(extras["tile_size"])
displaced = calibrated = 0
for mat in land.data.materials:
    out = next(x for x in mat.node_tree.nodes if x.type == "OUTPUT_MATERIAL")
    disp = feeding(out.inputs["Displacement"], "DISPLACEMENT")
    tex = feeding(disp.inputs["Height"], "TEX_IMAGE") if disp else None
    img = tex.image if tex else None
    if img is None or not img.is_float or tuple(img.size) != (n, n):
        continue
    displaced += 1
    offset, scale = float(mat["heightOffset"]), float(mat["heightScale"])
    calibrated += (abs(disp.inputs["Midlevel"].default_value + offset / scale) < 1e-6 and
                   math.isclose(disp.inputs["Scale"].default_value,
                                scale * fig["exaggeration"] * 1e-3, rel_tol=1e-6))
scene = bpy.context.scene
adaptive = (scene.render.engine == "CYCLES" and scene.cycles.feature_set == "EXPERIMENTAL"
            and land.cycles.use_adaptive_subdivision)
sea = bpy.data.objects["sea"]
co = numpy.empty(len(sea.data.vertices) * 3)
sea.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
r0, _ = bi.ellipsoid_radius(co, fig["radius_km"], fig["polar_km"])
level = fig["sea_level_m"] * fig["exaggeration"] * 1e-3
sea_error = float(numpy.max(numpy.abs(numpy.linalg.norm(co, axis=1) - (r0 + level)))) * 1e3
print("FACES", len(land.data.materials))
print("DISPLACED", displaced)
print("CALIBRATED", calibrated)
print("ADAPTIVE", int(adaptive))
print("SEA_ERROR_M", sea_error)
render(outdir + "/displaced.png")

# --- the same scene without displacement ---
land, fig = fresh(["--no-displacement"])
render(outdir + "/flat.png")

# --- the height pass: each face's height image as emission, on the flat globe ---
bpy.data.objects["sea"].hide_render = True
gltf, binary = bi.read_glb(glb)
tmp = bi.tempfile.mkdtemp()
for mat in land.data.materials:
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    for x in list(nodes):
        if x.type != "UVMAP":
            nodes.remove(x)
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = bi.load_height_image(gltf, binary, bi.os.path.dirname(glb), int(mat["heightTexture"]),
                                     "pass " + mat.name, tmp)
    tex.interpolation = "Closest"
    tex.extension = "EXTEND"
    uv = next((x for x in nodes if x.type == "UVMAP"), None)
    if uv is not None:
        links.new(uv.outputs["UV"], tex.inputs["Vector"])
    emit = nodes.new("ShaderNodeEmission")
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(tex.outputs["Color"], emit.inputs["Color"])
    links.new(emit.outputs["Emission"], out.inputs["Surface"])
    print("HEIGHT_OFFSET", float(mat["heightOffset"]))
    print("HEIGHT_SCALE", float(mat["heightScale"]))
bi.shutil.rmtree(tmp)
scene = bpy.context.scene
scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
scene.view_settings.view_transform = "Standard"
scene.cycles.samples = 4
scene.cycles.pixel_filter_type = "BOX"
render(outdir + "/heights.exr", "OPEN_EXR")
print("RENDERED", outdir)
