# wisp hair importer for Blender 3.4+: reads wisp's cyHair `.hair` files into a native hair
# Curves object with per-point `radius` (metres) and `wisp_color` (linear RGB) attributes.
#
# Install: Edit > Preferences > Add-ons > Install... > this file, then tick
# "Import-Export: wisp hair". Then File > Import > wisp hair (.hair).
# From a script (e.g. `blender -b --python-expr`):
#     import wisp_hair_import
#     obj = wisp_hair_import.import_wisp_hair("hair.hair", head_obj="head.obj")
#
# wisp's head space is centimetres, Y up, the face looking along +Z; Blender's is Z up,
# the face looking along -Y, so a point (x, y, z) becomes (x, -z, y) * scale, with scale
# 0.01 (centimetres to metres) by default. Widths (diameters) become radii in the same
# units.
#
# Blender 3.4 has no Python API to fill a Curves datablock (Curves.add_curves came in 3.5),
# so the strands go through a mesh: every point a vertex, consecutive points of a strand
# joined by an edge (numpy + foreach_set), per-point attributes on it, and a Geometry Nodes
# modifier (Mesh to Curve, Set Curve Radius) that Object > Convert > Curves applies. The
# result is a plain Curves object with no modifier and no helper object left behind.
import os
import struct
import time

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

bl_info = {
    "name": "wisp hair",
    "author": "wisp",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > wisp hair (.hair)",
    "description": "Imports wisp's cyHair .hair files as hair curves with radius and color",
    "category": "Import-Export",
}

_HEADER_BYTES = 128
_RADIUS_SOURCE = "wisp_radius"
# The strands' colour attribute. Not `color`: Cycles' Attribute node does not find a curves
# attribute of that name (the hair renders black), while any other name works.
COLOR_ATTRIBUTE = "wisp_color"


class CyHair:
    """A cyHair file's arrays.

    points      #P x 3 float32, as stored (wisp: centimetres, Y up)
    sizes       #S int64, points per strand (each >= 1)
    thickness   #P float32, diameters, same units as the points
    colors      #P x 3 float32, linear RGB
    info        the header's info string
    """

    def __init__(self, points, sizes, thickness, colors, info):
        self.points, self.sizes = points, sizes
        self.thickness, self.colors, self.info = thickness, colors, info


def read_cyhair(filepath):
    """Reads a cyHair file (Cem Yuksel's format, as docs/formats.md describes it).

    Raises ValueError naming the file, the byte offset and what is wrong.
    """
    with open(filepath, "rb") as f:
        data = f.read()

    def fail(at, what):
        raise ValueError(f"{filepath}: byte {at}: {what}")

    if len(data) < _HEADER_BYTES:
        fail(len(data), f"a cyHair header needs {_HEADER_BYTES} bytes, the file has {len(data)}")
    if data[:4] != b"HAIR":
        fail(0, f"expected the signature 'HAIR', got {data[:4]!r}")
    strands, points, flags, d_segments = struct.unpack_from("<4I", data, 4)
    d_thickness, _d_transparency = struct.unpack_from("<2f", data, 20)
    d_color = struct.unpack_from("<3f", data, 28)
    info = data[40:128].split(b"\0", 1)[0].decode("utf-8", "replace")
    has_segments, has_points = bool(flags & 1), bool(flags & 2)
    has_thickness, has_transparency, has_color = bool(flags & 4), bool(flags & 8), bool(flags & 16)
    if not has_points:
        fail(12, "the file has no points array (flag bit 1 is clear)")
    expected = (_HEADER_BYTES + 2 * strands * has_segments + 12 * points
                + 4 * points * has_thickness + 4 * points * has_transparency
                + 12 * points * has_color)
    if expected != len(data):
        fail(len(data), f"the header declares {strands} strands and {points} points, "
                        f"{expected} bytes, but the file has {len(data)}")
    at = _HEADER_BYTES
    if has_segments:
        sizes = np.frombuffer(data, np.uint16, strands, at).astype(np.int64) + 1
        at += 2 * strands
    else:
        sizes = np.full(strands, d_segments + 1, np.int64)
    if strands == 0:
        fail(4, "the file holds no strands")
    short = np.flatnonzero(sizes < 2)
    if len(short):
        fail(_HEADER_BYTES + 2 * int(short[0]) * has_segments,
             f"strand {int(short[0])} has {int(sizes[short[0]])} point; a hair curve needs 2")
    if int(sizes.sum()) != points:
        fail(_HEADER_BYTES, f"the strands have {int(sizes.sum())} points in all, "
                            f"the header says {points}")
    p = np.frombuffer(data, np.float32, 3 * points, at).reshape(-1, 3)
    at += 12 * points
    if has_thickness:
        thickness = np.frombuffer(data, np.float32, points, at)
        at += 4 * points
    else:
        thickness = np.full(points, d_thickness, np.float32)
    if has_transparency:
        at += 4 * points
    if has_color:
        colors = np.frombuffer(data, np.float32, 3 * points, at).reshape(-1, 3)
    else:
        colors = np.tile(np.array(d_color, np.float32), (points, 1))
    if not (np.isfinite(p).all() and np.isfinite(thickness).all()
            and np.isfinite(colors).all()):
        fail(_HEADER_BYTES, "the file holds NaN or infinite values")
    return CyHair(p, sizes, thickness, colors, info)


