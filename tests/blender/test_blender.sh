#!/usr/bin/env bash
# export-gltf's file opened in Blender (headless): frame count, vertex count and one frame's
# positions. Skipped (exit 77) where Blender is not installed (Debian: blender).
set -euo pipefail
command -v blender >/dev/null || { echo "skipped: blender is not installed"; exit 77; }
: "${DF_BIN:?}" "${DF_TMP:?}"
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$DF_TMP" && mkdir -p "$DF_TMP" && cd "$DF_TMP"
"$DF_BIN/synth-meshseq" -q --frames 12 --resolution 6 -o f.h5
"$DF_BIN/export-gltf" -q f.h5 --fps 24 -o f.glb
# the expected positions of frame 7, from the source file (h5py through HDF5_PLUGIN_PATH)
/usr/bin/python3 - <<'PY'
import h5py
with h5py.File("f.h5") as f:
    p = f["frames/positions"][...]
with open("expect.txt", "w") as out:
    out.write(f"{p.shape[0]} {p.shape[1]} 7\n")
    for v in p[7]:
        out.write(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
PY
blender -b --factory-startup --python "$here/import_gltf.py" -- f.glb expect.txt 2>&1 | grep -E "^blender:|Error|assert" || true
blender -b --factory-startup --python-exit-code 1 --python "$here/import_gltf.py" -- f.glb expect.txt >/dev/null 2>&1
# a skeleton sequence: every joint's world position at frame 11 (24 fps: Blender's own frame rate,
# so that the keys fall on whole frames)
"$DF_BIN/synth-actions" -q --classes walk --per-class 1 --frames 30 -o act.h5
"$DF_BIN/export-gltf" -q act.h5 --fps 24 -o act.glb
/usr/bin/python3 - <<'PY'
import h5py
with h5py.File("act.h5") as f:
    p, names = f["poses"][...], [n.decode() if isinstance(n, bytes) else n for n in f["skeleton/joint_names"][...]]
with open("act.txt", "w") as out:
    out.write(f"{p.shape[1]} {p.shape[0]} 11\n")
    for v in p[11]:
        out.write(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
open("act.txt.names", "w").write("\n".join(names) + "\n")
PY
blender -b --factory-startup --python "$here/import_skeleton.py" -- act.glb act.txt 2>&1 | grep -E "^blender:|Error|assert" || true
blender -b --factory-startup --python-exit-code 1 --python "$here/import_skeleton.py" -- act.glb act.txt >/dev/null 2>&1
