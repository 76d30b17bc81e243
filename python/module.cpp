// The `deformflow` Python module (pybind11): exact ACAP features and reconstruction on numpy
// arrays, the project's file kinds as dicts of arrays, and the metrics — the library's calls,
// not copies of them. Arrays come in as float64 / int C-contiguous (others are refused, not
// converted silently); long calls release the GIL. Importing it registers the zstd filter with
// the process's HDF5, so h5py opens the project's files too.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>  // mkdtemp
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "apps/gen_bdlstm.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "eval/mesh_metrics.h"
#include "eval/skeleton_metrics.h"
#include "geometry/acap_features.h"
#include "geometry/mesh_topology.h"
#include "geometry/reconstruction.h"
#include "io/acap_file.h"
#include "io/components_file.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/model_file.h"
#include "io/skeleton_file.h"
#include "io/zstd_filter.h"
#include "models/actgan/generate.h"
#include "models/bdlstm/generate.h"
#include "models/msae/model.h"

namespace py = pybind11;
using namespace df;

namespace {

using F64 = py::array_t<double, py::array::c_style>;
constexpr int kDims = geometry::kFeatureDims;

// An array argument checked for dtype, layout, shape and finiteness; ValueError naming it.
py::array_t<double, py::array::c_style> doubles(const py::array& a, const char* name,
                                                std::vector<py::ssize_t> shape) {
  if (!py::isinstance<py::array_t<double>>(a) || a.dtype().kind() != 'f' || a.itemsize() != 8)
    throw py::value_error(std::string(name) + " must be a float64 array (got " +
                          std::string(py::str(a.dtype())) + ")");
  if (a.ndim() != static_cast<py::ssize_t>(shape.size()))
    throw py::value_error(std::string(name) + " must have " + std::to_string(shape.size()) +
                          " dimensions, not " + std::to_string(a.ndim()));
  for (std::size_t d = 0; d < shape.size(); ++d)
    if (shape[d] >= 0 && a.shape(static_cast<py::ssize_t>(d)) != shape[d])
      throw py::value_error(std::string(name) + ": dimension " + std::to_string(d) + " must be " +
                            std::to_string(shape[d]) + ", not " +
                            std::to_string(a.shape(static_cast<py::ssize_t>(d))));
  if (!(a.flags() & py::array::c_style))
    throw py::value_error(std::string(name) + " must be C-contiguous (numpy.ascontiguousarray)");
  auto out = py::array_t<double, py::array::c_style>::ensure(a);
  const double* p = out.data();
  for (py::ssize_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(p[i]))
      throw py::value_error(std::string(name) + " holds a NaN or infinite value at flat index " +
                            std::to_string(i));
  return out;
}

Faces faces_of(const py::array& a, py::ssize_t vertices) {
  if (a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw py::value_error("faces must be an integer array");
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("faces must be [F, 3] triangles");
  auto f = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  Faces out(f.shape(0), 3);
  for (py::ssize_t i = 0; i < f.size(); ++i) {
    const auto v = f.data()[i];
    if (v < 0 || v >= vertices)
      throw py::value_error("faces: vertex " + std::to_string(v) + " is out of range (" +
                            std::to_string(vertices) + " vertices)");
    out.data()[i] = static_cast<int>(v);
  }
  return out;
}

Vertices vertices_of(const double* p, py::ssize_t V) {
  return Eigen::Map<const Vertices>(p, V, 3);
}

F64 array(std::vector<py::ssize_t> shape, const double* data) {
  F64 a(shape);
  std::copy(data, data + a.size(), a.mutable_data());
  return a;
}

template <class T>
py::array_t<T> array_of(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::dict mesh_dict(const Mesh& m) {
  py::dict d;
  d["vertices"] = array({m.vertices.rows(), 3}, m.vertices.data());
  py::array_t<std::int32_t> f({m.faces.rows(), Eigen::Index{3}});
  std::copy(m.faces.data(), m.faces.data() + m.faces.size(), f.mutable_data());
  d["faces"] = f;
  return d;
}

// Reconstruction of one or many frames [V, 9] / [F, V, 9], frames in parallel, the GIL released.
F64 solve_frames(const geometry::Reconstructor& rec, const py::array& features) {
  const int V = rec.n_vertices();
  const bool one = features.ndim() == 2;
  auto f =
      doubles(features, "features",
              one ? std::vector<py::ssize_t>{V, kDims} : std::vector<py::ssize_t>{-1, V, kDims});
  const py::ssize_t n = one ? 1 : f.shape(0);
  std::vector<double> out(static_cast<std::size_t>(n * V * 3));
  {
    py::gil_scoped_release free;
    tbb::parallel_for(py::ssize_t{0}, n, [&](py::ssize_t k) {
      const Vertices p = rec.solve(f.data() + k * V * kDims);
      std::copy(p.data(), p.data() + p.size(), out.data() + k * V * 3);
    });
  }
  return one ? array({V, 3}, out.data()) : array({n, V, 3}, out.data());
}

// ACAP features of meshes and the meshes back from them.
void bind_features(py::module_& m) {
  m.def(
      "acap_features",
      [](const py::array& verts, const py::array& faces, int reference, bool consistency) {
        auto v = doubles(verts, "verts", {-1, -1, 3});
        const py::ssize_t n = v.shape(0), V = v.shape(1);
        if (n == 0) throw py::value_error("verts has no frames");
        if (reference < 0 || reference >= n)
          throw py::value_error("reference " + std::to_string(reference) + " is not a frame (0.." +
                                std::to_string(n - 1) + ")");
        const Faces F = faces_of(faces, V);
        std::vector<double> out;
        {
          py::gil_scoped_release free;
          std::vector<Vertices> frames;
          for (py::ssize_t k = 0; k < n; ++k)
            frames.push_back(vertices_of(v.data() + k * V * 3, V));
          const geometry::AcapFeatureExtractor ex(frames[static_cast<std::size_t>(reference)], F);
          out = geometry::sequence_features(ex, frames, {}, consistency);
        }
        return array({n, V, kDims}, out.data());
      },
      py::arg("verts"), py::arg("faces"), py::arg("reference") = 0, py::arg("consistency") = true,
      "ACAP features [F, V, 9] of the frames verts [F, V, 3] (one sequence, in time order) on\n"
      "the triangles faces [T, 3], relative to frame `reference`: as obj2acap computes them\n"
      "(rotation logs made consistent across neighbours and with the previous frame; principal\n"
      "logs with consistency=False). Units: radians for the rotation, the stretch unitless.");

  py::class_<geometry::Reconstructor>(
      m, "Reconstructor", "Positions from ACAP features on one template, the system factored once.")
      .def(py::init([](const py::array& tmpl, const py::array& faces, int anchor,
                       const std::string& solver) {
             auto t = doubles(tmpl, "template", {-1, 3});
             if (solver != "gradients" && solver != "edges")
               throw py::value_error(
                   "solver must be 'gradients' (exact) or 'edges' (the papers' system)");
             const Faces F = faces_of(faces, t.shape(0));
             const Vertices V = vertices_of(t.data(), t.shape(0));
             py::gil_scoped_release free;
             return new geometry::Reconstructor(V, F, anchor,
                                                solver == "edges"
                                                    ? geometry::ReconstructionSolver::edges
                                                    : geometry::ReconstructionSolver::gradients);
           }),
           py::arg("template"), py::arg("faces"), py::arg("anchor") = 0,
           py::arg("solver") = "gradients",
           "template [V, 3] (the reference the features are relative to), faces [T, 3]; `anchor`: "
           "the\n"
           "vertex pinned at its template position (one per connected component); solver\n"
           "'gradients' (exact: features of a mesh give it back) or 'edges' (the papers' system).")
      .def("solve", &solve_frames, py::arg("features"),
           "Positions [V, 3] of features [V, 9], or [F, V, 3] of [F, V, 9] (frames in parallel).")
      .def_property_readonly("vertices", &geometry::Reconstructor::n_vertices)
      .def_property_readonly("factor_seconds", &geometry::Reconstructor::factor_seconds);

  m.def(
      "acap_reconstruct",
      [](const py::array& features, const py::array& tmpl, const py::array& faces, int anchor,
         const std::string& solver) {
        auto t = doubles(tmpl, "template", {-1, 3});
        const Faces F = faces_of(faces, t.shape(0));
        const geometry::Reconstructor rec(vertices_of(t.data(), t.shape(0)), F, anchor,
                                          solver == "edges"
                                              ? geometry::ReconstructionSolver::edges
                                              : geometry::ReconstructionSolver::gradients);
        return solve_frames(rec, features);
      },
      py::arg("features"), py::arg("template"), py::arg("faces"), py::arg("anchor") = 0,
      py::arg("solver") = "gradients",
      "Positions from features [V, 9] or [F, V, 9] on template [V, 3] (acap2obj's solve; for many\n"
      "calls on one template make a Reconstructor once).");
}

// The features' normalization (obj2acap's) both ways.
void bind_normalization(py::module_& m) {
  m.def(
      "normalization",
      [](const py::array& features, const std::string& mode) {
        auto f = doubles(features, "features", {-1, -1, kDims});
        if (mode != "group" && mode != "per-dim")
          throw py::value_error("mode must be 'group' or 'per-dim'");
        geometry::NormalizationBuilder b(mode == "group" ? NormalizationMode::group
                                                         : NormalizationMode::per_dim);
        b.add(f.data(), static_cast<std::size_t>(f.size() / kDims));
        const auto nz = b.finish();
        return py::make_tuple(array({kDims}, nz.min.data()), array({kDims}, nz.max.data()));
      },
      py::arg("features"), py::arg("mode") = "group",
      "(min[9], max[9]) that map features [F, V, 9] into [-0.95, 0.95] (obj2acap's --normalize:\n"
      "'group' shares one range per rotation and per stretch group, 'per-dim' one per number).");
  m.def(
      "normalize",
      [](const py::array& features, const py::array& lo, const py::array& hi, bool inverse) {
        auto f = doubles(features, "features", {-1, -1, kDims});
        auto a = doubles(lo, "min", {kDims}), b = doubles(hi, "max", {kDims});
        FeatureNormalization nz;
        std::copy(a.data(), a.data() + kDims, nz.min.begin());
        std::copy(b.data(), b.data() + kDims, nz.max.begin());
        F64 out({f.shape(0), f.shape(1), py::ssize_t{kDims}});
        for (py::ssize_t i = 0; i < f.size(); ++i) {
          const int d = static_cast<int>(i % kDims);
          out.mutable_data()[i] =
              inverse ? nz.denormalize(d, f.data()[i]) : nz.normalize(d, f.data()[i]);
        }
        return out;
      },
      py::arg("features"), py::arg("min"), py::arg("max"), py::arg("inverse") = false,
      "x_norm = -0.95 + 1.9 (x - min) / (max - min) per number of the 9 (inverse=True undoes it).");
}

// The papers' shape errors: E_rms and the per-vertex error.
void bind_shape_errors(py::module_& m) {
  m.def(
      "erms",
      [](const py::array& pred, const py::array& truth, const py::object& faces) {
        auto t = doubles(truth, "truth", {-1, -1, 3});
        auto p = doubles(pred, "pred", {t.shape(0), t.shape(1), 3});
        const py::ssize_t n = t.shape(0), V = t.shape(1);
        // the parts aligned one by one, as eval-metrics does (one part without faces)
        const eval::MeshParts parts =
            faces.is_none() ? eval::mesh_parts(Faces(0, 3), V)
                            : eval::mesh_parts(faces_of(faces.cast<py::array>(), V), V);
        double sum = 0;
        for (py::ssize_t k = 0; k < n; ++k) {
          const Vertices T = vertices_of(t.data() + k * V * 3, V);
          sum += eval::erms_share(vertices_of(p.data() + k * V * 3, V), T, parts);
        }
        return eval::erms_from_sum(sum, static_cast<double>(n), static_cast<double>(V));
      },
      py::arg("pred"), py::arg("truth"), py::arg("faces") = py::none(),
      "E_rms x 1000 (MSAE paper, Table 2) of pred against truth [F, V, 3]: each frame translated\n"
      "onto the truth's centroid — each connected part on its own when faces [T, 3] are given, as\n"
      "eval-metrics does — and both scaled so the truth fits the unit ball.");
  m.def(
      "vertex_error",
      [](const py::array& pred, const py::array& truth) {
        auto t = doubles(truth, "truth", {-1, -1, 3});
        auto p = doubles(pred, "pred", {t.shape(0), t.shape(1), 3});
        const py::ssize_t n = t.shape(0), V = t.shape(1);
        F64 out(std::vector<py::ssize_t>{n});
        for (py::ssize_t k = 0; k < n; ++k)
          out.mutable_data()[k] = eval::mean_vertex_error(vertices_of(p.data() + k * V * 3, V),
                                                          vertices_of(t.data() + k * V * 3, V));
        return out;
      },
      py::arg("pred"), py::arg("truth"),
      "Mean per-vertex distance per frame [F] (BD-LSTM paper, Tables 1-2; no alignment).");
}

// acap files into dicts of arrays.
void bind_acap_reader(py::module_& m) {
  m.def(
      "read_acap",
      [](const std::string& path) {
        const io::AcapReader r(path);
        const auto n = static_cast<py::ssize_t>(r.frames()),
                   V = static_cast<py::ssize_t>(r.vertices());
        py::dict d;
        d["template"] = mesh_dict(r.read_template());
        d["frame_names"] = r.frame_names();
        d["sequence_names"] = r.sequence_names();
        d["offsets"] = array_of(r.offsets(), {static_cast<py::ssize_t>(r.offsets().size())});
        if (r.has_positions()) {
          std::vector<float> p(static_cast<std::size_t>(n * V * 3));
          r.read_positions(0, static_cast<std::size_t>(n), p.data());
          d["positions"] = array_of(p, {n, V, 3});
        }
        if (r.has_raw()) {
          std::vector<double> f(static_cast<std::size_t>(n * V * kDims));
          r.read_raw(0, static_cast<std::size_t>(n), f.data());
          d["features"] = array({n, V, kDims}, f.data());
        }
        if (r.has_normalized()) {
          std::vector<float> f(static_cast<std::size_t>(n * V * kDims));
          r.read_normalized(0, static_cast<std::size_t>(n), f.data());
          d["normalized"] = array_of(f, {n, V, kDims});
        }
        if (r.has_normalization()) {
          const auto nz = r.normalization();
          d["normalization"] =
              py::dict(py::arg("min") = array({kDims}, nz.min.data()),
                       py::arg("max") = array({kDims}, nz.max.data()),
                       py::arg("mode") = nz.mode == NormalizationMode::group ? "group" : "per-dim");
        }
        if (r.has_source()) d["source"] = array_of(r.source(), {n});
        if (r.labelled()) {
          d["labels"] = array_of(r.labels(), {static_cast<py::ssize_t>(r.labels().size())});
          d["class_names"] = r.class_names();
        }
        d["history"] = r.history();
        return d;
      },
      py::arg("path"),
      "An acap file as a dict: template {vertices [V,3], faces [T,3]}, frame_names, "
      "sequence_names,\n"
      "offsets [S+1], and what it holds of positions [N,V,3] (float32), features [N,V,9] (raw,\n"
      "float64), normalized [N,V,9] (float32), normalization {min, max, mode}, source [N], labels\n"
      "and class_names, history.");
}

// acap files from arrays.
void bind_acap_writer(py::module_& m) {
  m.def(
      "write_acap",
      [](const std::string& path, const py::array& tmpl, const py::array& faces,
         const py::object& positions, const py::object& features) {
        auto t = doubles(tmpl, "template", {-1, 3});
        const py::ssize_t V = t.shape(0);
        Mesh mesh;
        mesh.vertices = vertices_of(t.data(), V);
        mesh.faces = faces_of(faces, V);
        if (positions.is_none() && features.is_none())
          throw py::value_error("give positions, features or both");
        py::ssize_t n = -1;
        F64 p, f;
        if (!positions.is_none())
          p = doubles(positions.cast<py::array>(), "positions", {-1, V, 3}), n = p.shape(0);
        if (!features.is_none())
          f = doubles(features.cast<py::array>(), "features", {n, V, kDims}), n = f.shape(0);
        AtomicOutput out(path, AtomicOutput::Kind::file, true);
        {
          io::AcapWriter w(out.temp_path(), path);
          w.write_template(mesh);
          std::vector<std::string> names;
          for (py::ssize_t k = 0; k < n; ++k) names.push_back(std::to_string(k));
          w.write_frame_names(names);
          w.write_sequences({0, n}, {"python"});
          const auto N = static_cast<std::size_t>(n), nv = static_cast<std::size_t>(V);
          if (!positions.is_none()) {
            std::vector<float> q(p.data(), p.data() + p.size());
            w.write_positions(N, nv, q.data());
          }
          if (!features.is_none()) {
            geometry::NormalizationBuilder b(NormalizationMode::group);
            b.add(f.data(), N * nv);
            const auto nz = b.finish();
            w.write_normalization(nz);
            w.create_raw(N, nv);
            w.write_raw_rows(0, N, f.data());
            std::vector<float> x(static_cast<std::size_t>(f.size()));
            for (std::size_t i = 0; i < x.size(); ++i)
              x[i] = static_cast<float>(nz.normalize(static_cast<int>(i % kDims), f.data()[i]));
            w.write_normalized(N, nv, x.data());
          }
          w.close();
        }
        out.commit();
      },
      py::arg("path"), py::arg("template"), py::arg("faces"), py::arg("positions") = py::none(),
      py::arg("features") = py::none(),
      "Writes an acap file (one sequence) from template [V,3], faces [T,3] and positions [N,V,3]\n"
      "and/or raw features [N,V,9] (normalized as obj2acap does, 'group' mode), atomically.");
}

// components files.
void bind_component_files(py::module_& m) {
  m.def(
      "read_components",
      [](const std::string& path) {
        const io::Components c = io::read_components(path);
        const auto V = c.tmpl.vertices.rows();
        py::dict d;
        d["space"] = c.space;
        d["template"] = mesh_dict(c.tmpl);
        py::list levels;
        for (const auto& L : c.levels) {
          py::dict l;
          std::vector<float> f(L.features.data(), L.features.data() + L.features.size());
          l["features"] =
              array_of(f, {L.features.rows(), V, static_cast<py::ssize_t>(c.per_vertex())});
          l["strength"] = array_of(L.strength, {static_cast<py::ssize_t>(L.strength.size())});
          l["center"] = array_of(L.center, {static_cast<py::ssize_t>(L.center.size())});
          l["kept"] = array_of(L.kept, {static_cast<py::ssize_t>(L.kept.size())});
          levels.append(l);
        }
        d["levels"] = levels;
        d["normalization"] = py::dict(py::arg("min") = array({kDims}, c.normalization.min.data()),
                                      py::arg("max") = array({kDims}, c.normalization.max.data()));
        if (c.space == "positions") d["mean"] = array({V, 3}, c.mean.data());
        d["model"] = c.model;
        return d;
      },
      py::arg("path"),
      "A components file: space ('acap' or 'positions'), template, levels (each: features\n"
      "[K,V,9] normalized ACAP features or [K,V,3] displacements, strength, center, kept),\n"
      "normalization, mean (positions only), model.");
}

// skeleton files both ways.
void bind_skeleton_files(py::module_& m) {
  m.def(
      "read_skeleton",
      [](const std::string& path) {
        const io::SkeletonFile s = io::read_skeleton_file(path);
        py::dict d;
        d["poses"] = array_of(s.poses, {static_cast<py::ssize_t>(s.frames),
                                        static_cast<py::ssize_t>(s.joints), s.dims});
        d["raw_poses"] = array_of(s.raw_poses(), {static_cast<py::ssize_t>(s.frames),
                                                  static_cast<py::ssize_t>(s.joints), s.dims});
        d["offsets"] = array_of(s.offsets, {static_cast<py::ssize_t>(s.offsets.size())});
        d["labels"] = array_of(s.labels, {static_cast<py::ssize_t>(s.labels.size())});
        d["class_names"] = s.class_names;
        d["sequence_names"] = s.sequence_names;
        d["parents"] = array_of(s.parents, {static_cast<py::ssize_t>(s.parents.size())});
        d["joint_names"] = s.joint_names;
        d["frame_rate"] = s.frame_rate;
        return d;
      },
      py::arg("path"),
      "A skeleton file: poses [T,J,D] as stored (normalized when the file is), raw_poses (the\n"
      "normalization undone, root-centred), offsets [S+1], labels [S], class_names,\n"
      "sequence_names, parents [J], joint_names, frame_rate.");

  m.def(
      "write_skeleton",
      [](const std::string& path, const py::array& poses, const std::vector<std::int64_t>& offsets,
         const std::vector<std::int32_t>& labels, const std::vector<std::string>& class_names,
         const std::vector<std::int32_t>& parents, const std::vector<std::string>& joint_names,
         double frame_rate) {
        const auto J = static_cast<py::ssize_t>(parents.size());
        auto p = doubles(poses, "poses", {-1, J, 3});
        io::SkeletonFile s;
        s.frames = static_cast<std::size_t>(p.shape(0));
        s.joints = static_cast<std::size_t>(J);
        s.poses.assign(p.data(), p.data() + p.size());
        s.offsets = offsets;
        if (s.offsets.size() < 2 || s.offsets.front() != 0 ||
            s.offsets.back() != static_cast<std::int64_t>(s.frames) ||
            !std::is_sorted(s.offsets.begin(), s.offsets.end()))
          throw py::value_error("offsets must run from 0 to the number of frames, non-decreasing");
        s.labels = labels;
        s.class_names = class_names;
        s.parents = parents;
        s.joint_names = joint_names;
        s.frame_rate = frame_rate;
        s.sequence_names.assign(s.sequences(), "");
        if (s.labels.size() != s.sequences()) throw py::value_error("labels: one per sequence");
        for (auto l : s.labels)
          if (l < 0 || static_cast<std::size_t>(l) >= class_names.size())
            throw py::value_error("labels: a class index out of range");
        if (joint_names.size() != parents.size())
          throw py::value_error("joint_names: one per joint");
        AtomicOutput out(path, AtomicOutput::Kind::file, true);
        {
          h5::File f(out.temp_path(), h5::File::Mode::create, path);
          io::write_header(f, "skeleton");
          io::write_skeleton_data(f, s);
        }
        out.commit();
      },
      py::arg("path"), py::arg("poses"), py::arg("offsets"), py::arg("labels"),
      py::arg("class_names"), py::arg("parents"), py::arg("joint_names"),
      py::arg("frame_rate") = 30.0,
      "Writes a skeleton file (raw coordinates, no normalization) that skel2h5, render-mesh and\n"
      "export-gltf read: poses [T, J, 3] of all sequences concatenated, offsets [S+1], labels [S]\n"
      "(class indices), class_names, parents [J] (-1 for a root), joint_names [J], frame_rate.");
}

// Any model file's kind and settings.
void bind_model_info(py::module_& m) {
  m.def(
      "read_model_info",
      [](const std::string& path) {
        h5::File f(path, h5::File::Mode::read);
        py::dict d;
        d["kind"] = io::declared_kind(f);
        py::dict config;
        const std::string group = io::model_layout::config;
        if (f.exists(group))
          for (const auto& a : f.attr_names(group)) {
            try {
              config[a.c_str()] = f.attr_string(group, a);
            } catch (const std::exception&) {
              try {
                config[a.c_str()] = f.attr_int(group, a);
              } catch (const std::exception&) {
                config[a.c_str()] = f.attr_doubles(group, a);
              }
            }
          }
        d["config"] = config;
        const auto log = io::read_training_log(f);
        if (!log.rows.empty()) {
          const auto cols =
              static_cast<py::ssize_t>(std::count(log.columns.begin(), log.columns.end(), ' ') + 1);
          d["log"] = array_of(log.rows, {static_cast<py::ssize_t>(log.rows.size()) / cols, cols});
          d["log_columns"] = log.columns;
        }
        d["history"] = io::read_history(f);
        return d;
      },
      py::arg("path"),
      "A model file's (bdlstm-model, msae-model, actgan-model) kind, its settings (/config) and\n"
      "its training log [rows, columns] with the columns' names.");
}

// MSAE's reconstruction.
void bind_msae(py::module_& m) {
  m.def(
      "msae_reconstruct",
      [](const std::string& model, const py::array& features, int levels) {
        const models::MsaeModel mm = models::load_msae_model(model);
        const auto V = static_cast<py::ssize_t>(mm.tmpl.vertices.rows());
        auto f = doubles(features, "features", {-1, V, kDims});
        const py::ssize_t n = f.shape(0);
        const int L = levels > 0 ? levels : mm.config.levels();
        if (L > mm.config.levels())
          throw py::value_error("levels: the model has " + std::to_string(mm.config.levels()));
        nn::Matrix<float> x(n, V * kDims);
        for (py::ssize_t i = 0; i < f.size(); ++i)
          x.data()[i] = static_cast<float>(
              mm.normalization.normalize(static_cast<int>(i % kDims), f.data()[i]));
        std::vector<nn::Matrix<float>> codes;
        nn::Matrix<float> y;
        {
          py::gil_scoped_release free;
          y = mm.net->reconstruct(x, L, &codes);
        }
        F64 out({n, V, py::ssize_t{kDims}});
        for (py::ssize_t i = 0; i < out.size(); ++i)
          out.mutable_data()[i] =
              mm.normalization.denormalize(static_cast<int>(i % kDims), y.data()[i]);
        py::list z;
        for (const auto& c : codes) {
          std::vector<float> v(c.data(), c.data() + c.size());
          z.append(array_of(v, {c.rows(), c.cols()}));
        }
        return py::make_tuple(out, z);
      },
      py::arg("model"), py::arg("features"), py::arg("levels") = 0,
      "An MSAE model (train-msae) on raw features [N, V, 9] of its template: (the reconstruction\n"
      "[N, V, 9] through the first `levels` levels (0: all), raw; every block's codes [N, kz]),\n"
      "as recon-msae computes them.");
}

// ActGAN's generation.
void bind_actgan(py::module_& m) {
  m.def(
      "actgan_generate",
      [](const std::string& model, const std::vector<std::string>& classes, const std::string& mix,
         int count, int length, std::uint64_t seed) {
        const models::ActganModel am = models::load_actgan_model(model);
        models::ActganGenerateOptions o;
        o.classes = classes;
        o.mix = mix;
        o.count = count;
        const int T = length > 0 ? length : am.length;
        if (T < 1 || count < 1) throw py::value_error("count and length must be positive");
        std::vector<std::string> names;
        const auto y = models::label_rows(am, o, names);
        io::SkeletonFile sk;
        std::vector<float> latents;
        {
          py::gil_scoped_release free;
          Rng rng(seed, 0);
          models::generate_actions(am, y, T, rng, sk.poses, latents);
        }
        sk.joints = am.joint_names.size();
        sk.dims = 3;
        sk.frames = names.size() * static_cast<std::size_t>(T);
        sk.normalization = am.normalization;
        const auto n = static_cast<py::ssize_t>(names.size()),
                   J = static_cast<py::ssize_t>(sk.joints);
        py::dict d;
        d["poses"] = array_of(sk.poses, {n, T, J, 3});
        d["raw_poses"] = array_of(sk.raw_poses(), {n, T, J, 3});
        d["latents"] = array_of(
            latents,
            {n, T, static_cast<py::ssize_t>(latents.size() / static_cast<std::size_t>(n * T))});
        d["names"] = names;
        d["joint_names"] = am.joint_names;
        d["parents"] = array_of(am.parents, {J});
        d["frame_rate"] = am.frame_rate;
        return d;
      },
      py::arg("model"), py::arg("classes") = std::vector<std::string>{}, py::arg("mix") = "",
      py::arg("count") = 10, py::arg("length") = 0, py::arg("seed") = 0,
      "Sequences from an ActGAN model (train-actgan), as gen-actgan makes them with the same "
      "seed:\n"
      "`count` per class of `classes` (all when empty) or of the mixture `mix` "
      "('walk:0.5,wave:0.5');\n"
      "`length` frames (0: the training clips'). A dict: poses [n, T, J, 3] in the model's "
      "normalized\n"
      "coordinates, raw_poses (normalization undone, root-centred), latents [n, T, Z], names,\n"
      "joint_names, parents, frame_rate.");
}

// BD-LSTM's prediction.
void bind_bdlstm(py::module_& m) {
  m.def(
      "bdlstm_generate",
      [](const std::string& model, const std::string& data, const std::vector<std::string>& from,
         int initial, int length, int samples, std::uint64_t seed) {
        if (from.empty())
          throw py::value_error("from: give at least one frame (an index, or SEQUENCE:K)");
        models::BdlstmGenerateOptions o;
        o.model = model;
        o.data = data;
        o.from = from;
        o.initial = initial;
        o.length = length;
        o.samples = samples;
        CommonOptions common;
        common.quiet = true;
        common.force = true;
        common.seed = seed;
        // gen-bdlstm's own code, through a temporary file: the same numbers as the tool
        std::string pattern =
            (std::filesystem::temp_directory_path() / "deformflow-bdlstm-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw py::value_error("cannot make a temporary folder");
        const std::filesystem::path dir = pattern, tmp = dir / "generated.h5";
        struct Remove {
          std::filesystem::path p;
          ~Remove() {
            std::error_code ec;
            std::filesystem::remove_all(p, ec);
          }
        } remove{dir};  // also when generation fails
        o.output = tmp.string();
        {
          py::gil_scoped_release free;
          apps::generate_bdlstm(o, common);
        }
        py::dict d;
        {
          const io::AcapReader r(o.output);
          const auto n = static_cast<py::ssize_t>(r.frames()),
                     V = static_cast<py::ssize_t>(r.vertices());
          F64 raw({n, V, py::ssize_t{kDims}});
          r.read_features(0, static_cast<std::size_t>(n), raw.mutable_data());
          d["features"] = raw;
          d["offsets"] = array_of(r.offsets(), {static_cast<py::ssize_t>(r.offsets().size())});
          d["sequence_names"] = r.sequence_names();
          if (r.has_source()) d["source"] = array_of(r.source(), {n});
          if (r.has_steps()) d["steps"] = array_of(r.steps(), {n});
          d["template"] = mesh_dict(r.read_template());
        }
        return d;
      },
      py::arg("model"), py::arg("data"), py::arg("from"), py::arg("initial") = 1,
      py::arg("length") = 15, py::arg("samples") = 1, py::arg("seed") = 0,
      "Frames predicted by a BD-LSTM model (train-bdlstm) as gen-bdlstm makes them: from each\n"
      "frame of `from` (global indices of the acap file `data`, or 'SEQUENCE:K' strings) with\n"
      "`initial` given frames, `length` future frames, `samples` per case (random initial states,\n"
      "`seed`). A dict: features [N, V, 9] raw (acap_reconstruct makes meshes), offsets and\n"
      "sequence_names (one sequence per case and sample), source (the data frame of each), steps\n"
      "(frames after the last given one), template.");
}

// The sequence and distribution measures: STED and MMD.
void bind_sequence_measures(py::module_& m) {
  m.def(
      "sted",
      [](const py::array& pred, const py::array& truth, const py::array& faces, int rings,
         double dt) {
        auto t = doubles(truth, "truth", {-1, -1, 3});
        auto p = doubles(pred, "pred", {t.shape(0), t.shape(1), 3});
        const py::ssize_t n = t.shape(0), V = t.shape(1);
        const Faces F = faces_of(faces, V);
        const auto topo = geometry::mesh_topology(F, static_cast<int>(V));
        const auto hoods = eval::edge_neighbourhoods(topo, rings);
        double spatial = 0, temporal = 0;
        for (py::ssize_t k = 0; k < n; ++k)
          spatial += eval::sted_spatial(vertices_of(p.data() + k * V * 3, V),
                                        vertices_of(t.data() + k * V * 3, V), topo, hoods);
        for (py::ssize_t k = 0; k + 1 < n; ++k)
          temporal += eval::sted_temporal(vertices_of(p.data() + k * V * 3, V),
                                          vertices_of(p.data() + (k + 1) * V * 3, V),
                                          vertices_of(t.data() + k * V * 3, V),
                                          vertices_of(t.data() + (k + 1) * V * 3, V), topo, dt);
        return py::dict(py::arg("spatial") = spatial / static_cast<double>(n),
                        py::arg("temporal") = n > 1 ? temporal / static_cast<double>(n - 1) : 0.0);
      },
      py::arg("pred"), py::arg("truth"), py::arg("faces"), py::arg("rings") = 1,
      py::arg("dt") = 1.0,
      "STED (Vasa & Skala 2011) of pred against truth [F, V, 3] on faces [T, 3]: {'spatial': the "
      "mean\n"
      "over frames of the relative edge-length deviation's weighted spread in `rings`-ring\n"
      "neighbourhoods, 'temporal': the mean over consecutive pairs of the relative speed\n"
      "difference (frame interval dt)}; eval-metrics' STED without its alignment.");

  m.def(
      "mmd",
      [](const py::array& x, const py::array& y) {
        auto a = doubles(x, "x", {-1, -1});
        auto b = doubles(y, "y", {-1, a.shape(1)});
        if (a.shape(0) < 2 || b.shape(0) < 2)
          throw py::value_error("mmd needs at least 2 samples on each side");
        const eval::RowMatrixF X =
            Eigen::Map<
                const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                a.data(), a.shape(0), a.shape(1))
                .cast<float>();
        const eval::RowMatrixF Y =
            Eigen::Map<
                const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                b.data(), b.shape(0), b.shape(1))
                .cast<float>();
        eval::MmdResult r;
        {
          py::gil_scoped_release free;
          r = eval::mmd2_max(X, Y);
        }
        return py::make_tuple(r.mmd2, r.bandwidth);
      },
      py::arg("x"), py::arg("y"),
      "(MMD_u^2, bandwidth): the unbiased squared MMD between the rows of x [m, D] and y [n, D]\n"
      "with a Gaussian kernel, maximised over bandwidths 1e-4 ... 1e9 (ActGAN's MMD_avg / MMD_seq\n"
      "when the rows are poses / flattened sequences), as eval-metrics computes it (float).");
}

}  // namespace

PYBIND11_MODULE(deformflow, m) {
  m.doc() =
      "deformflow: exact ACAP deformation features (Gao et al. 2019) and their reconstruction on\n"
      "numpy arrays, the deformflow file kinds (acap, components, skeleton, models) as dicts of\n"
      "arrays, and the papers' error measures. The same code as the command-line tools\n"
      "(obj2acap, acap2obj, eval-metrics): equal results.\n"
      "\n"
      "Arrays: float64 C-contiguous (numpy.ascontiguousarray(x, dtype=numpy.float64)); vertices\n"
      "[F, V, 3] or [V, 3]; faces [T, 3] integer; features [F, V, 9] per vertex the rotation's\n"
      "log (L01, L02, L12 of the skew matrix) then the stretch's upper triangle (S00, S01, S02,\n"
      "S11, S12, S22). Importing the module registers the zstd filter with HDF5, so h5py reads\n"
      "deformflow files in the same process.";
  h5::initialize();
  h5::register_zstd_filter();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IOError& e) {
      PyErr_SetString(PyExc_OSError, e.message().c_str());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_ValueError, e.message().c_str());
    }
  });

  m.def(
      "set_threads",
      [](int n) {
        static std::unique_ptr<tbb::global_control> limit;
        if (n < 0) throw py::value_error("threads must be >= 0");
        limit.reset();
        if (n > 0)
          limit = std::make_unique<tbb::global_control>(
              tbb::global_control::max_allowed_parallelism, n);
      },
      py::arg("threads"),
      "Worker threads of the module's parallel calls (0 = all cores, the default). Results do not\n"
      "depend on it.");

  bind_features(m);
  bind_normalization(m);
  bind_shape_errors(m);
  bind_acap_reader(m);
  bind_acap_writer(m);
  bind_component_files(m);
  bind_skeleton_files(m);
  bind_model_info(m);
  bind_msae(m);
  bind_actgan(m);
  bind_bdlstm(m);
  bind_sequence_measures(m);
}
