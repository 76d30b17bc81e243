#include "apps/edit_shape.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/word_lines.h"
#include "geometry/acap_features.h"
#include "geometry/reconstruction.h"
#include "io/acap_file.h"
#include "io/components_file.h"

namespace df::apps {
namespace {

constexpr int kDims = geometry::kFeatureDims;
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The components the edit may move, as raw ACAP feature directions D_k = raw(C_k) − raw(X_r).
struct Subspace {
  RowMatrixXd directions;           // [K_sel, 9V]
  std::vector<int> selected;        // index into all components (levels in order)
  std::vector<std::int32_t> level;  // [K] level of every component of the file
};

Subspace select_directions(const io::Components& c, const EditShapeOptions& opt) {
  for (int l : opt.levels)
    if (l < 0 || l >= static_cast<int>(c.levels.size()))
      throw UsageError(fmt::format("--levels: the components file has levels 0..{}, not {}",
                                   c.levels.size() - 1, l));
  Subspace s;
  const auto ref = geometry::identity_features(&c.normalization);
  std::vector<const float*> rows;
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    const auto& L = c.levels[l];
    const bool wanted = opt.levels.empty() || std::find(opt.levels.begin(), opt.levels.end(),
                                                        static_cast<int>(l)) != opt.levels.end();
    for (Eigen::Index k = 0; k < L.features.rows(); ++k) {
      if (wanted && (L.kept[static_cast<std::size_t>(k)] || opt.include_pruned)) {
        s.selected.push_back(static_cast<int>(s.level.size()));
        rows.push_back(L.features.row(k).data());
      }
      s.level.push_back(static_cast<std::int32_t>(l));
    }
  }
  if (rows.empty())
    throw InvalidInput(
        "no component to edit with (the chosen levels' components were all pruned: "
        "--include-pruned uses them)",
        opt.components);
  const int D = c.per_vertex();
  const auto n = static_cast<Eigen::Index>(D) * c.tmpl.vertices.rows();
  s.directions.resize(static_cast<Eigen::Index>(rows.size()), n);
  const auto& nz = c.normalization;
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (Eigen::Index j = 0; j < n; ++j) {
      const int d = static_cast<int>(j % D);
      s.directions(static_cast<Eigen::Index>(k), j) =
          c.space == "positions"
              ? static_cast<double>(rows[k][j])  // displacements as they are
              : nz.denormalize(d, rows[k][j]) - nz.denormalize(d, ref[static_cast<std::size_t>(d)]);
    }
  return s;
}

// Where the edit starts: the shape's positions and raw features (none for position
// components), the weights it was made with, and its history.
struct Start {
  Vertices positions;
  std::vector<double> features;  // [9V]
  std::vector<double> weights;   // [K] every component's
  std::vector<int> handles;      // the vertices the edit it came from held
  std::string history;
};

Start read_start(const EditShapeOptions& opt, const io::Components& c, const Subspace& s) {
  const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
  const bool positions_space = c.space == "positions";
  Start st;
  st.weights.assign(s.level.size(), 0.0);
  if (opt.from.empty()) {
    st.positions = positions_space ? c.mean : c.tmpl.vertices;
    const auto id = geometry::identity_features();
    for (std::size_t i = 0; i < V; ++i) st.features.insert(st.features.end(), id.begin(), id.end());
    return st;
  }
  const io::AcapReader r(opt.from);
  r.require_template(c.tmpl, "the components file");
  if (opt.from_frame < 0 || static_cast<std::size_t>(opt.from_frame) >= r.frames())
    throw UsageError(fmt::format("--from-frame {}: {} has frames 0..{}", opt.from_frame, opt.from,
                                 r.frames() - 1));
  const auto frame = static_cast<std::size_t>(opt.from_frame);
  st.history = r.history();
  if (positions_space && !r.has_positions())
    throw InvalidInput("has no positions to edit with position components", opt.from);
  if (!positions_space) {
    st.features.resize(V * kDims);
    r.read_features(frame, 1, st.features.data());
  }
  st.positions =
      r.has_positions()
          ? r.read_frame_positions(frame)
          : geometry::Reconstructor(c.tmpl.vertices, c.tmpl.faces).solve(st.features.data());
  if (r.has_edit()) {
    const auto e = r.read_edit();
    st.handles.assign(e.handles.begin(), e.handles.end());
    if (e.weights.size() == s.level.size() && e.level == s.level)
      st.weights = e.weights;
    else
      log::warn(
          "{} was edited with another components file ({}): this edit starts from zero weights on "
          "top of it",
          opt.from, e.components);
  }
  return st;
}

// Coarse then fine: the handles of the edit the shape came from stay where they are, unless this
// edit moves them or --release-handles frees them. (Without them a detail edit with one handle
// is free to turn the whole shape about it: the coarse step's placement is lost.)
void keep_earlier_handles(Handles& h, const Start& start, const EditShapeOptions& opt) {
  if (opt.release_handles || start.handles.empty()) return;
  std::set<int> seen(h.vertices.begin(), h.vertices.end());
  std::size_t kept = 0;
  for (int v : start.handles) {
    if (v < 0 || v >= start.positions.rows() || !seen.insert(v).second) continue;
    h.vertices.push_back(v);
    h.targets.emplace_back(start.positions.row(v));
    ++kept;
  }
  if (kept)
    log::info("holding the {} handle(s) of {}'s edit where they are (--release-handles frees them)",
              kept, opt.from);
}

// --sample N handles with their targets in a frame of --to.
void sample_handles(Handles& h, const EditShapeOptions& opt, const io::Components& c) {
  if (opt.sample <= 0) return;
  if (opt.to.empty())
    throw UsageError("--sample needs --to (the shape whose positions are the targets)");
  const io::AcapReader r(opt.to);
  r.require_template(c.tmpl, "the components file");
  if (!r.has_positions()) throw InvalidInput("has no positions to take targets from", opt.to);
  if (opt.to_frame < 0 || static_cast<std::size_t>(opt.to_frame) >= r.frames())
    throw UsageError(
        fmt::format("--to-frame {}: {} has frames 0..{}", opt.to_frame, opt.to, r.frames() - 1));
  const auto V = c.tmpl.vertices.rows();
  if (opt.sample > V)
    throw UsageError(fmt::format("--sample {}: the template has {} vertices", opt.sample, V));
  const Vertices p = r.read_frame_positions(static_cast<std::size_t>(opt.to_frame));
  std::set<int> seen(h.vertices.begin(), h.vertices.end());
  for (int v : furthest_point_sample(c.tmpl.vertices, opt.sample)) {
    if (!seen.insert(v).second) continue;  // a handle of the file wins
    h.vertices.push_back(v);
    h.targets.emplace_back(p.row(v));
  }
}

// The handles with their targets (held vertices at their start positions).
void place_handles(Handles& h, const std::vector<int>& fixed, const Vertices& start,
                   bool relative) {
  if (relative)
    for (std::size_t k = 0; k < h.vertices.size(); ++k)
      if (h.targets[k].allFinite()) h.targets[k] += start.row(h.vertices[k]);
  std::set<int> seen(h.vertices.begin(), h.vertices.end());
  for (int v : fixed) {
    if (v < 0 || v >= start.rows())
      throw UsageError(fmt::format(
          "--fixed: vertex {} does not exist (the template has {} vertices)", v, start.rows()));
    if (!seen.insert(v).second)
      throw UsageError(fmt::format("--fixed: vertex {} is held twice", v));
    h.vertices.push_back(v);
    h.targets.emplace_back(Eigen::RowVector3d::Constant(std::nan("")));
  }
  for (std::size_t k = 0; k < h.vertices.size(); ++k)
    if (!h.targets[k].allFinite()) h.targets[k] = start.row(h.vertices[k]);
}

// Per handle, how far the shape the weights give with nothing held (one anchor, then the best
// translation) is from its target.
std::vector<double> handle_residual(const io::Components& c, const std::vector<double>& features,
                                    const Handles& h) {
  const geometry::Reconstructor free(c.tmpl.vertices, c.tmpl.faces, h.vertices.front());
  const Vertices p = free.solve(features.data());
  Eigen::RowVector3d shift = Eigen::RowVector3d::Zero();
  for (std::size_t k = 0; k < h.vertices.size(); ++k) shift += h.targets[k] - p.row(h.vertices[k]);
  shift /= static_cast<double>(h.vertices.size());
  std::vector<double> r;
  for (std::size_t k = 0; k < h.vertices.size(); ++k)
    r.push_back((p.row(h.vertices[k]) + shift - h.targets[k]).norm());
  return r;
}

// The files an edit reads (never to be overwritten by its output).
std::vector<std::filesystem::path> edit_inputs(const EditShapeOptions& opt) {
  std::vector<std::filesystem::path> inputs{opt.components};
  for (const auto& p : {opt.handles, opt.from, opt.to})
    if (!p.empty()) inputs.emplace_back(p);
  return inputs;
}

void write_edit(const EditShapeOptions& opt, const io::Components& c,
                const std::vector<std::string>& histories, const geometry::SubspaceEditResult& res,
                io::ShapeEdit record, bool force) {
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, force, edit_inputs(opt));
  {
    io::AcapWriter f(out.temp_path(), opt.output, histories);
    const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
    f.write_template(c.tmpl);
    f.write_normalization(c.normalization);
    f.write_frame_names({"edit"});
    f.write_sequences({0, 1}, {"edit"});
    if (!opt.to.empty())
      f.write_source({opt.to_frame}, opt.to, "edit-shape");  // eval-metrics pairs them
    const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> p = res.positions.cast<float>();
    f.write_positions(1, V, p.data());
    if (!res.features.empty()) {  // (position components: positions only)
      f.create_raw(1, V);
      f.write_raw_rows(0, 1, res.features.data());
      std::vector<float> x(res.features.size());
      for (std::size_t j = 0; j < x.size(); ++j)
        x[j] = static_cast<float>(
            c.normalization.normalize(static_cast<int>(j % kDims), res.features[j]));
      f.write_normalized(1, V, x.data());
    }
    f.write_edit(record);
    f.close();
  }
  out.commit();
}

