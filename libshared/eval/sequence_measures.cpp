#include "eval/sequence_measures.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

#include "core/error.h"
#include "eval/shape_error.h"

namespace df::eval {

using convert::FrameSet;
using convert::normalized_features;
using convert::reconstruct;

SequenceShape shape_of(const FrameSet& pred) {
  SequenceShape sh{
      geometry::mesh_topology(pred.tmpl.faces, static_cast<int>(pred.tmpl.vertices.rows())), {}};
  sh.parts = mesh_parts(sh.topo);
  return sh;
}

FeatureChange feature_change_of(const FrameSet& pred, int change_span) {
  FeatureChange fc;
  if (!pred.raw.rows()) return fc;
  const auto span = static_cast<std::int64_t>(change_span);
  std::vector<double> sum;
  std::vector<int> count;
  // Each frame is normalized once; the last span + 1 stay in a ring.
  std::vector<Eigen::VectorXd> ring(static_cast<std::size_t>(span + 1));
  auto slot = [&](std::int64_t t) -> Eigen::VectorXd& {
    return ring[static_cast<std::size_t>(t % (span + 1))];
  };
  for (std::size_t s = 0; s + 1 < pred.offsets.size(); ++s) {
    const std::int64_t begin = pred.offsets[s], n = pred.offsets[s + 1] - begin;
    for (std::int64_t t = 0; t < n; ++t) {
      slot(t) = normalized_features(pred, static_cast<std::size_t>(begin + t), pred.normalization);
      if (t < span) continue;
      const auto i = static_cast<std::size_t>(t - span);
      const double c = feature_change(slot(t - span), slot(t));
      if (sum.size() <= i) sum.resize(i + 1), count.resize(i + 1);
      sum[i] += c, count[i] += 1, fc.total += c, ++fc.n;
    }
  }
  for (std::size_t t = 0; t < sum.size(); ++t) fc.by_index.push_back(sum[t] / count[t]);
  return fc;
}

// Which PRED frame is measured against which TRUTH frame: /frames/source, else frame by frame.
FramePairs pair_frames(const FrameSet& pred, const FrameSet& truth) {
  if (truth.tmpl.vertices.rows() != pred.tmpl.vertices.rows() ||
      truth.tmpl.faces != pred.tmpl.faces)
    throw InvalidInput(
        fmt::format("its template ({} vertices) differs from {}'s ({} vertices)",
                    truth.tmpl.vertices.rows(), pred.path, pred.tmpl.vertices.rows()),
        truth.path);
  FramePairs pairs;
  if (!pred.source.empty()) {
    for (std::size_t i = 0; i < pred.size(); ++i)
      if (pred.source[i] >= 0) {
        if (static_cast<std::size_t>(pred.source[i]) >= truth.size())
          throw InvalidInput(
              fmt::format("frame {} pairs with frame {} of the truth, which has {} frames", i,
                          pred.source[i], truth.size()),
              pred.path + "/frames/source");
        pairs.emplace_back(i, static_cast<std::size_t>(pred.source[i]));
      }
  } else {
    if (pred.size() != truth.size())
      throw InvalidInput(fmt::format("has {} frames and no /frames/source; the truth has {}",
                                     pred.size(), truth.size()),
                         pred.path);
    for (std::size_t i = 0; i < pred.size(); ++i) pairs.emplace_back(i, i);
  }
  if (pairs.empty()) throw InvalidInput("no frame pairs with the truth", pred.path);
  return pairs;
}

PairMeasures measure_pairs(FrameSet& pred, FrameSet& truth, const SequenceShape& sh,
                           const FramePairs& pairs, const PairOptions& opt) {
  PairMeasures pm;
  reconstruct(pred);
  reconstruct(truth);
  const auto& T = truth.tmpl.vertices;
  pm.diag = (T.colwise().maxCoeff() - T.colwise().minCoeff()).norm();
  const auto hoods = edge_neighbourhoods(sh.topo, opt.sted_rings);
  const auto& nz = truth.normalization ? truth.normalization : pred.normalization;
  const bool features = pred.raw.rows() && truth.raw.rows();
  pm.results.resize(pairs.size());
  std::vector<Vertices> aligned(pairs.size());
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
    const auto [i, j] = pairs[k];
    const Vertices& gt = truth.positions[j];
    aligned[k] = align_parts(pred.positions[i], gt, sh.parts, opt.align);
    PairResult& r = pm.results[k];
    r.error = mean_vertex_error(aligned[k], gt);
    r.unit_ball = unit_ball_squared_error(aligned[k], gt);
    r.sted_s = sted_spatial(aligned[k], gt, sh.topo, hoods);
    if (features)
      r.rse = relative_squared_error(normalized_features(truth, j, nz),
                                     normalized_features(pred, i, nz));
  });
  for (std::size_t k = 0; k + 1 < pairs.size(); ++k) {
    const auto [i0, j0] = pairs[k];
    const auto [i1, j1] = pairs[k + 1];
    const auto s =
        std::upper_bound(pred.offsets.begin(), pred.offsets.end(), static_cast<std::int64_t>(i0));
    if (i1 != i0 + 1 || static_cast<std::int64_t>(i1) >= *s) continue;
    pm.sted_t += sted_temporal(aligned[k], aligned[k + 1], truth.positions[j0], truth.positions[j1],
                               sh.topo, opt.sted_dt);
    ++pm.sted_t_n;
  }
  return pm;
}

