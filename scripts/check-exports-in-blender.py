# Opens a run's exports in Blender the way a user does and compares them with positions.npy.
#
#   clothsim run paper-fig5 --duration 0.5 --export pc2,gltf --render none --out out/fig5
#   blender -b --python scripts/check-exports-in-blender.py -- out/fig5
#
# Checks what the folder has of (docs/exports.md):
#   pc2   Imports rest.obj (Blender's OBJ importer, Y up: it puts the axis change in the object's
#         rotation and keeps the file's coordinates as the mesh's), adds a Mesh Cache modifier
#         reading animation.pc2 with its default settings, and at every frame compares the
#         evaluated mesh's vertices (object space) with positions.npy, which the cache rounds to
#         float32.
#   gltf  Imports final.glb (Blender's glTF importer, which turns glTF's y up into Blender's z up
#         in the mesh's coordinates), checks that its vertex and face counts are final.obj's, and
#         compares its first rows*cols vertices (world space, turned back to y up) with the last
#         frame of positions.npy. Shading "Smooth": Debian 12's Blender 3.4.1 fails with Debian's
#         NumPy 1.24 in the importer's default shading guess (np.bool, gone from NumPy 1.24).
# Prints the largest difference of each and exits 1 if one is above float32 rounding of the
# sheet's coordinates, or if the folder has neither export.
import os
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
positions = np.load(out + "/positions.npy")
scale = float(np.abs(positions).max())
tolerance = 1e-6 * max(1.0, scale)
failed = False
checked = 0


def clear():
    bpy.ops.wm.read_factory_settings(use_empty=True)


if os.path.exists(out + "/animation.pc2"):
    clear()
    if hasattr(bpy.ops.wm, "obj_import"):  # Blender 3.3 and later
        bpy.ops.wm.obj_import(filepath=out + "/rest.obj", forward_axis="NEGATIVE_Z", up_axis="Y")
    else:
        bpy.ops.import_scene.obj(filepath=out + "/rest.obj", split_mode="OFF", axis_forward="-Z", axis_up="Y")
    sheet = bpy.context.selected_objects[0]
    cache = sheet.modifiers.new("clothsim", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = out + "/animation.pc2"

    worst = 0.0
    for frame in range(positions.shape[0]):
        bpy.context.scene.frame_set(frame)
        evaluated = sheet.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        vertices = np.array([v.co[:] for v in mesh.vertices])
        evaluated.to_mesh_clear()
        worst = max(worst, float(np.abs(vertices - positions[frame]).max()))
    print(f"clothsim PC2 in Blender {bpy.app.version_string}: {positions.shape[0]} frames, "
          f"{positions.shape[1]} vertices, largest difference {worst:.3g} m (coordinates up to {scale:.3g} m)")
    failed |= worst > tolerance
    checked += 1

if os.path.exists(out + "/final.glb"):
    clear()
    bpy.ops.import_scene.gltf(filepath=out + "/final.glb", import_shading="SMOOTH")
    sheet = bpy.data.objects["clothsim_sheet"]
    mesh = sheet.data
    world = np.array([(sheet.matrix_world @ v.co)[:] for v in mesh.vertices])
    clothsim = np.stack([world[:, 0], world[:, 2], -world[:, 1]], axis=1)  # Blender z up to y up
    obj_vertices = obj_faces = 0
    with open(out + "/final.obj") as obj:
        for line in obj:
            obj_vertices += line.startswith("v ")
            obj_faces += line.startswith("f ")
    particles = positions.shape[1]
    worst = float(np.abs(clothsim[:particles] - positions[-1]).max())
    same_counts = len(mesh.vertices) == obj_vertices and len(mesh.polygons) == obj_faces
    print(f"clothsim glTF in Blender {bpy.app.version_string}: {len(mesh.vertices)} vertices, "
          f"{len(mesh.polygons)} faces (final.obj: {obj_vertices}, {obj_faces}), material "
          f"{mesh.materials[0].name} double-sided {not mesh.materials[0].use_backface_culling}, "
          f"largest difference {worst:.3g} m (coordinates up to {scale:.3g} m)")
    failed |= worst > tolerance or not same_counts
    checked += 1

sys.exit(0 if checked > 0 and not failed else 1)