// The ACAP edit: Levenberg-Marquardt on the weights (geometry/subspace_edit), the handles held.
geometry::SubspaceEditResult solve_acap(const io::Components& c, const Subspace& sub,
                                        const Eigen::VectorXd& w0, const Start& start,
                                        const Handles& handles,
                                        const geometry::SubspaceEditOptions& opt) {
  // f⁰: the start's features less the part the solved weights already give.
  Eigen::VectorXd base = Eigen::Map<const Eigen::VectorXd>(
      start.features.data(), static_cast<Eigen::Index>(start.features.size()));
  base -= sub.directions.transpose() * w0;
  Vertices pinned = start.positions;
  for (std::size_t k = 0; k < handles.vertices.size(); ++k)
    pinned.row(handles.vertices[k]) = handles.targets[k];
  const geometry::SubspaceEditor editor(
      c.tmpl.vertices, c.tmpl.faces, handles.vertices, sub.directions,
      std::vector<double>(base.data(), base.data() + base.size()));
  log::debug("{} components, {} handles; system factored in {:.3f} s", sub.selected.size(),
             handles.vertices.size(), editor.factor_seconds());
  return editor.edit(w0, pinned, opt,
                     [](int it, double e) { log::debug("step {}: energy {:.6g}", it, e); });
}

