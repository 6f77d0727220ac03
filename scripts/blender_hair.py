# Renders a wisp hairstyle with Blender's Cycles and its Principled Hair BSDF, on the same
# strands, camera and lights as `wisp render`, for the side-by-side in docs/render.md and
# the colour comparison of scripts/compare_blender --colors.
# Run by scripts/compare_blender (not by CI):
#   blender -b --factory-startup -P scripts/blender_hair.py -- \
#       HAIR.hair HEAD.obj EYE(x,y,z) TARGET(x,y,z) FOV SIZE OUT.png [SAMPLES] \
#       [--melanin] [--coverage OUT.npy] [--stats OUT.json] [--check-attributes]
#   --melanin           colour the strands through melanin (the Principled Hair BSDF's
#                       MELANIN parametrization, per-curve attributes; see
#                       melanin_from_color) instead of the default direct colouring
#   --coverage OUT.npy  also write the hair's coverage of each pixel (float32 SIZE×SIZE,
#                       row 0 at the top): the fraction of the pixel's camera samples whose
#                       first hit is a strand, from a shader AOV the hair material writes
#   --stats OUT.json    also write the render's wall time and the melanin per strand
#   --check-attributes  (with --melanin) first render two thumbnails with every strand's
#                       melanin at 0 and at 0.99, and stop if they look alike: the per-curve
#                       attributes did not reach the shader
# wisp's head space (cm, Y up, +Z forward) maps to Blender's (Z up, −Y forward) by
# (x, y, z) → (x, −z, y), one Blender unit per centimetre. wisp's lights are given relative
# to the camera (RenderOptions: key (−0.8, 0.6, 0.3) × 1.5, fill (0.8, 0.1, 0.6) × 0.2,
# rim (0.45, 0.5, −0.75) × 1.6, ambient 0.05); wisp's shading has no 1/π, so a sun of strength π·L gives the same
# irradiance on a Lambertian surface.
import argparse
import importlib.util
import json
import math
import os
import sys
import tempfile
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector

parser = argparse.ArgumentParser(prog="blender_hair.py")
parser.add_argument("hair")
parser.add_argument("head")
parser.add_argument("eye")
parser.add_argument("target")
parser.add_argument("fov", type=float)
parser.add_argument("size", type=int)
parser.add_argument("out")
parser.add_argument("samples", type=int, nargs="?", default=64)
parser.add_argument("--melanin", action="store_true")
parser.add_argument("--coverage")
parser.add_argument("--stats")
parser.add_argument("--check-attributes", action="store_true")
args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:])
eye = [float(v) for v in args.eye.split(",")]
target = [float(v) for v in args.target.split(",")]
fov, size, out = args.fov, args.size, args.out

# Cycles' Principled Hair BSDF in melanin mode, matched to wisp's fibre model
# (src/render/fiber_scattering.hpp, FiberParams): longitudinal roughness β_m, azimuthal
# roughness β_n, index of refraction, cuticle tilt.
HAIR_ROUGHNESS = 0.3
HAIR_RADIAL_ROUGHNESS = 0.3
HAIR_IOR = 1.55
HAIR_OFFSET_DEGREES = 2.0
MELANIN_ATTRIBUTE = "wisp_melanin"
REDNESS_ATTRIBUTE = "wisp_melanin_redness"
COVERAGE_AOV = "wisp_hair"


# ---- Strand colour → melanin. ---------------------------------------------------------
# wisp's own mapping, from its Python module (Blender's Python is Debian's python3, which
# loads it): the fibre model's melanin_from_color, so that both renderers give each strand
# the same absorption σa (per unit of fibre radius). Its concentrations are in Chiang et al.'s
# (pbrt's) units; Cycles' pigments absorb σa = eu_c·(0.506, 0.841, 1.653) +
# ph_c·(0.343, 0.733, 1.924) (intern/cycles/kernel/closure/bsdf_hair_principled.h), the same
# spectra scaled by 0.506/0.419 and 0.343/0.187 (to 0.1 %), so eu_c = eu·0.419/0.506 and
# ph_c = ph·0.187/0.343; and Cycles' inputs are Melanin m and Melanin Redness r with
# qty = −ln(1 − m), eu_c = qty·(1 − r), ph_c = qty·r (svm_closure.h), so qty = eu_c + ph_c,
# r = ph_c / qty (0 where qty = 0) and m = 1 − e^−qty. Tint white adds no absorption.
# WISP_PYTHON=dir selects the module's directory (default: build/release/python).
sys.path.insert(0, os.environ.get("WISP_PYTHON") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "build", "release", "python"))
import wisp  # noqa: E402

EUMELANIN_SIGMA = np.array([0.419, 0.697, 1.37])
PHEOMELANIN_SIGMA = np.array([0.187, 0.4, 1.05])
CYCLES_EUMELANIN_SCALE = 0.419 / 0.506
CYCLES_PHEOMELANIN_SCALE = 0.187 / 0.343


