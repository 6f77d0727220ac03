# Renders a wisp hairstyle with Blender's Cycles and its Principled Hair BSDF, on the same
# strands, camera and lights as `wisp render`, for the side-by-side in docs/render.md.
# Run by scripts/compare_blender (not by CI):
#   blender -b --factory-startup -P scripts/blender_hair.py -- \
#       HAIR.hair HEAD.obj EYE(x,y,z) TARGET(x,y,z) FOV SIZE OUT.png
# wisp's head space (cm, Y up, +Z forward) maps to Blender's (Z up, −Y forward) by
# (x, y, z) → (x, −z, y), one Blender unit per centimetre. wisp's lights are given relative
# to the camera (RenderOptions: key (−0.8, 0.6, 0.3) × 1.5, fill (0.8, 0.1, 0.6) × 0.2,
# ambient 0.05); wisp's shading has no 1/π, so a sun of strength π·L gives the same
# irradiance on a Lambertian surface.
import math
import struct
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


def read_cyhair(path):
    """points #P×3, sizes #S (points per strand), thickness #P (diameter, cm), colors #S×3."""
    data = open(path, "rb").read()
    if data[:4] != b"HAIR":
        sys.exit(f"{path}: not a cyHair file")
    strands, points, flags, d_segments = struct.unpack_from("<4I", data, 4)
    d_thickness, d_transparency = struct.unpack_from("<2f", data, 20)
    d_color = struct.unpack_from("<3f", data, 28)
    at = 128
    if flags & 1:
        sizes = np.frombuffer(data, np.uint16, strands, at).astype(np.int64) + 1
        at += 2 * strands
    else:
        sizes = np.full(strands, d_segments + 1, np.int64)
    p = np.frombuffer(data, np.float32, 3 * points, at).reshape(-1, 3)
    at += 12 * points
    thickness = np.full(points, d_thickness, np.float32)
    if flags & 4:
        thickness = np.frombuffer(data, np.float32, points, at).copy()
        at += 4 * points
    if flags & 8:
        at += 4 * points
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    colors = np.tile(np.array(d_color, np.float32), (strands, 1))
    if flags & 16:
        c = np.frombuffer(data, np.float32, 3 * points, at).reshape(-1, 3)
        colors = c[first]
    return p, sizes, thickness, colors


def read_obj(path):
    verts, faces = [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            verts.append([float(x) for x in t[1:4]])
        elif t[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in t[1:]])
    return np.array(verts), faces


bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# The hair: a mesh of polylines (one edge per segment) turned into curves by geometry nodes,
# which Cycles renders as hair with the Principled Hair BSDF.
p, sizes, thickness, colors = read_cyhair(hair_path)
P = len(p)
ends = np.cumsum(sizes)
starts = ends - sizes
seg_mask = np.ones(P, bool)
seg_mask[ends - 1] = False
a = np.nonzero(seg_mask)[0]
edges = np.stack([a, a + 1], axis=1)
mesh = bpy.data.meshes.new("hair")
mesh.vertices.add(P)
mesh.vertices.foreach_set("co", to_blender(p).astype(np.float32).ravel())
mesh.edges.add(len(edges))
mesh.edges.foreach_set("vertices", edges.astype(np.int32).ravel())
mesh.update()
strand_of_point = np.repeat(np.arange(len(sizes)), sizes)
col = mesh.attributes.new("wisp_color", "FLOAT_COLOR", "POINT")
rgba = np.concatenate([colors[strand_of_point], np.ones((P, 1), np.float32)], axis=1)
col.data.foreach_set("color", rgba.astype(np.float32).ravel())
rad = mesh.attributes.new("wisp_radius", "FLOAT", "POINT")
rad.data.foreach_set("value", (0.5 * thickness).astype(np.float32))
# The polylines' mesh is only a source: a hair-curves object reads it through its geometry
# nodes, since Cycles renders curves as hair only on a Curves object.
mesh_obj = bpy.data.objects.new("hair_polylines", mesh)
scene.collection.objects.link(mesh_obj)
mesh_obj.hide_render = True
mesh_obj.hide_viewport = True
hair_obj = bpy.data.objects.new("hair", bpy.data.hair_curves.new("hair"))
scene.collection.objects.link(hair_obj)

tree = bpy.data.node_groups.new("to_curves", "GeometryNodeTree")
tree.inputs.new("NodeSocketGeometry", "Geometry")
tree.outputs.new("NodeSocketGeometry", "Geometry")
n_in = tree.nodes.new("NodeGroupInput")
n_out = tree.nodes.new("NodeGroupOutput")
to_curve = tree.nodes.new("GeometryNodeMeshToCurve")
set_radius = tree.nodes.new("GeometryNodeSetCurveRadius")
radius_attr = tree.nodes.new("GeometryNodeInputNamedAttribute")
radius_attr.data_type = "FLOAT"
radius_attr.inputs["Name"].default_value = "wisp_radius"
set_material = tree.nodes.new("GeometryNodeSetMaterial")
source = tree.nodes.new("GeometryNodeObjectInfo")
source.inputs["Object"].default_value = mesh_obj
tree.links.new(source.outputs["Geometry"], to_curve.inputs["Mesh"])
tree.links.new(to_curve.outputs["Curve"], set_radius.inputs["Curve"])
# Named Attribute has one output per data type, all called "Attribute": link the float one
# (the first is the vector output, disabled for a float attribute, and its link is ignored).
radius_out = next(o for o in radius_attr.outputs if o.enabled and o.type == "VALUE")
tree.links.new(radius_out, set_radius.inputs["Radius"])
tree.links.new(set_radius.outputs["Curve"], set_material.inputs["Geometry"])
tree.links.new(set_material.outputs["Geometry"], n_out.inputs[0])
modifier = hair_obj.modifiers.new("to_curves", "NODES")
modifier.node_group = tree

hair_mat = bpy.data.materials.new("hair")
hair_mat.use_nodes = True
nt = hair_mat.node_tree
nt.nodes.clear()
bsdf = nt.nodes.new("ShaderNodeBsdfHairPrincipled")
bsdf.parametrization = "COLOR"
attr = nt.nodes.new("ShaderNodeAttribute")
attr.attribute_name = "wisp_color"
mout = nt.nodes.new("ShaderNodeOutputMaterial")
nt.links.new(attr.outputs["Color"], bsdf.inputs["Color"])
nt.links.new(bsdf.outputs[0], mout.inputs["Surface"])
set_material.inputs["Material"].default_value = hair_mat
hair_obj.data.materials.append(hair_mat)

# The head, with wisp's skin albedo.
v, faces = read_obj(head_path)
head = bpy.data.meshes.new("head")
head.from_pydata(to_blender(v).tolist(), [], faces)
for poly in head.polygons:
    poly.use_smooth = True
head.update()
head_obj = bpy.data.objects.new("head", head)
scene.collection.objects.link(head_obj)
skin = bpy.data.materials.new("skin")
skin.use_nodes = True
skin.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.62, 0.42, 0.32, 1)
skin.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.8
skin.node_tree.nodes["Principled BSDF"].inputs["Specular"].default_value = 0.2
head.materials.append(skin)

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
