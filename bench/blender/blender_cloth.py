# Blender's own cloth on the sheet of `clothsim run cotton-drape` at N x N: the measurement that
# issue 25 compares clothsim with ("ten times faster than Blender's cloth on the same sheet").
#
#   blender -b --factory-startup --python bench/blender/blender_cloth.py -- N FRAMES FPS QUALITY
#
# The sheet: N x N vertices, side (N - 1) / 127 m (cotton-drape's spacing of 1/127 m), hung by the
# two corners of one edge (a pinned vertex group, clothsim's anchors=edge-corners), Blender's
# "Cotton" preset values (the ones its Physics panel applies: mass 0.3 kg per vertex, tension,
# compression and shear 15, bending 0.5) at QUALITY steps per frame, at FPS frames per second, no
# collisions. FRAMES frames are simulated one after the other as the timeline plays them
# (scene.frame_set), which is what baking does. Prints one JSON line: the vertex count, the frames
# simulated, the wall seconds of the frames alone, the lowest vertex's height at the end (a check
# that the cloth moved), and the seconds one of Blender's cloth frames stands for, measured.
#
# Blender's cloth does not take a frame as 1/FPS seconds: its solver works in frames, with gravity
# scaled to 0.001 g per frame squared, so a frame is sqrt(0.001) = 0.0316 s at any frame rate
# (measured here by a small sheet falling in a vacuum, seconds_per_frame()).
import json
import sys
import time

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
n, frames, fps, quality = int(args[0]), int(args[1]), int(args[2]), int(args[3])

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps = fps
scene.frame_start = 1
scene.frame_end = frames


def add_grid(name, count, spacing, height):
    """A flat, horizontal count x count grid of vertices `spacing` apart at `height`, linked to the scene."""
    side = (count - 1) * spacing
    vertices = [(spacing * j - side / 2, spacing * i, height) for i in range(count) for j in range(count)]
    faces = [(i * count + j, i * count + j + 1, (i + 1) * count + j + 1, (i + 1) * count + j)
             for i in range(count - 1) for j in range(count - 1)]
    grid = bpy.data.meshes.new(name)
    grid.from_pydata(vertices, [], faces)
    grid.update()
    added = bpy.data.objects.new(name, grid)
    scene.collection.objects.link(added)
    return added


# cotton-drape's sheet: N x N, 1/127 m apart, at a height of 1 m, row 0's two corners pinned.
sheet = add_grid("sheet", n, 1.0 / 127.0, 1.0)
mesh = sheet.data

pinned = sheet.vertex_groups.new(name="pinned")
pinned.add([0, n - 1], 1.0, "REPLACE")

cloth = sheet.modifiers.new(name="Cloth", type="CLOTH")
settings = cloth.settings
settings.quality = quality
settings.mass = 0.3
settings.tension_stiffness = 15.0
settings.compression_stiffness = 15.0
settings.shear_stiffness = 15.0
settings.bending_stiffness = 0.5
settings.vertex_group_mass = "pinned"
cloth.collision_settings.use_collision = False
cloth.collision_settings.use_self_collision = False
cloth.point_cache.frame_start = 1
cloth.point_cache.frame_end = frames

scene.frame_set(1)
start = time.perf_counter()
for frame in range(2, frames + 1):
    scene.frame_set(frame)
wall = time.perf_counter() - start

evaluated = sheet.evaluated_get(bpy.context.evaluated_depsgraph_get())
lowest = min((sheet.matrix_world @ v.co).z for v in evaluated.data.vertices)


def seconds_per_frame():
    """Blender's cloth runs in its own time: measured by a small free sheet falling in a vacuum.

    Its solver steps v += g' dt, x += v dt in frames (dt = 1 / quality), so after N = quality F
    steps from rest the sheet has fallen g' dt^2 N (N + 1) / 2; g' = g T^2 for T seconds a frame.
    """
    fall_frames = 11
    falling = add_grid("fall", 3, 0.1, 0.0)
    modifier = falling.modifiers.new(name="Cloth", type="CLOTH")
    modifier.settings.quality = quality
    modifier.settings.air_damping = 0.0
    modifier.collision_settings.use_collision = False
    scene.frame_set(1)
    for frame in range(2, fall_frames + 1):
        scene.frame_set(frame)
    fallen = -falling.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices[0].co.z
    steps = quality * (fall_frames - 1)
    dt = 1.0 / quality
    g_frames = fallen / (dt * dt * steps * (steps + 1) / 2)
    return (g_frames / abs(scene.gravity[2])) ** 0.5


print(json.dumps({"blender": bpy.app.version_string, "vertices": len(mesh.vertices), "quality": quality,
                  "frames_simulated": frames - 1, "wall_seconds": wall, "lowest_z": lowest,
                  "seconds_per_frame": seconds_per_frame()}))
