# Renders a wisp hairstyle with Blender's Cycles and its Principled Hair BSDF, on the same
# strands, camera and lights as `wisp render`, for the side-by-side in docs/render.md.
# Run by scripts/compare_blender (not by CI):
#   blender -b --factory-startup -P scripts/blender_hair.py -- \
#       HAIR.hair HEAD.obj EYE(x,y,z) TARGET(x,y,z) FOV SIZE OUT.png
# wisp's head space (cm, Y up, +Z forward) maps to Blender's (Z up, −Y forward) by
# (x, y, z) → (x, −z, y), one Blender unit per centimetre. wisp's lights are given relative
# to the camera (RenderOptions: key (−0.8, 0.6, 0.3) × 1.5, fill (0.8, 0.1, 0.6) × 0.2,
# rim (0.45, 0.5, −0.75) × 1.6, ambient 0.05); wisp's shading has no 1/π, so a sun of strength π·L gives the same
# irradiance on a Lambertian surface.
import importlib.util
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix, Vector

argv = sys.argv[sys.argv.index("--") + 1:]
hair_path, head_path = argv[0], argv[1]
eye = [float(v) for v in argv[2].split(",")]
target = [float(v) for v in argv[3].split(",")]
fov, size, out = float(argv[4]), int(argv[5]), argv[6]


def to_blender(p):
    """wisp head space (#N×3, Y up) to Blender's (Z up)."""
    p = np.asarray(p, dtype=np.float64).reshape(-1, 3)
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


# The strands and the head come in through wisp's Blender add-on (blender/wisp_hair_import.py:
# a hair Curves object with wisp's widths as radius and its colours, Principled Hair BSDF in
# direct colouring), at one Blender unit per centimetre.
spec = importlib.util.spec_from_file_location(
    "wisp_hair_import",
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender",
                 "wisp_hair_import.py"))
addon = importlib.util.module_from_spec(spec)
spec.loader.exec_module(addon)

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
addon.import_wisp_hair(hair_path, scale=1.0, material=True, name="hair")
head_objects = addon.import_head_obj(head_path, scale=1.0)

# wisp's skin albedo on the head.
skin = bpy.data.materials.new("skin")
skin.use_nodes = True
skin.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.62, 0.42, 0.32, 1)
skin.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.8
skin.node_tree.nodes["Principled BSDF"].inputs["Specular"].default_value = 0.2
for head in head_objects:
    if head.type == "MESH":
        head.data.materials.clear()
        head.data.materials.append(skin)
        for poly in head.data.polygons:
            poly.use_smooth = True

# The camera.
cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(fov)
cam_data.clip_start = 1.0
cam_data.clip_end = 10000.0
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
e = Vector(to_blender(eye)[0])
t = Vector(to_blender(target)[0])
forward = (t - e).normalized()
cam.matrix_world = Matrix.Translation(e) @ forward.to_track_quat("-Z", "Y").to_matrix().to_4x4()
scene.camera = cam
right = forward.cross(Vector((0, 0, 1))).normalized()
up = right.cross(forward)


def camera_light(direction, strength, name):
    """A sun whose light comes from `direction` given in wisp's camera frame (x right, y up,
    z toward the viewer)."""
    d = (direction[0] * right + direction[1] * up - direction[2] * forward).normalized()
    light = bpy.data.lights.new(name, "SUN")
    light.energy = strength * math.pi
    light.angle = math.radians(1.0)
    obj = bpy.data.objects.new(name, light)
    obj.matrix_world = d.to_track_quat("Z", "Y").to_matrix().to_4x4()
    scene.collection.objects.link(obj)


camera_light((-0.8, 0.6, 0.3), 1.5, "key")
camera_light((0.8, 0.1, 0.6), 0.2, "fill")
camera_light((0.45, 0.5, -0.75), 1.6, "rim")

# Ambient 0.05 lights the scene; the camera sees wisp's grey background.
world = bpy.data.worlds.new("world")
world.use_nodes = True
wn = world.node_tree
wn.nodes.clear()
amb = wn.nodes.new("ShaderNodeBackground")
amb.inputs["Color"].default_value = (0.05, 0.05, 0.055, 1)
bg = wn.nodes.new("ShaderNodeBackground")
bg.inputs["Color"].default_value = (0.3, 0.3, 0.31, 1)
path = wn.nodes.new("ShaderNodeLightPath")
mix = wn.nodes.new("ShaderNodeMixShader")
wout = wn.nodes.new("ShaderNodeOutputWorld")
wn.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
wn.links.new(amb.outputs[0], mix.inputs[1])
wn.links.new(bg.outputs[0], mix.inputs[2])
wn.links.new(mix.outputs[0], wout.inputs["Surface"])
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = int(argv[7]) if len(argv) > 7 else 64
scene.cycles.use_denoising = False
scene.cycles.max_bounces = 8
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "PNG"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
