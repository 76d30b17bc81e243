"""The deformflow Python module against the command-line tools on the same data (ctest label
`python`; run: PYTHONPATH=build/python DF_BIN=build/bin python3 -m pytest tests/python)."""
import json
import os
import subprocess

import h5py
import numpy as np
import pytest

import deformflow as df

BIN = os.environ.get("DF_BIN", os.path.join(os.path.dirname(__file__), "..", "..", "build", "bin"))


def tool(*args):
    return subprocess.run([os.path.join(BIN, args[0]), *args[1:]], check=True, capture_output=True, text=True).stdout


@pytest.fixture(scope="module")
def finger(tmp_path_factory):
    """A twisting finger (synth-meshseq) and its features from obj2acap."""
    d = tmp_path_factory.mktemp("finger")
    tool("synth-meshseq", "-q", "--frames", "12", "--resolution", "6", "-o", str(d / "f.h5"))
    tool("obj2acap", "-q", str(d / "f.h5"), "-o", str(d / "a.h5"))
    return d


def test_features_equal_obj2acap(finger):
    a = df.read_acap(str(finger / "a.h5"))
    verts = a["positions"].astype(np.float64)  # obj2acap read the same float32 positions
    f = df.acap_features(verts, a["template"]["faces"])
    assert f.shape == a["features"].shape
    assert np.abs(f - a["features"]).max() <= 1e-12
    # without consistency: principal logs, the same stretches
    g = df.acap_features(verts, a["template"]["faces"], consistency=False)
    assert np.abs(g[..., 3:] - a["features"][..., 3:]).max() <= 1e-12


def test_reconstruction_equals_acap2obj_and_round_trips(finger):
    a = df.read_acap(str(finger / "a.h5"))
    tool("acap2obj", "-q", str(finger / "a.h5"), "--anchor-positions", "reference", "-o", str(finger / "r.h5"))
    stored = df.read_acap(str(finger / "r.h5"))["positions"]  # float32 in the file
    rec = df.Reconstructor(a["template"]["vertices"], a["template"]["faces"])
    p = rec.solve(a["features"])
    assert p.shape == stored.shape
    assert np.array_equal(p.astype(np.float32), stored)  # the same solve, rounded as the file is
    assert np.array_equal(rec.solve(a["features"][3]), p[3])  # one frame alone
    # features of the reconstruction give it back (the exact gradient system)
    f = df.acap_features(p, a["template"]["faces"])
    assert np.abs(df.acap_reconstruct(f, a["template"]["vertices"], a["template"]["faces"]) - p).max() < 1e-9


def test_metrics_equal_eval_metrics(finger):
    a = df.read_acap(str(finger / "a.h5"))
    truth = a["positions"].astype(np.float64)
    pred = truth + 0.01 * np.sin(np.arange(truth.size)).reshape(truth.shape)
    df.write_acap(str(finger / "p.h5"), a["template"]["vertices"], a["template"]["faces"], positions=pred)
    erms = json.loads(tool("eval-metrics", str(finger / "p.h5"), str(finger / "a.h5"), "--json", "-"))["erms"]
    assert df.erms(pred.astype(np.float32).astype(np.float64), truth) == pytest.approx(erms, rel=1e-5)
    assert df.vertex_error(truth, truth).max() == 0


def test_file_kinds_read_back(finger, tmp_path):
    a = df.read_acap(str(finger / "a.h5"))
    out = str(tmp_path / "w.h5")
    df.write_acap(out, a["template"]["vertices"], a["template"]["faces"], positions=a["positions"].astype(np.float64),
                  features=a["features"])
    b = df.read_acap(out)
    assert np.array_equal(b["positions"], a["positions"])
    assert np.array_equal(b["features"], a["features"])
    assert np.array_equal(b["template"]["faces"], a["template"]["faces"])
    lo, hi = df.normalization(a["features"])
    assert np.allclose(b["normalization"]["min"], lo) and np.allclose(b["normalization"]["max"], hi)
    x = df.normalize(a["features"], lo, hi)
    assert np.abs(x).max() <= 0.95 + 1e-12
    assert np.allclose(df.normalize(x, lo, hi, inverse=True), a["features"], atol=1e-12)
    tool("h5check", "-q", out)  # a valid acap file


