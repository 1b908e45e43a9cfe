# Opens a run's PC2 export in Blender the way a user does and compares it with positions.npy.
#
#   clothsim run paper-fig5 --duration 0.5 --export pc2 --render none --out out/fig5
#   blender -b --python scripts/check-pc2-in-blender.py -- out/fig5
#
# Imports rest.obj (Blender's OBJ importer, Y up: it puts the axis change in the object's
# rotation and keeps the file's coordinates as the mesh's), adds a Mesh Cache modifier reading
# animation.pc2 with its default settings, and at every frame compares the evaluated mesh's
# vertices (object space) with positions.npy, which the cache rounds to float32. Prints the
# largest difference and exits 1 if it is above float32 rounding of the sheet's coordinates.
import sys

import bpy
import numpy as np

out = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
if hasattr(bpy.ops.wm, "obj_import"):  # Blender 3.3 and later
    bpy.ops.wm.obj_import(filepath=out + "/rest.obj", forward_axis="NEGATIVE_Z", up_axis="Y")
else:
    bpy.ops.import_scene.obj(filepath=out + "/rest.obj", split_mode="OFF", axis_forward="-Z", axis_up="Y")
sheet = bpy.context.selected_objects[0]
cache = sheet.modifiers.new("clothsim", "MESH_CACHE")
cache.cache_format = "PC2"
cache.filepath = out + "/animation.pc2"

positions = np.load(out + "/positions.npy")
worst = 0.0
for frame in range(positions.shape[0]):
    bpy.context.scene.frame_set(frame)
    evaluated = sheet.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    vertices = np.array([v.co[:] for v in mesh.vertices])
    evaluated.to_mesh_clear()
    worst = max(worst, float(np.abs(vertices - positions[frame]).max()))
scale = float(np.abs(positions).max())
print(f"clothsim PC2 in Blender {bpy.app.version_string}: {positions.shape[0]} frames, "
      f"{positions.shape[1]} vertices, largest difference {worst:.3g} m (coordinates up to {scale:.3g} m)")
sys.exit(0 if worst <= 1e-6 * max(1.0, scale) else 1)
