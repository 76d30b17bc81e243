"""ACAP features from Python (deformflow.acap_features) against obj2acap on the same frames, at
1 and 2 threads: obj2acap reads the positions from an acap file and writes features (its whole
run); Python times the call on arrays already in memory and, separately, read + call.
  PYTHONPATH=build/python python3 bench/python_acap.py build/bin DATA.h5"""
import subprocess
import sys
import tempfile
import time

import numpy as np

import deformflow as df

bin_dir, data = sys.argv[1], sys.argv[2]
a = df.read_acap(data)
verts = a["positions"].astype(np.float64)
faces = a["template"]["faces"]
F, V = verts.shape[:2]
print(f"| frames | threads | obj2acap s | acap_features s | read + acap_features s | ratio |")
print("|---|---|---|---|---|---|")
for threads in (1, 2):
    df.set_threads(threads)
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        subprocess.run([f"{bin_dir}/obj2acap", "-q", "-f", "--threads", str(threads), data, "-o", f"{d}/o.h5"], check=True)
        tool = time.perf_counter() - t
    calls = []
    for _ in range(3):
        t = time.perf_counter()
        df.acap_features(verts, faces)
        calls.append(time.perf_counter() - t)
    t = time.perf_counter()
    b = df.read_acap(data)
    df.acap_features(b["positions"].astype(np.float64), b["template"]["faces"])
    both = time.perf_counter() - t
    print(f"| {F} x {V} v | {threads} | {tool:.2f} | {min(calls):.2f} | {both:.2f} | {min(calls) / tool:.2f} |")