def absorption_fit(b):
    """Chiang et al. 2016 eq. 9's polynomial in the azimuthal roughness β_n (for the report
    of how much of each colour two pigments give)."""
    return 5.969 - 0.215 * b + 2.532 * b**2 - 10.73 * b**3 + 5.574 * b**4 + 0.245 * b**5


def cycles_melanin(eu, ph):
    """pbrt-unit concentrations → Cycles' (Melanin, Melanin Redness), #N each."""
    eu_c, ph_c = eu * CYCLES_EUMELANIN_SCALE, ph * CYCLES_PHEOMELANIN_SCALE
    qty = eu_c + ph_c
    redness = np.divide(ph_c, qty, out=np.zeros_like(qty), where=qty > 0)
    return 1.0 - np.exp(-qty), redness


def melanin_from_color(c):
    """#N×3 linear RGB → (m, r, eu, ph): Cycles' inputs and pbrt's concentrations."""
    pigments = wisp.melanin_from_color(np.asarray(c, np.float32), HAIR_RADIAL_ROUGHNESS)
    eu, ph = pigments[:, 0].astype(np.float64), pigments[:, 1].astype(np.float64)
    m, r = cycles_melanin(eu, ph)
    return m, r, eu, ph


# ---------------------------------------------------------------------------------------


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
hair_obj = addon.import_wisp_hair(args.hair, scale=1.0, material=True, name="hair")
head_objects = addon.import_head_obj(args.head, scale=1.0)
hair_material = hair_obj.data.materials[0]


def set_curve_attribute(curves, name, values):
    attr = curves.attributes.get(name) or curves.attributes.new(name, "FLOAT", "CURVE")
    attr.data.foreach_set("value", np.asarray(values, np.float32))
    # foreach_set does not tell the depsgraph; without the tag a render after the first
    # keeps the values the first one saw.
    curves.update_tag()


stats = {}
if args.melanin:
    # One colour per curve: the colour of its first point. wisp colours a strand uniformly
    # (every point of a strand has the same colour); reading it back from the imported
    # curves, rather than from the file, keeps each value on its own curve whatever order
    # Mesh to Curve put the strands in.
    curves = hair_obj.data
    first = np.zeros(len(curves.curves), np.int32)
    curves.curves.foreach_get("first_point_index", first)
    rgba = np.zeros(len(curves.points) * 4, np.float32)
    curves.attributes[addon.COLOR_ATTRIBUTE].data.foreach_get("color", rgba)
    strand_rgb = rgba.reshape(-1, 4)[first, :3]
    m, r, eu, ph = melanin_from_color(strand_rgb)
    # How much of the colour two pigments can give: the colour eq. 9 gives back for the
    # fitted σa (c = e^(−√σa · fit)), against the strands' own.
    sigma_fit = eu[:, None] * EUMELANIN_SIGMA + ph[:, None] * PHEOMELANIN_SIGMA
    fitted_rgb = np.exp(-np.sqrt(sigma_fit) * absorption_fit(HAIR_RADIAL_ROUGHNESS))
    # Curve-domain float attributes, read by Attribute nodes: Cycles 3.4 exports a Curves
    # datablock's CURVE-domain attributes per curve (--check-attributes proves they arrive).
    set_curve_attribute(curves, MELANIN_ATTRIBUTE, m)
    set_curve_attribute(curves, REDNESS_ATTRIBUTE, r)
    stats["melanin"] = {
        "strands": len(m),
        "mean_color_linear": strand_rgb.mean(axis=0).tolist(),
        "mean_fitted_color_linear": fitted_rgb.mean(axis=0).tolist(),
        "melanin_mean": float(m.mean()), "melanin_min": float(m.min()),
        "melanin_max": float(m.max()),
        "redness_mean": float(r.mean()), "redness_min": float(r.min()),
        "redness_max": float(r.max()),
        "eumelanin_mean": float(eu.mean()), "pheomelanin_mean": float(ph.mean()),
    }

    nt = hair_material.node_tree
    nt.nodes.clear()
    bsdf = nt.nodes.new("ShaderNodeBsdfHairPrincipled")
    bsdf.parametrization = "MELANIN"
    inputs = bsdf.inputs
    inputs["Tint"].default_value = (1, 1, 1, 1)
    inputs["Roughness"].default_value = HAIR_ROUGHNESS
    inputs["Radial Roughness"].default_value = HAIR_RADIAL_ROUGHNESS
    inputs["Coat"].default_value = 0.0
    inputs["IOR"].default_value = HAIR_IOR
    inputs["Offset"].default_value = math.radians(HAIR_OFFSET_DEGREES)
    inputs["Random Color"].default_value = 0.0
    inputs["Random Roughness"].default_value = 0.0
    out_node = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(bsdf.outputs[0], out_node.inputs["Surface"])
    for i, (name, socket) in enumerate(((MELANIN_ATTRIBUTE, "Melanin"),
                                        (REDNESS_ATTRIBUTE, "Melanin Redness"))):
        attr = nt.nodes.new("ShaderNodeAttribute")
        attr.attribute_type = "GEOMETRY"
        attr.attribute_name = name
        attr.location = (-400, -200 * i)
        nt.links.new(attr.outputs["Fac"], inputs[socket])
    bsdf.location, out_node.location = (-150, 0), (150, 0)

