"""A tiny PyTorch autoencoder on ACAP features computed through deformflow, and meshes back.

    python3 python/examples/torch_acap.py finger.h5 [--iterations 300] [-o recon.h5]

finger.h5: any acap file with positions (synth-meshseq -o finger.h5 makes one). The features
come from deformflow.acap_features, are normalised to [-0.95, 0.95] for tanh, a one-hidden-layer
autoencoder (9V -> 16 -> 9V) learns them, and its reconstructions go back to positions with
deformflow.Reconstructor; the script prints the training loss and E_rms (x1000) of the
reconstructed meshes, and writes them as an acap file (acap2obj / render-mesh / export-gltf read it).
"""
import argparse

import numpy as np
import torch

import deformflow as df

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("data")
parser.add_argument("--iterations", type=int, default=300)
parser.add_argument("--code", type=int, default=16)
parser.add_argument("-o", "--output", default="recon.h5")
args = parser.parse_args()

a = df.read_acap(args.data)
verts = a["positions"].astype(np.float64)                 # [F, V, 3]
faces = a["template"]["faces"]
features = df.acap_features(verts, faces)                  # [F, V, 9]
lo, hi = df.normalization(features)
x = torch.tensor(df.normalize(features, lo, hi).reshape(len(verts), -1), dtype=torch.float32)

torch.manual_seed(0)
model = torch.nn.Sequential(torch.nn.Linear(x.shape[1], args.code), torch.nn.Tanh(),
                            torch.nn.Linear(args.code, x.shape[1]), torch.nn.Tanh())
optimizer = torch.optim.Adam(model.parameters(), lr=1e-3)
for it in range(1, args.iterations + 1):
    optimizer.zero_grad()
    loss = torch.mean((model(x) - x) ** 2)
    loss.backward()
    optimizer.step()
    if it % max(1, args.iterations // 5) == 0 or it == args.iterations:
        print(f"iteration {it}: loss {loss.item():.6f}")

with torch.no_grad():
    y = model(x).double().numpy().reshape(features.shape)
decoded = df.normalize(np.ascontiguousarray(y), lo, hi, inverse=True)
recon = df.Reconstructor(verts[0], faces).solve(decoded)   # [F, V, 3]
print(f"E_rms of the reconstructed meshes: {df.erms(recon, verts):.3f}")
df.write_acap(args.output, verts[0], faces, positions=recon, features=decoded)
print(f"wrote {args.output}")
