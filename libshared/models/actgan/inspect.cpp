#include "models/actgan/inspect.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/error.h"
#include "core/progress.h"
#include "io/skeleton_file.h"
#include "nn/adam.h"

namespace df::models {
namespace {

constexpr Eigen::Index kFitBatch = 256;

// The poses asked about and the training poses they are set against, in the model's
// coordinates, with their model class and sequence.
struct Poses {
  nn::Matrix<float> x;
  std::vector<int> label;
  std::vector<std::size_t> sequence;
};

struct PoseSets {
  Poses queries, references;
};

PoseSets pose_sets(const ActganModel& m, const io::SkeletonFile& s,
                   const ActganInspectOptions& opt) {
  const std::string& path = opt.input;
  if (s.joints * 3 != static_cast<std::size_t>(m.config.pose) || s.dims != 3)
    throw InvalidInput(fmt::format("{} joints x {}: the model was trained on {} values per pose",
                                   s.joints, s.dims, m.config.pose),
                       path);
  std::vector<int> to_model(s.class_names.size(), -1);
  for (std::size_t c = 0; c < s.class_names.size(); ++c) {
    const auto it = std::find(m.class_names.begin(), m.class_names.end(), s.class_names[c]);
    if (it != m.class_names.end()) to_model[c] = static_cast<int>(it - m.class_names.begin());
  }
  const bool has_test = std::count(s.test.begin(), s.test.end(), 1) > 0;
  const bool split = has_test && !opt.all;
  const bool by_subject = !opt.subjects.empty();
  if (by_subject && s.subjects.size() != s.sequences())
    throw InvalidInput(
        "--subjects: the file records no subjects (skel2h5 takes them from the recordings' names "
        "or --labels)",
        path);
  auto chosen = [&](std::size_t q) {
    return std::find(opt.subjects.begin(), opt.subjects.end(), s.subjects[q]) != opt.subjects.end();
  };
  auto in_test = [&](std::size_t q) { return has_test && s.test[q] == 1; };
  const std::vector<float> poses = io::poses_normalized_as(s, m.normalization);
  const auto P = static_cast<Eigen::Index>(s.frame_size());
  auto take = [&](Poses& into, auto keep) {
    std::size_t n = 0;
    for (std::size_t q = 0; q < s.sequences(); ++q)
      if (keep(q) && to_model[static_cast<std::size_t>(s.labels[q])] >= 0) n += s.length(q);
    into.x.resize(static_cast<Eigen::Index>(n), P);
    Eigen::Index r = 0;
    for (std::size_t q = 0; q < s.sequences(); ++q) {
      const int c = to_model[static_cast<std::size_t>(s.labels[q])];
      if (!keep(q) || c < 0) continue;
      for (auto f = s.offsets[q]; f < s.offsets[q + 1]; ++f, ++r) {
        into.x.row(r) = Eigen::Map<const Eigen::RowVectorXf>(
            poses.data() + static_cast<std::size_t>(f) * static_cast<std::size_t>(P), P);
        into.label.push_back(c);
        into.sequence.push_back(q);
      }
    }
  };
  PoseSets out;
  if (by_subject) {
    take(out.queries, chosen);
    take(out.references, [&](std::size_t q) { return !chosen(q) && !in_test(q); });
  } else {
    take(out.queries, [&](std::size_t q) { return !split || in_test(q); });
    take(out.references, [&](std::size_t q) { return !split || !in_test(q); });
  }
  if (out.queries.x.rows() == 0)
    throw InvalidInput(
        "no pose of a class the model knows" + std::string(by_subject ? " of those subjects"
                                                           : split    ? " in the test part"
                                                                      : ""),
        path);
  return out;
}

// RMS over coordinates (model coordinates) and mean per-joint distance in the data's
// root-centred units (each coordinate's difference times its std and the scale).
PoseError pose_error(const ActganModel& m, const nn::Matrix<float>& a, const nn::Matrix<float>& b) {
  PoseError e;
  if (a.rows() == 0) return e;
  const auto& nz = m.normalization;
  double joints = 0;
  for (Eigen::Index r = 0; r < a.rows(); ++r)
    for (Eigen::Index j = 0; j < a.cols() / 3; ++j) {
      double d2 = 0;
      for (Eigen::Index k = 0; k < 3; ++k) {
        const Eigen::Index c = 3 * j + k;
        const double unit = nz.present() ? nz.std[static_cast<std::size_t>(c)] * nz.scale : 1.0;
        d2 += std::pow(static_cast<double>(a(r, c) - b(r, c)) * unit, 2);
      }
      joints += std::sqrt(d2);
    }
  e.rms = std::sqrt(static_cast<double>((a - b).squaredNorm()) / static_cast<double>(a.size()));
  e.joint_distance = joints / static_cast<double>(a.rows() * (a.cols() / 3));
  return e;
}

// Each query's nearest reference pose of the same class from another sequence; a query without
// one keeps itself (error 0) and is counted in *alone, which the report prints.
nn::Matrix<float> nearest_references(const PoseSets& ps, std::size_t* alone) {
  const Poses &q = ps.queries, &r = ps.references;
  nn::Matrix<float> out = q.x;
  const Eigen::VectorXf r_norm = r.x.rowwise().squaredNorm();
  for (Eigen::Index i = 0; i < q.x.rows(); ++i) {
    float best = std::numeric_limits<float>::max();
    bool found = false;
    for (Eigen::Index j = 0; j < r.x.rows(); ++j) {
      const auto jj = static_cast<std::size_t>(j), ii = static_cast<std::size_t>(i);
      if (r.label[jj] != q.label[ii] || r.sequence[jj] == q.sequence[ii]) continue;
      const float d = r_norm[j] - 2 * r.x.row(j).dot(q.x.row(i));
      if (d < best) best = d, found = true, out.row(i) = r.x.row(j);
    }
    if (!found) ++*alone;
  }
  return out;
}

}  // namespace

nn::Matrix<float> fit_latent_codes(const ActganModel& m, const nn::Matrix<float>& poses,
                                   const std::vector<int>& labels, int steps, double lr) {
  if (m.config.generator == Generator::pose)
    throw Error("internal: fit_latent_codes on the direct-pose baseline");
  nn::Matrix<float> recon(poses.rows(), poses.cols());
  const Eigen::Index Z = m.config.latent, C = m.config.classes;
  std::optional<Progress> progress;  // none for a plain decode (0 steps)
  if (steps > 0) progress.emplace("fitting latent codes", static_cast<std::size_t>(poses.rows()));
  for (Eigen::Index r0 = 0; r0 < poses.rows(); r0 += kFitBatch) {
    const Eigen::Index n = std::min(kFitBatch, poses.rows() - r0);
    nn::Matrix<float> y = nn::Matrix<float>::Zero(n, C);
    for (Eigen::Index i = 0; i < n; ++i) y(i, labels[static_cast<std::size_t>(r0 + i)]) = 1;
    const nn::Matrix<float> x = poses.middleRows(r0, n);
    nn::Vector<float> h = nn::Vector<float>::Zero(n * Z), grad(n * Z);
    nn::AdamOptions ao;
    ao.lr = lr;
    ao.schedule = nn::AdamOptions::Schedule::exponential;
    ao.decay_rate = 0.1;
    ao.decay_steps = std::max(1, steps);
    nn::Adam<float> adam(static_cast<std::size_t>(n * Z), ao);
    for (int it = 0; it <= steps; ++it) {
      nn::Tape<float> tape;
      const auto p = m.gen->store().bind_constant(tape);
      const nn::Var<float> hv = tape.variable(Eigen::Map<const nn::Matrix<float>>(h.data(), n, Z));
      const nn::Var<float> out = m.gen->decode(p, hv, tape.constant(y));
      if (it == steps) {
        recon.middleRows(r0, n) = out.value();
        break;
      }
      tape.backward(nn::sum_squares(nn::sub(tape.constant(x), out)));
      grad = Eigen::Map<const nn::Vector<float>>(hv.grad().data(), n * Z);
      adam.step(h, grad);
    }
    if (progress) progress->advance(static_cast<std::size_t>(n));
  }
  if (progress) progress->finish();
  return recon;
}

DecoderReach decoder_reach(const ActganModel& m, const io::SkeletonFile& s,
                           const ActganInspectOptions& opt) {
  if (m.config.generator == Generator::pose)
    throw InvalidInput(
        "the direct-pose baseline (--generator pose) has no frame decoder to inspect", opt.model);
  const PoseSets ps = pose_sets(m, s, opt);
  DecoderReach d;
  d.part = !opt.subjects.empty()                                         ? "subjects"
           : opt.all || std::count(s.test.begin(), s.test.end(), 1) == 0 ? "all"
                                                                         : "test";
  d.poses = static_cast<std::size_t>(ps.queries.x.rows());
  d.training_poses = static_cast<std::size_t>(ps.references.x.rows());
  const nn::Matrix<float> fitted =
      fit_latent_codes(m, ps.queries.x, ps.queries.label, opt.steps, opt.lr);
  const nn::Matrix<float> start = fit_latent_codes(m, ps.queries.x, ps.queries.label, 0, opt.lr);
  const nn::Matrix<float> mean = ps.references.x.colwise().mean().replicate(ps.queries.x.rows(), 1);
  const nn::Matrix<float> nearest = nearest_references(ps, &d.without_reference);
  d.fitted = pose_error(m, fitted, ps.queries.x);
  d.start = pose_error(m, start, ps.queries.x);
  d.mean_pose = pose_error(m, mean, ps.queries.x);
  d.nearest = pose_error(m, nearest, ps.queries.x);
  for (std::size_t c = 0; c < m.class_names.size(); ++c) {
    std::vector<Eigen::Index> rows;
    for (std::size_t i = 0; i < ps.queries.label.size(); ++i)
      if (ps.queries.label[i] == static_cast<int>(c)) rows.push_back(static_cast<Eigen::Index>(i));
    if (rows.empty()) continue;
    auto pick = [&](const nn::Matrix<float>& a) {
      nn::Matrix<float> out(static_cast<Eigen::Index>(rows.size()), a.cols());
      for (std::size_t k = 0; k < rows.size(); ++k)
        out.row(static_cast<Eigen::Index>(k)) = a.row(rows[k]);
      return out;
    };
    d.classes.push_back(m.class_names[c]);
    d.poses_by_class.push_back(rows.size());
    d.fitted_by_class.push_back(pose_error(m, pick(fitted), pick(ps.queries.x)));
    d.nearest_by_class.push_back(pose_error(m, pick(nearest), pick(ps.queries.x)));
  }
  return d;
}

}  // namespace df::models
