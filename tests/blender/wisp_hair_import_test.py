# Headless test of blender/wisp_hair_import.py, run by CTest through run_blender_test.sh:
#   blender -b --factory-startup --python-exit-code 1 --python wisp_hair_import_test.py -- \
#       ADDON.py WISP_EXE WORK_DIR
# Installs and enables the add-on as a user would (Preferences > Install, into the
# BLENDER_USER_SCRIPTS the driver points at WORK_DIR), imports a hand-written .hair file of
# known values and one that wisp generates (with wisp's head), and checks the Curves
# object: type, curve and point counts, radius and color, positions after the axis and
# unit conversion. Any failure raises, so Blender exits with code 1.
import os
import struct
import subprocess
import sys

import bpy
import numpy as np
from mathutils import Matrix

addon_path, wisp_exe, work = sys.argv[sys.argv.index("--") + 1:][:3]
os.makedirs(work, exist_ok=True)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def write_cyhair(path, sizes, points, thickness, colors):
    """A cyHair file with the segments, points, thickness and color arrays."""
    S, P = len(sizes), len(points)
    header = struct.pack("<4sIII I f f 3f", b"HAIR", S, P, 1 | 2 | 4 | 16, 0, 0.01, 1.0,
                         0.3, 0.2, 0.1)
    header += b"test".ljust(88, b"\0")
    assert len(header) == 128
    with open(path, "wb") as f:
        f.write(header)
        f.write((np.asarray(sizes) - 1).astype("<u2").tobytes())
        f.write(np.asarray(points, np.float32).tobytes())
        f.write(np.asarray(thickness, np.float32).tobytes())
        f.write(np.asarray(colors, np.float32).tobytes())


def curves_arrays(obj):
    c = obj.data
    P = len(c.points)
    pos = np.empty(3 * P, np.float32)
    c.attributes["position"].data.foreach_get("vector", pos)
    radius = np.empty(P, np.float32)
    c.attributes["radius"].data.foreach_get("value", radius)
    color = np.empty(4 * P, np.float32)
    c.attributes["wisp_color"].data.foreach_get("color", color)
    sizes = np.array([cv.points_length for cv in c.curves])
    return pos.reshape(-1, 3), radius, color.reshape(-1, 4), sizes


# 1. Install and enable the add-on the way Preferences > Add-ons > Install does.
bpy.ops.preferences.addon_install(filepath=addon_path, overwrite=True)
bpy.ops.preferences.addon_enable(module="wisp_hair_import")
import wisp_hair_import  # noqa: E402  (on the path once installed)

check(hasattr(bpy.types, "IMPORT_SCENE_OT_wisp_hair"),
      "the add-on registers import_scene.wisp_hair")
menu_funcs = getattr(bpy.types.TOPBAR_MT_file_import.draw, "_draw_funcs", [])
check(wisp_hair_import._menu_import in menu_funcs, "File > Import lists 'wisp hair (.hair)'")

# 2. Known values: 3 strands of 2, 3 and 4 points.
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_enable(module="wisp_hair_import")
sizes = [2, 3, 4]
pts = np.array([[1, 2, 3], [1, 5, 3],
                [-4, 10, 7], [-4, 9, 8], [-4, 8, 9],
                [0, 0, 0], [1, 0, 0], [2, 0, 0], [3.5, -1.25, 0.5]], np.float32)
widths = np.linspace(0.01, 0.09, 9).astype(np.float32)
strand_colors = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
cols = np.repeat(strand_colors, sizes, axis=0)
small = os.path.join(work, "small.hair")
write_cyhair(small, sizes, pts, widths, cols)
result = bpy.ops.import_scene.wisp_hair(filepath=small)
check(result == {"FINISHED"}, f"the operator finishes ({result})")
obj = bpy.context.view_layer.objects.active
check(obj is not None and obj.type == "CURVES",
      f"the imported object is CURVES ({obj and obj.type})")
check(len(obj.modifiers) == 0, "no modifier is left on it")
check(len(obj.data.curves) == 3 and len(obj.data.points) == 9,
      f"3 curves, 9 points ({len(obj.data.curves)}, {len(obj.data.points)})")
pos, radius, color, got_sizes = curves_arrays(obj)
check(list(got_sizes) == sizes, f"points per curve {list(got_sizes)}")
expected = np.stack([pts[:, 0], -pts[:, 2], pts[:, 1]], axis=1) * 0.01
check(np.allclose(pos, expected, atol=1e-7), "positions are (x, -z, y) * 0.01")
check(np.allclose(pos[1], [0.01, -0.03, 0.05], atol=1e-7),
      f"(1, 5, 3) cm -> (0.01, -0.03, 0.05) m, got {pos[1]}")
