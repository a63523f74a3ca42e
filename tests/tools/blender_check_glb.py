# blender_check_glb.py - run inside Blender (blender -b --python THIS -- GLB OUT.png):
# import a planetgen .glb with Blender's own glTF importer, report what it found
# and render one frame with Cycles on the CPU. Optional arguments after OUT.png:
# resolution (default 160) and samples (default 8).
#
# Prints lines the C test (tests/test_export_blender.c) parses:
#   PRIMITIVES n        material slots that own polygons (one per glTF primitive)
#   BASECOLOR n         materials whose Base Color comes from an image texture
#   NORMALMAP n         materials whose Normal comes from a Normal Map node fed by an image
#   TRIANGLES n
#   RENDERED path
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's Blender 3.4 importer uses numpy.bool
    numpy.bool = bool

import bpy
import mathutils

args = sys.argv[sys.argv.index("--") + 1:]
glb, out_png = args[:2]
size = int(args[2]) if len(args) > 2 else 160  # optional: resolution, samples
samples = int(args[3]) if len(args) > 3 else 8
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
scene = bpy.context.scene
objs = [o for o in scene.objects if o.type == "MESH"]
used = set()
tris = 0
for o in objs:
    for p in o.data.polygons:
        used.add((o.name, p.material_index))
        tris += len(p.vertices) - 2


def linked_image(sock):
    return bool(sock.links) and sock.links[0].from_node.type == "TEX_IMAGE" \
        and sock.links[0].from_node.image is not None \
        and sock.links[0].from_node.image.size[0] > 0


base = normal = 0
mats = {m for o in objs for m in o.data.materials if m}
for m in mats:
    bsdf = next((n for n in m.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if bsdf is None:
        continue
    base += linked_image(bsdf.inputs["Base Color"])
    ns = bsdf.inputs["Normal"]
    if ns.links and ns.links[0].from_node.type == "NORMAL_MAP":
        normal += linked_image(ns.links[0].from_node.inputs["Color"])
print("PRIMITIVES", len(used))
print("BASECOLOR", base)
print("NORMALMAP", normal)
print("TRIANGLES", tris)

# One small Cycles frame: orthographic camera over the equator at longitude 0,
# a sun behind the camera, black world.
radius = max(max(abs(c) for c in o.dimensions) for o in objs) / 2
cam_data = bpy.data.cameras.new("cam")
cam_data.type = "ORTHO"
cam_data.ortho_scale = 2.3 * radius
cam_data.clip_start = radius * 0.01
cam_data.clip_end = radius * 10
cam = bpy.data.objects.new("cam", cam_data)
scene.collection.objects.link(cam)
cam.location = mathutils.Vector((3 * radius, 0, 0))
cam.rotation_euler = (-cam.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = cam
sun_data = bpy.data.lights.new("sun", "SUN")
sun_data.energy = 4.0
sun = bpy.data.objects.new("sun", sun_data)
scene.collection.objects.link(sun)
sun.rotation_euler = mathutils.Vector((1, -0.4, 0.5)).to_track_quat("Z", "Y").to_euler()
world = bpy.data.worlds.new("black")
world.color = (0, 0, 0)
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "PNG"
scene.render.filepath = out_png
bpy.ops.render.render(write_still=True)
print("RENDERED", out_png)
