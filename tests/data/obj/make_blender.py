# Writes blender_sphere.obj with Blender's own OBJ exporter (Blender 3.4's C++ one):
#   blender -b --factory-startup --python tests/data/obj/make_blender.py
# A UV sphere (radius 1, Blender's Z up) with two materials, "skin" and "scalp" (the faces
# above 0.3), smooth shading: what a user's head exported from Blender looks like to wisp
# (o, usemtl, s, vt and vn lines of their own counts, quads and triangles, a .mtl that is not
# shipped with it).
import os

import bpy

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=1.0)
sphere = bpy.context.active_object
sphere.name = "Head"
skin = bpy.data.materials.new("skin")
scalp = bpy.data.materials.new("scalp")
sphere.data.materials.append(skin)
sphere.data.materials.append(scalp)
for poly in sphere.data.polygons:
    poly.material_index = 1 if poly.center.z > 0.3 else 0
bpy.ops.object.shade_smooth()
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_sphere.obj")
bpy.ops.wm.obj_export(filepath=out, export_selected_objects=False, export_uv=True,
                      export_normals=True, export_materials=True,
                      export_triangulated_mesh=False, forward_axis="NEGATIVE_Z", up_axis="Y")
os.remove(os.path.splitext(out)[0] + ".mtl")
