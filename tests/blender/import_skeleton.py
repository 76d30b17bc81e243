"""Run inside Blender (blender -b --factory-startup --python import_skeleton.py -- FILE.glb EXPECT.txt):
imports export-gltf's skeleton file and checks the joint count and every joint's world position
at one frame against EXPECT.txt ("J T probe", then J lines of x y z). Exits 1 on a mismatch."""
import sys

import bpy
import numpy

if not hasattr(numpy, "bool") or "bool" in getattr(numpy, "__former_attrs__", {}):
    numpy.bool = bool  # Debian 12's Blender 3.4 importer with numpy 1.24 (see import_gltf.py)

glb, expect = sys.argv[sys.argv.index("--") + 1:][:2]
with open(expect) as f:
    joints, frames, probe = (int(x) for x in f.readline().split())
    truth = [tuple(float(x) for x in line.split()) for line in f]
names = [line for line in open(expect + ".names").read().split("\n") if line]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
objects = {o.name: o for o in bpy.context.scene.objects}
missing = [n for n in names if n not in objects]
assert not missing, f"joints not imported: {missing}"
action = next(o.animation_data.action for o in objects.values() if o.animation_data and o.animation_data.action)
first, last = action.frame_range
bpy.context.scene.frame_set(int(round(first + probe * (last - first) / (frames - 1))))
worst = 0.0
for name, t in zip(names, truth):
    w = objects[name].matrix_world.translation  # Blender +Z up: glTF (x, y, z) = (x, z, -y)
    worst = max(worst, abs(w.x - t[0]), abs(w.z - t[1]), abs(-w.y - t[2]))
print(f"blender: {len(names)} joints, frame {probe} of {frames} off by {worst:.2e}")
sys.exit(0 if worst < 1e-4 else 1)