def wisp_to_blender(points, scale=0.01):
    """wisp head space (#N x 3; cm, Y up, +Z forward) to Blender's (Z up, -Y forward),
    (x, y, z) -> (x, -z, y) * scale. Returns #N x 3 float32."""
    p = np.asarray(points, np.float32).reshape(-1, 3)
    out = np.empty_like(p)
    out[:, 0] = p[:, 0]
    out[:, 1] = -p[:, 2]
    out[:, 2] = p[:, 1]
    out *= np.float32(scale)
    return out


def _polyline_mesh(name, hair, scale):
    """A mesh of loose edges: vertex i is point i, an edge joins consecutive points of a
    strand; per-point float `wisp_radius` and float colour `wisp_color` attributes."""
    P = len(hair.points)
    ends = np.cumsum(hair.sizes)
    joined = np.ones(P, bool)
    joined[ends - 1] = False
    # uint32, the type of MEdge's vertex indices: foreach_set copies a matching buffer
    # straight (0.2 s for 3.1 M edges) but converts an int32 one item by item (1 s).
    a = np.flatnonzero(joined).astype(np.uint32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(P)
    mesh.vertices.foreach_set("co", wisp_to_blender(hair.points, scale).ravel())
    mesh.edges.add(len(a))
    mesh.edges.foreach_set("vertices", np.stack([a, a + 1], axis=1).ravel())
    radius = mesh.attributes.new(_RADIUS_SOURCE, "FLOAT", "POINT")
    radius.data.foreach_set("value", (hair.thickness * np.float32(0.5 * scale)).astype(np.float32))
    rgba = np.ones((P, 4), np.float32)
    rgba[:, :3] = hair.colors
    color = mesh.attributes.new(COLOR_ATTRIBUTE, "FLOAT_COLOR", "POINT")
    color.data.foreach_set("color", rgba.ravel())
    mesh.update()
    return mesh


def _to_curves_tree():
    """Geometry nodes: mesh -> Mesh to Curve -> Set Curve Radius (from wisp_radius)."""
    tree = bpy.data.node_groups.new("wisp_mesh_to_hair", "GeometryNodeTree")
    if hasattr(tree, "interface"):  # Blender 4.0+ replaced tree.inputs/outputs
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    n_in = tree.nodes.new("NodeGroupInput")
    n_out = tree.nodes.new("NodeGroupOutput")
    to_curve = tree.nodes.new("GeometryNodeMeshToCurve")
    set_radius = tree.nodes.new("GeometryNodeSetCurveRadius")
    radius = tree.nodes.new("GeometryNodeInputNamedAttribute")
    radius.data_type = "FLOAT"
    radius.inputs["Name"].default_value = _RADIUS_SOURCE
    tree.links.new(n_in.outputs[0], to_curve.inputs["Mesh"])
    tree.links.new(to_curve.outputs["Curve"], set_radius.inputs["Curve"])
    # The node has one output per data type, all named "Attribute" in 3.4; only the one of
    # its data_type is enabled (outputs["Attribute"] is the disabled vector one).
    value = next(s for s in radius.outputs if s.enabled)
    tree.links.new(value, set_radius.inputs["Radius"])
    tree.links.new(set_radius.outputs["Curve"], n_out.inputs[0])
    return tree


def _hair_material(name):
    """Principled Hair BSDF coloured by the `wisp_color` attribute."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    bsdf = nt.nodes.new("ShaderNodeBsdfHairPrincipled")
    bsdf.parametrization = "COLOR"
    attr = nt.nodes.new("ShaderNodeAttribute")
    attr.attribute_name = COLOR_ATTRIBUTE
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    attr.location, bsdf.location, out.location = (-400, 0), (-150, 0), (150, 0)
    nt.links.new(attr.outputs["Color"], bsdf.inputs["Color"])
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def import_head_obj(filepath, scale=0.01, collection=None, name="head"):
    """Imports a Y-up, +Z-forward OBJ (wisp's head space) with Blender's OBJ importer,
    whose default axes do (x, y, z) -> (x, -z, y), and bakes the importer's rotation and
    scale into the mesh, so the head's vertices are where the hair's points are (both
    objects keep an identity transform). Returns the new mesh objects."""
    from mathutils import Matrix

    before = set(bpy.data.objects)
    bpy.ops.wm.obj_import(filepath=str(filepath), global_scale=scale,
                          forward_axis="NEGATIVE_Z", up_axis="Y")
    new = [o for o in bpy.data.objects if o not in before]
    for o in new:
        if o.type == "MESH":
            o.data.transform(o.matrix_world)
            o.matrix_world = Matrix.Identity(4)
        if collection is not None and collection not in o.users_collection:
            for c in list(o.users_collection):
                c.objects.unlink(o)
            collection.objects.link(o)
    if len(new) == 1:
        new[0].name = name
    return new


def import_wisp_hair(filepath, head_obj="", scale=0.01, material=True, name=None,
                     collection=None):
    """Imports a wisp `.hair` file as a hair Curves object and returns it.

    filepath    the cyHair file (wisp: centimetres, Y up, +Z forward)
    head_obj    optional OBJ of the head in the same space, imported beside the hair
    scale       Blender units per file unit (0.01: centimetres to metres)
    material    add a Principled Hair BSDF material reading the `wisp_color` attribute
    name        the object's name (default: the file's stem)
    collection  where the objects go (default: the active collection)

    The object (type 'CURVES') has one curve per strand, one point per control point
    (positions (x, -z, y) * scale), the built-in float `radius` (half the width * scale)
    and a float colour `wisp_color` per point (linear RGB, alpha 1). The strand points are
    control points of wisp's pinned Catmull-Rom spline, imported as poly curves.
    """
    t0 = time.perf_counter()
    hair = read_cyhair(filepath)
    if name is None:
        name = os.path.splitext(os.path.basename(str(filepath)))[0]
    context = bpy.context
    if collection is None:
        collection = context.view_layer.active_layer_collection.collection

    mesh = _polyline_mesh(name, hair, scale)
    obj = bpy.data.objects.new(name, mesh)
    collection.objects.link(obj)
    tree = _to_curves_tree()
    modifier = obj.modifiers.new("wisp_to_hair", "NODES")
    modifier.node_group = tree

    # Convert > Curves applies the modifier and swaps the object's data for a Curves
    # datablock; it works on the selected objects.
    view_layer = context.view_layer
    for o in list(context.selected_objects):
        o.select_set(False)
    obj.select_set(True)
    view_layer.objects.active = obj
    result = bpy.ops.object.convert(target="CURVES")
    if "FINISHED" not in result or obj.type != "CURVES":
        raise RuntimeError(f"{filepath}: converting the strands to hair curves failed "
                           f"({result}, object type {obj.type})")
    # The helper mesh is left with a stale user count of 1 though nothing uses it
    # (bpy.data.user_map finds no user).
    bpy.data.node_groups.remove(tree)
    mesh.user_clear()
    bpy.data.meshes.remove(mesh)

    curves = obj.data
    curves.name = name
    for attr_name in (_RADIUS_SOURCE, ".select_vert", ".select_edge"):
        attr = curves.attributes.get(attr_name)
        if attr is not None:
            curves.attributes.remove(attr)
    if len(curves.curves) != len(hair.sizes) or len(curves.points) != len(hair.points):
        raise RuntimeError(f"{filepath}: made {len(curves.curves)} curves and "
                           f"{len(curves.points)} points, expected {len(hair.sizes)} and "
                           f"{len(hair.points)}")
    if material:
        curves.materials.append(_hair_material(name))
    if head_obj:
        import_head_obj(head_obj, scale, collection)
        for o in list(context.selected_objects):
            o.select_set(False)
        obj.select_set(True)
        view_layer.objects.active = obj
    obj["wisp_source"] = str(filepath)
    obj["wisp_import_seconds"] = time.perf_counter() - t0
    return obj


class ImportWispHair(bpy.types.Operator, ImportHelper):
    """Import a wisp cyHair file as hair curves with radius and color"""

    bl_idname = "import_scene.wisp_hair"
    bl_label = "Import wisp hair"
    bl_options = {"REGISTER", "UNDO", "PRESET"}

    filename_ext = ".hair"
    filter_glob: StringProperty(default="*.hair", options={"HIDDEN"})
    head_obj: StringProperty(
        name="Head OBJ", subtype="FILE_PATH", default="",
        description="Optional head mesh (.obj, wisp's head space) imported with the hair")
    scale: FloatProperty(
        name="Scale", default=0.01, min=1e-6, soft_max=1.0,
        description="Blender units per file unit (0.01: wisp's centimetres to metres)")
    material: BoolProperty(
        name="Hair Material", default=True,
        description="Add a Principled Hair BSDF coloured by the strands' wisp_color attribute")

    def execute(self, context):
        try:
            obj = import_wisp_hair(self.filepath, head_obj=bpy.path.abspath(self.head_obj),
                                   scale=self.scale, material=self.material)
        except (OSError, ValueError, RuntimeError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"wisp hair: {len(obj.data.curves)} strands, "
                              f"{len(obj.data.points)} points in "
                              f"{obj['wisp_import_seconds']:.2f} s")
        return {"FINISHED"}


def _menu_import(self, context):
    self.layout.operator(ImportWispHair.bl_idname, text="wisp hair (.hair)")


def register():
    bpy.utils.register_class(ImportWispHair)
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)


def unregister():
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
    bpy.utils.unregister_class(ImportWispHair)


if __name__ == "__main__":
    register()
