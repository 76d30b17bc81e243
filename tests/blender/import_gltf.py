"""Run inside Blender (blender -b --factory-startup --python import_gltf.py -- FILE.glb EXPECT.txt):
imports an export-gltf file and checks its animation against the source positions written by
test_blender.sh: the frame count, the vertex count and one frame's positions (evaluated with the
shape keys at that frame). Exits 1 with a message on a mismatch."""
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer still uses numpy.bool, which Debian's numpy 1.24 removed
# (AttributeError on import): the alias it meant.
if not hasattr(numpy, "bool") or "bool" in getattr(numpy, "__former_attrs__", {}):
    numpy.bool = bool

glb, expect = sys.argv[sys.argv.index("--") + 1:][:2]
with open(expect) as f:
    frames, vertices, probe = (int(x) for x in f.readline().split())
    truth = [tuple(float(x) for x in line.split()) for line in f]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
assert len(meshes) == 1, f"{len(meshes)} meshes"
obj = meshes[0]
keys = obj.data.shape_keys.key_blocks if obj.data.shape_keys else []
assert len(obj.data.vertices) == vertices, f"{len(obj.data.vertices)} vertices, expected {vertices}"
assert len(keys) == frames + 1, f"{len(keys)} shape keys, expected {frames} targets + the basis"
action = obj.data.shape_keys.animation_data.action
first, last = action.frame_range
fps = bpy.context.scene.render.fps / bpy.context.scene.render.fps_base
# Blender places key k at time k / fps (its scene frame 1 + k * scene_fps / fps)
bpy.context.scene.frame_set(int(round(first + probe * (last - first) / (frames - 1))))
mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
# glTF is +Y up, Blender +Z up: the importer maps (x, y, z) -> (x, -z, y)
worst = max(max(abs(a - b) for a, b in zip((v.co.x, v.co.z, -v.co.y), t)) for v, t in zip(mesh.vertices, truth))
print(f"blender: {len(keys) - 1} targets, {len(mesh.vertices)} vertices, frame {probe} off by {worst:.2e}")
sys.exit(0 if worst < 1e-4 else 1)