SampleGroups sample_groups(const FrameSet& pred) {
  SampleGroups groups;
  for (std::size_t s = 0; s < pred.sequences.size(); ++s) {
    const auto tilde = pred.sequences[s].rfind('~');
    if (tilde != std::string::npos) groups[pred.sequences[s].substr(0, tilde)].push_back(s);
  }
  std::erase_if(groups, [](const auto& g) { return g.second.size() < 2; });
  return groups;
}

std::pair<double, std::size_t> sample_spread(FrameSet& pred, const SampleGroups& groups,
                                             const SequenceShape& sh) {
  double spread = 0;
  std::size_t n = 0;
  if (groups.empty()) return {spread, n};
  reconstruct(pred);
  for (const auto& [name, seqs] : groups) {
    const auto len = pred.offsets[seqs[0] + 1] - pred.offsets[seqs[0]];
    for (auto s : seqs)
      if (pred.offsets[s + 1] - pred.offsets[s] != len)
        throw InvalidInput("samples of '" + name + "' have different lengths", pred.path);
    for (std::int64_t t = 0; t < len; ++t) {
      const auto i0 = static_cast<std::size_t>(pred.offsets[seqs[0]] + t);
      if (!pred.step.empty() && pred.step[i0] == 0) continue;
      for (std::size_t a = 0; a < seqs.size(); ++a)
        for (std::size_t b = a + 1; b < seqs.size(); ++b) {
          const auto& pa = pred.positions[static_cast<std::size_t>(pred.offsets[seqs[a]] + t)];
          const auto& pb = pred.positions[static_cast<std::size_t>(pred.offsets[seqs[b]] + t)];
          spread += mean_vertex_error(align_parts(pb, pa, sh.parts), pa);
          ++n;
        }
    }
  }
  return {spread, n};
}

Totals totals_of(const FrameSet& pred, const FramePairs& pairs,
                 const std::vector<PairResult>& results) {
  Totals t;
  t.skip_given =
      std::any_of(pred.step.begin(), pred.step.end(), [](std::int32_t s) { return s > 0; });
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    const int step =
        pred.step.empty() ? static_cast<int>(pairs[k].first) : pred.step[pairs[k].first];
    t.by_step[step].first += r.error, t.by_step[step].second += 1;
    if (t.skip_given && step == 0) continue;
    ++t.counted;
    t.err += r.error, t.ub += r.unit_ball, t.sted_s += r.sted_s;
    if (r.rse >= 0) t.rse_max = std::max(t.rse_max, r.rse), t.rse_mean += r.rse, ++t.rse_n;
  }
  return t;
}

SamplesVsTruth samples_vs_truth(const FrameSet& pred, const SampleGroups& groups,
                                const FramePairs& pairs, const std::vector<PairResult>& results,
                                bool skip_given) {
  SamplesVsTruth v;
  if (groups.empty()) return v;
  std::vector<double> seq_sum(pred.sequences.size(), 0.0);
  std::vector<std::size_t> seq_n(pred.sequences.size(), 0);
  for (std::size_t k = 0; k < results.size(); ++k) {
    const std::size_t i = pairs[k].first;
    if (skip_given && pred.step[i] == 0) continue;
    const auto s = static_cast<std::size_t>(
        std::upper_bound(pred.offsets.begin(), pred.offsets.end(), static_cast<std::int64_t>(i)) -
        pred.offsets.begin() - 1);
    seq_sum[s] += results[k].error, ++seq_n[s];
  }
  for (const auto& [name, seqs] : groups) {
    std::vector<double> e;
    for (auto s : seqs)
      if (seq_n[s]) e.push_back(seq_sum[s] / static_cast<double>(seq_n[s]));
    if (e.empty()) continue;
    v.best += *std::min_element(e.begin(), e.end());
    v.worst += *std::max_element(e.begin(), e.end());
    v.mean += std::accumulate(e.begin(), e.end(), 0.0) / static_cast<double>(e.size());
    ++v.cases;
  }
  if (v.cases) v.best /= v.cases, v.worst /= v.cases, v.mean /= v.cases;
  return v;
}

double motion_between(const Vertices& a, const Vertices& b) {
  const Eigen::RowVector3d shift = a.colwise().mean() - b.colwise().mean();
  return ((a.rowwise() - shift) - b).rowwise().norm().mean();
}

std::vector<PaceCase> pace_of(const FrameSet& pred, const FrameSet& truth) {
  std::vector<PaceCase> cases;
  if (pred.step.empty() || pred.source.empty()) return cases;
  for (std::size_t s = 0; s + 1 < pred.offsets.size(); ++s) {
    const auto begin = static_cast<std::size_t>(pred.offsets[s]),
               end = static_cast<std::size_t>(pred.offsets[s + 1]);
    std::size_t last_given = end;  // the frame before step 1
    for (std::size_t i = begin; i + 1 < end; ++i)
      if (pred.step[i] == 0 && pred.step[i + 1] == 1) last_given = i;
    if (last_given + kPaceSteps >= end) continue;  // (also: no step 1)
    const auto first = pred.source.begin() + static_cast<std::ptrdiff_t>(last_given);
    if (std::any_of(first, first + kPaceSteps + 1, [](std::int64_t j) { return j < 0; })) continue;
    PaceCase c{pred.sequences[s]};
    for (std::size_t k = last_given + 1; k <= last_given + kPaceSteps; ++k) {
      c.predicted += motion_between(pred.positions[k], pred.positions[k - 1]);
      c.truth += motion_between(truth.positions[static_cast<std::size_t>(pred.source[k])],
                                truth.positions[static_cast<std::size_t>(pred.source[k - 1])]);
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

}  // namespace df::eval