check(np.allclose(radius, widths * 0.005, rtol=1e-6), "radius = width / 2 * 0.01")
check(np.allclose(color[:, :3], cols) and np.all(color[:, 3] == 1), "per-point colors")
check(obj.data.attributes["wisp_color"].data_type == "FLOAT_COLOR", "wisp_color is a float color")
check("wisp_radius" not in obj.data.attributes, "the helper attribute is removed")
check(len(bpy.data.meshes) == 0 and len(bpy.data.node_groups) == 0,
      f"no helper mesh or node group is left ({len(bpy.data.meshes)}, "
      f"{len(bpy.data.node_groups)})")
check(len(obj.data.materials) == 1, "a hair material")

# 3. A file wisp writes, with wisp's head.
hair = os.path.join(work, "short.hair")
head = os.path.join(work, "head.obj")
subprocess.run([wisp_exe, "generate", "--preset", "short", "--strands", "2000", "--wisps", "200",
                "-o", hair, "-q"], check=True)
subprocess.run([wisp_exe, "head", "-o", head], check=True, stdout=subprocess.DEVNULL)
bpy.ops.wm.read_factory_settings(use_empty=True)
obj = wisp_hair_import.import_wisp_hair(hair, head_obj=head)
src = wisp_hair_import.read_cyhair(hair)
check(obj.type == "CURVES", "wisp's file imports as CURVES")
check(len(obj.data.curves) == len(src.sizes) == 2000,
      f"{len(obj.data.curves)} curves, {len(src.sizes)} in the file")
check(len(obj.data.points) == len(src.points), f"{len(obj.data.points)} points")
pos, radius, color, got_sizes = curves_arrays(obj)
check(np.array_equal(got_sizes, src.sizes), "points per curve as in the file")
check(np.allclose(pos, wisp_hair_import.wisp_to_blender(src.points), atol=1e-6),
      "every point in order, (x, -z, y) * 0.01")
last = len(src.points) - 1
x, y, z = src.points[last]
check(np.allclose(pos[last], [0.01 * x, -0.01 * z, 0.01 * y], atol=1e-6),
      f"last point ({x}, {y}, {z}) cm -> {pos[last]} m")
check(np.allclose(radius, src.thickness * 0.005, rtol=1e-6), "radii")
check(np.allclose(color[:, :3], src.colors), "colors")
heads = [o for o in bpy.data.objects if o.type == "MESH"]
check(len(heads) == 1, f"one head mesh ({[o.name for o in heads]})")
if heads:
    v = np.empty(3 * len(heads[0].data.vertices), np.float32)
    heads[0].data.vertices.foreach_get("co", v)
    v = v.reshape(-1, 3)
    # The OBJ's vertices, turned (x, -z, y) * 0.01, have the same bounds as the head's, in
    # the mesh and in the world (the importer's transform is baked into the mesh).
    check(heads[0].matrix_world == Matrix.Identity(4), "the head has an identity transform")
    obj_v = np.array([[float(t) for t in line.split()[1:4]] for line in open(head)
                      if line.startswith("v ")], np.float32)
    want = wisp_hair_import.wisp_to_blender(obj_v)
    lo, hi = v.min(axis=0), v.max(axis=0)
    check(np.allclose(lo, want.min(axis=0), atol=1e-5) and
          np.allclose(hi, want.max(axis=0), atol=1e-5),
          f"head bounds {lo}..{hi} m, expected {want.min(axis=0)}..{want.max(axis=0)}")
    roots = pos[np.concatenate([[0], np.cumsum(got_sizes)[:-1]])]
    inside = np.all((roots >= lo - 0.01) & (roots <= hi + 0.01), axis=1).mean()
    check(inside > 0.99, f"the roots lie on the head ({inside:.3f} within its bounds)")

# 4. A bad file is refused with the file named.
bad = os.path.join(work, "bad.hair")
with open(bad, "wb") as f:
    f.write(b"HAIR" + b"\0" * 20)
try:
    wisp_hair_import.read_cyhair(bad)
    check(False, "a truncated file is refused")
except ValueError as e:
    check("bad.hair" in str(e) and "byte" in str(e), f"a truncated file is refused: {e}")

one = os.path.join(work, "one.hair")
write_cyhair(one, [2, 1], pts[:3], widths[:3], cols[:3])
try:
    wisp_hair_import.read_cyhair(one)
    check(False, "a strand of 1 point is refused")
except ValueError as e:
    check("strand 1 has 1 point" in str(e), f"a strand of 1 point is refused: {e}")

bpy.ops.preferences.addon_disable(module="wisp_hair_import")
check(not hasattr(bpy.types, "IMPORT_SCENE_OT_wisp_hair"), "disabling the add-on unregisters it")

if failures:
    print(f"wisp_hair_import_test: {len(failures)} failures")
    sys.exit(1)
print("wisp_hair_import_test: all checks passed")