def test_skeleton_components_and_models(tmp_path):
    tool("synth-actions", "-q", "--classes", "walk,squat", "--per-class", "3", "--frames", "10", "-o", str(tmp_path / "s.h5"))
    s = df.read_skeleton(str(tmp_path / "s.h5"))
    assert s["poses"].shape[1:] == (20, 3) and s["class_names"] == ["walk", "squat"]
    tool("synth-meshseq", "-q", "--kind", "bumps", "--frames", "20", "--resolution", "5", "--seed", "2", "-o", str(tmp_path / "b.h5"))
    tool("obj2acap", "-q", str(tmp_path / "b.h5"), "-o", str(tmp_path / "d.h5"))
    tool("train-msae", "-q", "--kz", "2,2", "--iterations", "5", str(tmp_path / "d.h5"), "-o", str(tmp_path / "m.h5"))
    tool("extract-components", "-q", str(tmp_path / "m.h5"), str(tmp_path / "d.h5"), "-o", str(tmp_path / "c.h5"))
    c = df.read_components(str(tmp_path / "c.h5"))
    assert c["space"] == "acap" and len(c["levels"]) == 2 and c["levels"][0]["features"].shape[1:] == (36, 9)
    m = df.read_model_info(str(tmp_path / "m.h5"))
    assert m["kind"] == "msae-model" and m["config"]["iterations"] == 5
    assert m["log"].shape[1] == len(m["log_columns"].split())


def test_h5py_reads_zstd_after_import(finger):
    with h5py.File(str(finger / "a.h5"), "r") as f:
        raw = f["features/raw"][...]
    assert np.array_equal(raw, df.read_acap(str(finger / "a.h5"))["features"])


@pytest.mark.parametrize("bad,message", [
    (lambda v, f: (v[..., :2], f), "dimension 2 must be 3"),
    (lambda v, f: (v[0], f), "must have 3 dimensions"),
    (lambda v, f: (v.astype(np.float32), f), "must be a float64 array"),
    (lambda v, f: (np.asfortranarray(v), f), "C-contiguous"),
    (lambda v, f: (np.where(np.arange(v.size).reshape(v.shape) == 7, np.nan, v), f), "NaN"),
    (lambda v, f: (v, f + v.shape[1]), "out of range"),
    (lambda v, f: (v, f.astype(np.float64)), "integer"),
])
def test_bad_arrays_raise_value_error(finger, bad, message):
    a = df.read_acap(str(finger / "a.h5"))
    v, f = bad(a["positions"].astype(np.float64), a["template"]["faces"])
    with pytest.raises(ValueError, match=message):
        df.acap_features(v, f)


def test_bad_files_raise_with_the_path(tmp_path):
    with pytest.raises((ValueError, OSError), match="nope.h5"):
        df.read_acap(str(tmp_path / "nope.h5"))
    with pytest.raises(ValueError, match="reference"):
        df.acap_features(np.zeros((2, 3, 3)), np.array([[0, 1, 2]]), reference=5)


