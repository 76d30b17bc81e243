"""python/examples/torch_acap.py runs (a few iterations) where PyTorch is installed."""
import os
import subprocess
import sys

import pytest

BIN = os.environ.get("DF_BIN", os.path.join(os.path.dirname(__file__), "..", "..", "build", "bin"))
EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "..", "python", "examples", "torch_acap.py")


def test_torch_example(tmp_path):
    pytest.importorskip("torch")
    subprocess.run([os.path.join(BIN, "synth-meshseq"), "-q", "--frames", "12", "--resolution", "6", "-o",
                    str(tmp_path / "finger.h5")], check=True)
    out = subprocess.run([sys.executable, EXAMPLE, str(tmp_path / "finger.h5"), "--iterations", "30", "-o",
                          str(tmp_path / "r.h5")], check=True, capture_output=True, text=True).stdout
    assert "E_rms of the reconstructed meshes" in out
    assert (tmp_path / "r.h5").exists()
    subprocess.run([os.path.join(BIN, "h5check"), "-q", str(tmp_path / "r.h5")], check=True)