// Position components (SPLOCS): p = p⁰ + Σ w_k C_k + t, linear, with a free translation t (as
// the ACAP edit's positions are free up to the handles, and E_rms aligns by translation: the
// components, fitted to centred shapes, should not have to carry where the shape stands); the
// weights minimise Σ_h ‖p_h − t_h‖² / (H d²) + λ‖w‖² (d: the template's diagonal), one solve.
geometry::SubspaceEditResult fit_positions(const Subspace& sub, const Eigen::VectorXd& w0,
                                           const Vertices& start, const Handles& h, double l2,
                                           double diagonal) {
  const auto K = sub.directions.rows(), H = static_cast<Eigen::Index>(h.vertices.size());
  const Eigen::VectorXd flat =
      Eigen::Map<const Eigen::VectorXd>(start.data(), start.size());  // row-major V x 3
  const Eigen::VectorXd base = flat - sub.directions.transpose() * w0;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * H, K + 3);  // the weights, then t
  Eigen::VectorXd b(3 * H);
  for (Eigen::Index k = 0; k < H; ++k)
    for (int a = 0; a < 3; ++a) {
      const Eigen::Index j = 3 * h.vertices[static_cast<std::size_t>(k)] + a;
      A.row(3 * k + a).head(K) = sub.directions.col(j).transpose();
      A(3 * k + a, K + a) = 1;
      b[3 * k + a] = h.targets[static_cast<std::size_t>(k)][a] - base[j];
    }
  const double s = static_cast<double>(H) * diagonal * diagonal;
  const auto energy = [&](const Eigen::VectorXd& x) {
    return (A * x - b).squaredNorm() / s + l2 * x.head(K).squaredNorm();
  };
  Eigen::MatrixXd N = A.transpose() * A / s;
  N.diagonal().head(K).array() += l2;
  N.diagonal().array() += 1e-14 * (1 + N.diagonal().cwiseAbs().maxCoeff());
  const Eigen::VectorXd x = N.ldlt().solve(A.transpose() * b / s);
  geometry::SubspaceEditResult res;
  res.weights = x.head(K);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(K + 3);
  x0.head(K) = w0;
  res.energy = {energy(x0), energy(x)};
  res.iterations = 1;
  res.converged = true;
  const Eigen::VectorXd p = base + sub.directions.transpose() * res.weights;
  res.positions =
      Eigen::Map<const Vertices>(p.data(), start.rows(), 3).rowwise() + x.tail(3).transpose();
  return res;
}

}  // namespace