def test_models_run_as_the_tools(tmp_path):
    """msae_reconstruct equals recon-msae; actgan_generate equals gen-actgan with the same seed."""
    tool("synth-meshseq", "-q", "--kind", "bumps", "--frames", "20", "--resolution", "5", "--seed", "2", "-o", str(tmp_path / "b.h5"))
    tool("obj2acap", "-q", str(tmp_path / "b.h5"), "-o", str(tmp_path / "d.h5"))
    tool("train-msae", "-q", "--kz", "2,2", "--iterations", "5", str(tmp_path / "d.h5"), "-o", str(tmp_path / "m.h5"))
    tool("recon-msae", "-q", "--part", "all", str(tmp_path / "m.h5"), str(tmp_path / "d.h5"), "-o", str(tmp_path / "r.h5"))
    d = df.read_acap(str(tmp_path / "d.h5"))
    recon, codes = df.msae_reconstruct(str(tmp_path / "m.h5"), d["features"])
    r = df.read_acap(str(tmp_path / "r.h5"))
    lo, hi = r["normalization"]["min"], r["normalization"]["max"]
    assert np.abs(df.normalize(recon, lo, hi) - r["normalized"]).max() < 1e-5  # float network
    assert len(codes) == 1 + 2 and codes[0].shape == (20, 2)
    tool("synth-actions", "-q", "--classes", "walk,squat", "--per-class", "4", "--frames", "12", "--seed", "1", "-o", str(tmp_path / "raw.h5"))
    tool("skel2h5", "-q", str(tmp_path / "raw.h5"), "--length", "8", "--clip-stride", "4", "--test-fraction", "0.25", "--seed", "2", "-o", str(tmp_path / "clips.h5"))
    tool("train-actgan", "-q", "--noise", "3", "--latent", "2", "--hidden", "6", "--fc", "8", "--batch", "4", "--pretrain-batch", "8",
         "--pretrain-iterations", "3", "--iterations", "3", "--seed", "3", str(tmp_path / "clips.h5"), "-o", str(tmp_path / "a.h5"))
    tool("gen-actgan", "-q", "--count", "2", "--seed", "5", str(tmp_path / "a.h5"), "-o", str(tmp_path / "g.h5"))
    g = df.actgan_generate(str(tmp_path / "a.h5"), count=2, seed=5)
    s = df.read_skeleton(str(tmp_path / "g.h5"))
    assert len(g["names"]) == 4 and g["raw_poses"].shape == g["poses"].shape
    assert np.array_equal(g["poses"].reshape(s["poses"].shape), s["poses"])


def test_bdlstm_generate_equals_gen_bdlstm(tmp_path):
    tool("synth-meshseq", "-q", "--frames", "24", "--resolution", "3", "--periods", "2", "-o", str(tmp_path / "f.h5"))
    tool("obj2acap", "-q", str(tmp_path / "f.h5"), "-o", str(tmp_path / "d.h5"))
    tool("train-bdlstm", "-q", "--window", "6", "--batch", "2", "--latent", "4", "--hidden", "6", "--lstm-layers", "1",
         "--iterations", "5", "--seed", "3", str(tmp_path / "d.h5"), "-o", str(tmp_path / "m.h5"))
    tool("gen-bdlstm", "-q", "--seed", "4", "--from", "5", "--initial", "2", "--length", "4", "--samples", "2",
         str(tmp_path / "m.h5"), str(tmp_path / "d.h5"), "-o", str(tmp_path / "g.h5"))
    g = df.bdlstm_generate(str(tmp_path / "m.h5"), str(tmp_path / "d.h5"), ["5"], initial=2, length=4, samples=2, seed=4)
    t = df.read_acap(str(tmp_path / "g.h5"))
    lo, hi = t["normalization"]["min"], t["normalization"]["max"]
    assert np.array_equal(df.normalize(g["features"], lo, hi).astype(np.float32), t["normalized"])
    assert np.array_equal(g["source"], t["source"]) and g["sequence_names"] == t["sequence_names"]


def test_write_skeleton_reads_back(tmp_path):
    tool("synth-actions", "-q", "--classes", "walk,kick", "--per-class", "2", "--frames", "6", "-o", str(tmp_path / "s.h5"))
    s = df.read_skeleton(str(tmp_path / "s.h5"))
    out = str(tmp_path / "w.h5")
    df.write_skeleton(out, s["raw_poses"].astype(np.float64), list(s["offsets"]), list(s["labels"]), s["class_names"],
                      list(s["parents"]), s["joint_names"], s["frame_rate"])
    w = df.read_skeleton(out)
    assert np.array_equal(w["poses"], s["raw_poses"]) and w["class_names"] == s["class_names"]
    tool("h5check", "-q", out)
    with pytest.raises(ValueError, match="offsets"):
        df.write_skeleton(out, s["raw_poses"].astype(np.float64), [0, 3], [0], s["class_names"], list(s["parents"]),
                          s["joint_names"])


