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
#   gltf-animation  Sets the scene's frame rate to the run's, imports animation.glb the same way,
#         checks that it has a shape key per frame and an action over them spanning the frames
#         one scene frame apart, and compares the evaluated mesh's particles (world space, y up)
#         with positions.npy at the first, middle and last frames, and halfway between the middle
#         frame and the next with the mean of the two (the LINEAR blend).
# Prints the largest difference of each and exits 1 if one is above float32 rounding of the
# sheet's coordinates, or if the folder has neither export.
import json
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

if os.path.exists(out + "/animation.glb"):
    clear()
    with open(out + "/summary.json") as summary:
        fps = json.load(summary)["files"]["animation.glb"]["fps"]
    scene = bpy.context.scene
    scene.render.fps = fps  # before the import, which turns seconds into frames at this rate
    scene.render.fps_base = 1.0
    bpy.ops.import_scene.gltf(filepath=out + "/animation.glb", import_shading="SMOOTH")
    sheet = bpy.data.objects["clothsim_sheet"]
    keys = sheet.data.shape_keys
    frames = positions.shape[0]
    particles = positions.shape[1]
    shape_keys = len(keys.key_blocks) - 1  # less the basis
    action = keys.animation_data.action if keys.animation_data else None
    first, last = action.frame_range if action else (0.0, -1.0)

    def particles_at(frame, subframe=0.0):
        scene.frame_set(frame, subframe=subframe)
        evaluated = sheet.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        world = np.array([(evaluated.matrix_world @ v.co)[:] for v in mesh.vertices[:particles]])
        evaluated.to_mesh_clear()
        return np.stack([world[:, 0], world[:, 2], -world[:, 1]], axis=1)  # Blender z up to y up

    worst = 0.0
    middle = frames // 2
    start = int(round(first))
    for frame in sorted({0, middle, frames - 1}):
        worst = max(worst, float(np.abs(particles_at(start + frame) - positions[frame]).max()))
    if middle + 1 < frames:
        blend = 0.5 * (positions[middle] + positions[middle + 1])
        worst = max(worst, float(np.abs(particles_at(start + middle, 0.5) - blend).max()))
    right_shape = shape_keys == frames and abs((last - first) - (frames - 1)) < 1e-3
    print(f"clothsim glTF animation in Blender {bpy.app.version_string}: {shape_keys} shape keys, action "
          f"'{action.name if action else None}' frames {first:g} to {last:g} at {fps} fps ({frames} frames in "
          f"positions.npy), {len(sheet.data.vertices)} vertices; at frames 0, {middle}, {middle + 0.5}, "
          f"{frames - 1}: largest difference {worst:.3g} m (coordinates up to {scale:.3g} m)")
    failed |= worst > tolerance or not right_shape
    checked += 1

sys.exit(0 if checked > 0 and not failed else 1)