std::vector<int> furthest_point_sample(const Vertices& v, int n) {
  std::vector<int> out;
  if (n <= 0 || v.rows() == 0) return out;
  Eigen::VectorXd d = Eigen::VectorXd::Constant(v.rows(), std::numeric_limits<double>::infinity());
  int next = 0;
  while (static_cast<int>(out.size()) < n) {
    out.push_back(next);
    d = d.cwiseMin((v.rowwise() - v.row(next)).rowwise().squaredNorm());
    Eigen::Index far = 0;
    d.maxCoeff(&far);
    next = static_cast<int>(far);
  }
  return out;
}

Handles read_handles(const std::string& path, int n_vertices) {
  Handles h;
  std::set<int> seen;
  for (const auto& [number, words] : read_word_lines(path, "the handle file")) {
    const auto where = fmt::format("{}:{}", path, number);
    if (words.size() != 1 && words.size() != 4)
      throw InvalidInput(
          "expected `vertex x y z` or `vertex`, got " + std::to_string(words.size()) + " words",
          where);
    std::size_t used = 0;
    long v = -1;
    try {
      v = std::stol(words[0], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != words[0].size())
      throw InvalidInput(fmt::format("'{}' is not a vertex index", words[0]), where);
    if (v < 0 || v >= n_vertices)
      throw InvalidInput(
          fmt::format("vertex {} does not exist (the template has {} vertices)", v, n_vertices),
          where);
    if (!seen.insert(static_cast<int>(v)).second)
      throw InvalidInput(fmt::format("vertex {} is held twice", v), where);
    Eigen::RowVector3d t = Eigen::RowVector3d::Constant(std::nan(""));
    for (std::size_t a = 1; a < words.size(); ++a) {
      try {
        t[static_cast<Eigen::Index>(a - 1)] = std::stod(words[a], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != words[a].size() || !std::isfinite(t[static_cast<Eigen::Index>(a - 1)]))
        throw InvalidInput(fmt::format("the target '{}' is not a finite number", words[a]), where);
    }
    h.vertices.push_back(static_cast<int>(v));
    h.targets.push_back(t);
  }
  return h;
}

void edit_shape(const EditShapeOptions& opt, const CommonOptions& common) {
  const OutputClaim claim = claim_output(opt.output, common.force, edit_inputs(opt));
  const io::Components c = io::read_components(opt.components);
  const int V = static_cast<int>(c.tmpl.vertices.rows());
  Handles handles = opt.handles.empty() ? Handles{} : read_handles(opt.handles, V);
  const Subspace sub = select_directions(c, opt);
  const Start start = read_start(opt, c, sub);
  place_handles(handles, opt.fixed, start.positions, opt.relative);  // the file's, then --fixed
  keep_earlier_handles(handles, start, opt);
  sample_handles(handles, opt, c);
  if (handles.vertices.empty())
    throw UsageError(
        "no handles: give --handles FILE (lines `vertex x y z`), --sample N --to SHAPE or --fixed");

  Eigen::VectorXd w0(static_cast<Eigen::Index>(sub.selected.size()));
  for (std::size_t k = 0; k < sub.selected.size(); ++k)
    w0[static_cast<Eigen::Index>(k)] = start.weights[sub.selected[k]];
  const double diagonal =
      (c.tmpl.vertices.colwise().maxCoeff() - c.tmpl.vertices.colwise().minCoeff()).norm();
  if (c.space == "positions" && opt.solver.l1 > 0)
    throw UsageError(
        "--l1 is for ACAP components; position components (SPLOCS) are fitted linearly (--l2)");
  const auto res = c.space == "positions"
                       ? fit_positions(sub, w0, start.positions, handles, opt.solver.l2, diagonal)
                       : solve_acap(c, sub, w0, start, handles, opt.solver);

  io::ShapeEdit record;
  record.components = opt.components;
  record.l2 = opt.solver.l2;
  record.iterations = res.iterations;
  record.converged = res.converged;
  record.weights = start.weights;
  for (std::size_t k = 0; k < sub.selected.size(); ++k)
    record.weights[sub.selected[k]] = res.weights[static_cast<Eigen::Index>(k)];
  record.level = sub.level;
  record.edited.assign(sub.level.size(), 0);
  for (int k : sub.selected) record.edited[static_cast<std::size_t>(k)] = 1;
  record.handles.assign(handles.vertices.begin(), handles.vertices.end());
  for (const auto& t : handles.targets)
    record.targets.insert(record.targets.end(), {t[0], t[1], t[2]});
  if (c.space == "positions")
    for (std::size_t k = 0; k < handles.vertices.size(); ++k)
      record.residual.push_back(
          (res.positions.row(handles.vertices[k]) - handles.targets[k]).norm());
  else
    record.residual = handle_residual(c, res.features, handles);
  record.energy = res.energy;
  std::vector<std::string> histories{c.history};
  if (!opt.from.empty()) histories.push_back(start.history);
  write_edit(opt, c, histories, res, record, common.force);

  if (!res.converged)
    log::warn("the solver stopped after {} steps without converging (--iterations)",
              res.iterations);
  log::info(
      "{} components, {} handles: energy {:.4g} -> {:.4g} in {} steps; the weights alone reach the "
      "handles within {:.3g} x the template's diagonal{}; wrote {}",
      sub.selected.size(), handles.vertices.size(), res.energy.front(), res.energy.back(),
      res.iterations, *std::max_element(record.residual.begin(), record.residual.end()) / diagonal,
      c.space == "positions" ? " (position components: the handles are fitted, not held)" : "",
      opt.output);
}

}  // namespace df::apps