def test_sted_and_mmd(finger):
    a = df.read_acap(str(finger / "a.h5"))
    truth = a["positions"].astype(np.float64)
    pred = truth + 0.01 * np.cos(np.arange(truth.size)).reshape(truth.shape)
    df.write_acap(str(finger / "q.h5"), a["template"]["vertices"], a["template"]["faces"], positions=pred)
    printed = tool("eval-metrics", str(finger / "q.h5"), str(finger / "a.h5"))  # STED: translation-free
    line = [l for l in printed.splitlines() if l.strip().startswith("STED")][0].split()
    s = df.sted(pred.astype(np.float32).astype(np.float64), truth, a["template"]["faces"])
    assert s["spatial"] == pytest.approx(float(line[2]), rel=1e-5)
    assert df.sted(truth, truth, a["template"]["faces"])["spatial"] == 0
    rng = np.random.default_rng(1)
    x, y = rng.normal(size=(30, 4)), rng.normal(size=(30, 4)) + 2
    assert df.mmd(x, y)[0] > df.mmd(x, rng.normal(size=(30, 4)))[0]


def test_erms_aligns_each_part_as_eval_metrics(finger, tmp_path):
    a = df.read_acap(str(finger / "a.h5"))
    v, f = a["positions"].astype(np.float64), a["template"]["faces"]
    V = v.shape[1]
    two = np.ascontiguousarray(np.concatenate([v, v + [3.0, 0, 0]], axis=1))  # two fingers side by side
    faces = np.concatenate([f, f + V])
    pred = two.copy()
    pred[:, V:] += [0.2, -0.1, 0.3]  # the second part moved: no error once each part is aligned
    df.write_acap(str(tmp_path / "t.h5"), two[0], faces, positions=two)
    df.write_acap(str(tmp_path / "p.h5"), two[0], faces, positions=pred)
    erms = json.loads(tool("eval-metrics", str(tmp_path / "p.h5"), str(tmp_path / "t.h5"), "--json", "-"))["erms"]
    assert df.erms(pred, two, faces) == pytest.approx(erms, abs=1e-4)
    assert df.erms(pred, two, faces) < 1e-3 < df.erms(pred, two)


def two_grids(tmp_path, parts):
    """Frames of `parts` separate 4 x 4 grids bending, as obj2acap's features."""
    verts, faces, frames = [], [], []
    for p in range(parts):
        base = len(verts)
        verts += [(3.0 * p + 0.5 * i, 0.5 * j, 0.0) for j in range(4) for i in range(4)]
        for j in range(3):
            for i in range(3):
                a = base + 4 * j + i
                faces += [(a, a + 1, a + 5), (a, a + 5, a + 4)]
    for f in range(12):
        x = np.array(verts, dtype=np.float64)
        for p in range(parts):
            rows = slice(16 * p, 16 * p + 16)
            x[rows, 2] = 0.2 * np.sin(0.5 * f + p + x[rows, 0]) * x[rows, 1]
        frames.append(x)
    df.write_acap(str(tmp_path / "raw.h5"), np.array(verts), np.array(faces, dtype=np.int32),
                  positions=np.array(frames))
    tool("obj2acap", "-q", str(tmp_path / "raw.h5"), "-o", str(tmp_path / "data.h5"))
    return tmp_path / "data.h5"


@pytest.mark.parametrize("parts", [1, 2])
def test_msae_resume_refuses_unbridged_distances_on_separate_parts(tmp_path, parts):
    """A checkpoint written before stop 78 (/geodesic@method heat: other parts at the diameter)
    resumes on a mesh of one part, where the distances agree, and is refused on two parts."""
    data = two_grids(tmp_path, parts)
    ck = tmp_path / "ck.h5"
    tool("train-msae", "-q", "--iterations", "10", "--kz", "2,2", "--batch", "4", str(data), "-o", str(ck))
    with h5py.File(ck, "r") as f:
        assert f["/geodesic"].attrs["method"] in (b"heat-bridged", "heat-bridged")
    with h5py.File(ck, "r+") as f:
        f["/geodesic"].attrs.modify("method", "heat")
    run = subprocess.run([os.path.join(BIN, "train-msae"), "-q", "--iterations", "20", "--kz", "2,2", "--batch", "4",
                          "--resume", "--checkpoint", str(ck), str(data), "-o", str(tmp_path / "r.h5")],
                         capture_output=True, text=True)
    if parts == 1:
        assert run.returncode == 0, run.stderr
    else:
        assert run.returncode == 1
        assert "2 separate parts" in run.stderr and "remove it and train anew" in run.stderr
        assert not (tmp_path / "r.h5").exists()