if args.coverage:
    # Every camera sample that first hits a strand writes 1 into a value AOV, the skin and
    # the background nothing (0); Cycles averages AOVs over a pixel's samples like the
    # picture, so the pass is the hair's coverage of the pixel in front of the head.
    nt = hair_material.node_tree
    aov_node = nt.nodes.new("ShaderNodeOutputAOV")
    if hasattr(aov_node, "aov_name"):  # Blender 4.0+
        aov_node.aov_name = COVERAGE_AOV
    else:
        aov_node.name = COVERAGE_AOV
    aov_node.inputs["Value"].default_value = 1.0
    aov_node.location = (150, -200)
    aov = scene.view_layers[0].aovs.add()
    aov.name, aov.type = COVERAGE_AOV, "VALUE"

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
scene.cycles.samples = args.samples
scene.cycles.use_denoising = False
# Light hair takes its colour from light scattered through tens of fibres (Zinke et al.
# 2008): Cycles' default limits (4 glossy bounces, 12 in all) cut that off and leave blonde
# and grey hair darker and more contrasted than converged.
scene.cycles.max_bounces = 64
scene.cycles.glossy_bounces = 64
scene.cycles.transmission_bounces = 64
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "PNG"


def read_image(path):
    """An image Blender wrote, as #H×#W×4 float32 (row 0 at the top)."""
    img = bpy.data.images.load(path)
    px = np.zeros(img.size[0] * img.size[1] * 4, np.float32)
    img.pixels.foreach_get(px)
    h, w = img.size[1], img.size[0]
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1]


if args.check_attributes:
    if not args.melanin:
        sys.exit("blender_hair.py: --check-attributes needs --melanin")
    # Two 64² thumbnails at 4 samples of the hair alone (the head hidden) with every
    # strand's melanin at 0 (nearly white hair) and at 0.99 (black). An Attribute node that
    # finds nothing reads 0, so if the attributes did not reach the shader both come out
    # white and, rendered with the same seed, identical.
    curves = hair_obj.data
    n = len(curves.curves)
    keep = (scene.render.resolution_x, scene.cycles.samples)
    scene.render.resolution_x = scene.render.resolution_y = 64
    scene.cycles.samples = 4
    for head in head_objects:
        head.hide_render = True
    levels = []
    with tempfile.TemporaryDirectory() as tmp:
        for value in (0.0, 0.99):
            set_curve_attribute(curves, MELANIN_ATTRIBUTE, np.full(n, value))
            scene.render.filepath = os.path.join(tmp, f"check_{value}.png")
            bpy.ops.render.render(write_still=True)
            levels.append(read_image(scene.render.filepath)[..., :3])
    set_curve_attribute(curves, MELANIN_ATTRIBUTE, m)
    for head in head_objects:
        head.hide_render = False
    scene.render.resolution_x = scene.render.resolution_y = keep[0]
    scene.cycles.samples = keep[1]
    means = [float(v.mean()) for v in levels]
    print(f"blender_hair.py: attribute check: mean level {means[0]:.3f} with melanin 0, "
          f"{means[1]:.3f} with melanin 0.99")
    stats["attribute_check"] = {"mean_level_melanin_0": means[0],
                                "mean_level_melanin_0.99": means[1]}
    if means[0] - means[1] < 0.01:
        sys.exit("blender_hair.py: the melanin attribute does not reach the shader")

coverage_dir = None
if args.coverage:
    # The compositor writes the AOV to an OpenEXR file (linear floats; a PNG would go
    # through the view transform), read back below.
    coverage_dir = tempfile.TemporaryDirectory()
    scene.use_nodes = True
    ct = scene.node_tree
    layers = ct.nodes.get("Render Layers") or ct.nodes.new("CompositorNodeRLayers")
    composite = ct.nodes.get("Composite") or ct.nodes.new("CompositorNodeComposite")
    ct.links.new(layers.outputs["Image"], composite.inputs["Image"])
    file_out = ct.nodes.new("CompositorNodeOutputFile")
    file_out.base_path = coverage_dir.name
    file_out.format.file_format = "OPEN_EXR"
    file_out.format.color_depth = "32"
    file_out.file_slots[0].path = "coverage"
    ct.links.new(layers.outputs[COVERAGE_AOV], file_out.inputs[0])

scene.render.filepath = out
start = time.perf_counter()
bpy.ops.render.render(write_still=True)
stats["render_seconds"] = time.perf_counter() - start
print(f"blender_hair.py: rendered {out} in {stats['render_seconds']:.1f} s")

if args.coverage:
    name = next(f for f in os.listdir(coverage_dir.name) if f.startswith("coverage"))
    np.save(args.coverage, read_image(os.path.join(coverage_dir.name, name))[..., 0].copy())
    coverage_dir.cleanup()
if args.stats:
    with open(args.stats, "w") as f:
        json.dump(stats, f, indent=1)
