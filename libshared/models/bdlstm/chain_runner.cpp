// ChainRunner and the completion paths of gen-bdlstm (generate.h): the model's chains run over
// the planned cases.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "models/bdlstm/generate.h"

namespace df::models {
namespace {

using Matrix = nn::Matrix<float>;
using Eigen::Index;

float relative_difference(const Matrix& a, const Matrix& b, Index row) {
  const float n = a.row(row).norm();
  return (a.row(row) - b.row(row)).norm() / std::max(n, 1e-12f);
}

}  // namespace

ChainRunner::ChainRunner(const BdlstmGenerateOptions& opt, const BdlstmModel& m,
                         const GenerationData& d, std::int64_t stride, std::uint64_t seed)
    : opt_(opt),
      m_(m),
      d_(d),
      q_(stride),
      window_(opt.window ? opt.window : m.training.window),
      restart_(opt.restart == Restart::window),
      latent_(opt.latent),
      threshold_(opt.threshold > 0                       ? opt.threshold
                 : opt.merge_scale == MergeScale::motion ? 1.0
                                                         : 0.05),
      rng_(seed, 2),
      forward_(std::make_unique<ChainStepper>(*m.net, 0)) {
  if (window_ < 2) throw UsageError("--window must be at least 2");
  if (m.net->n_chains() == 2) backward_own_ = std::make_unique<ChainStepper>(*m.net, 1);
  backward_ = backward_own_ ? backward_own_.get() : forward_.get();
}

ChainRunner::~ChainRunner() = default;

std::int64_t ChainRunner::source_of(std::int64_t from,
                                    std::int64_t k) const {  // data frame k steps after `from`
  const std::size_t s = d_.sequence_of(from);
  return from + k * q_ < d_.offsets[s + 1] ? from + k * q_ : -1;
}

namespace {

std::vector<GeneratedSequence> named_samples(const std::string& name, int K) {
  std::vector<GeneratedSequence> g(static_cast<std::size_t>(K));
  for (int k = 0; k < K; ++k)
    g[static_cast<std::size_t>(k)].name = K == 1 ? name : fmt::format("{}~{}", name, k);
  return g;
}

void push(GeneratedSequence& s, const Matrix& row, std::int64_t source, std::int32_t step) {
  s.frames.push_back(row);
  s.source.push_back(source);
  s.step.push_back(step);
}

}  // namespace

namespace {

// Steps 1..L of a gap: (1 − w_t) F_t + w_t B_{L−t} for row `row`, w_t = backward(t).
template <class W>
std::vector<Matrix> mixed_path(const std::vector<Matrix>& F, const std::vector<Matrix>& B,
                               Index row, W backward) {
  const auto L = static_cast<std::int64_t>(F.size()) - 1;
  std::vector<Matrix> p;
  for (std::int64_t t = 1; t <= L; ++t) {
    const auto w = static_cast<float>(backward(t, L));
    const Matrix f = F[static_cast<std::size_t>(t)].row(row);
    const Matrix b = B[static_cast<std::size_t>(L - t)].row(row);
    p.push_back(w == 0 ? f : w == 1 ? b : Matrix((1 - w) * f + w * b));
  }
  return p;
}

}  // namespace

std::vector<Matrix> merged_path(const std::vector<Matrix>& F, const std::vector<Matrix>& B,
                                Index row, std::int64_t merge, int blend) {
  // 0 up to the merge, 1 after it, a linear ramp over `blend` frames centred between frames
  // merge and merge + 1; the last frame is the keyframe.
  return mixed_path(F, B, row, [&](std::int64_t t, std::int64_t L) {
    const double ramp = 0.5 + (static_cast<double>(t - merge) - 0.5) / (blend + 1);
    return t == L ? 1.0 : std::clamp(ramp, 0.0, 1.0);
  });
}

std::vector<Matrix> weighted_path(const std::vector<Matrix>& F, const std::vector<Matrix>& B,
                                  Index row) {
  return mixed_path(F, B, row, [](std::int64_t t, std::int64_t L) {
    return static_cast<double>(t) / static_cast<double>(L);
  });
}

std::vector<GeneratedSequence> ChainRunner::predict(const GenerationCase& c) {
  const int K = opt_.samples;
  const auto& X = d_.features;
  const std::int64_t u = static_cast<std::int64_t>(c.frames.size()), last = c.frames.back();
  auto g = named_samples(c.name, K);
  for (auto& s : g)
    for (std::int64_t t = 0; t < u; ++t)
      push(s, X.row(c.frames[static_cast<std::size_t>(t)]), c.frames[static_cast<std::size_t>(t)],
           0);
  if (opt_.method == GenerateMethod::still) {  // zero motion: the last given frame, repeated
    for (auto& s : g)
      for (int k = 1; k <= opt_.length; ++k) push(s, X.row(last), source_of(last, k), k);
  } else if (opt_.method == GenerateMethod::nearest) {
    const auto path = nearest_motion(m_, d_, c.frames, opt_.length, q_, opt_.neighbours);
    for (auto& s : g)
      for (int k = 1; k <= opt_.length; ++k)
        push(s, path[static_cast<std::size_t>(k - 1)], source_of(last, k), k);
  } else if (opt_.method == GenerateMethod::linear || opt_.method == GenerateMethod::damped) {
    // The last step, shrinking by d a frame (linear: d = 1, the step kept; reach is then k exactly)
    const double d = opt_.method == GenerateMethod::linear ? 1 : opt_.damping;
    const Matrix a = X.row(c.frames[static_cast<std::size_t>(u - 2)]), b = X.row(last);
    double reach = 0, step = 1;  // d + d² + … + d^k
    for (int k = 1; k <= opt_.length; ++k) {
      step *= d;
      reach += step;
      for (auto& s : g) push(s, b + static_cast<float>(reach) * (b - a), source_of(last, k), k);
    }
  } else {
    // Rows = samples. Feed the given frames, then free-run; restart every window.
    std::vector<Matrix> recent;  // the last u frames (each [K, 9V])
    for (std::int64_t t = 0; t < u; ++t)
      recent.push_back(Matrix(X.row(c.frames[static_cast<std::size_t>(t)])).replicate(K, 1));
    const auto init = static_cast<float>(m_.config.init_state);
    int produced = 0;
    while (produced < opt_.length) {
      forward_->reset(K, init, K > 1 ? opt_.state_sigma : 0, rng_);
      Matrix y;
      for (const auto& x : recent) y = forward_->step(x, latent_, rng_);
      int in_run = static_cast<int>(u);
      while (true) {
        ++produced;
        for (int k = 0; k < K; ++k)
          push(g[static_cast<std::size_t>(k)], y.row(k), source_of(last, produced), produced);
        recent.erase(recent.begin());
        recent.push_back(y);
        // --restart never: one chain carries its LSTM state to the end.
        if (produced == opt_.length || (restart_ && in_run >= window_ - 1)) break;
        y = forward_->step(y, latent_, rng_);
        ++in_run;
      }
    }
  }
  return g;
}

std::vector<std::vector<Matrix>> ChainRunner::complete_gap(std::int64_t a, std::int64_t b) {
  const int K = opt_.samples;
  const auto& X = d_.features;
  const std::int64_t L = (b - a) / q_;                                 // steps
  std::vector<std::vector<Matrix>> path(static_cast<std::size_t>(K));  // steps 1 .. L
  if (opt_.method == GenerateMethod::linear) {
    for (int k = 0; k < K; ++k)
      for (std::int64_t t = 1; t <= L; ++t)
        path[static_cast<std::size_t>(k)].push_back(
            X.row(a) + (static_cast<float>(t) / static_cast<float>(L)) * (X.row(b) - X.row(a)));
    return path;
  }
  const auto init = static_cast<float>(m_.config.init_state);
  std::vector<float> best(static_cast<std::size_t>(K), std::numeric_limits<float>::infinity());
  for (int attempt = 0; attempt < opt_.retries; ++attempt) {
    const bool rnd = K > 1 || attempt > 0;
    forward_->reset(K, init, rnd ? opt_.state_sigma : 0, rng_);
    std::vector<Matrix> F{Matrix(X.row(a)).replicate(K, 1)};
    for (std::int64_t t = 0; t < L; ++t) F.push_back(forward_->step(F.back(), latent_, rng_));
    backward_->reset(K, -init, rnd ? opt_.state_sigma : 0, rng_);
    std::vector<Matrix> B{Matrix(X.row(b)).replicate(K, 1)};
    for (std::int64_t t = 0; t < L; ++t) B.push_back(backward_->step(B.back(), latent_, rng_));
    if (opt_.merge ==
        Merge::weighted) {  // no merge point: each chain weighs most near its keyframe
      for (int k = 0; k < K; ++k) path[static_cast<std::size_t>(k)] = weighted_path(F, B, k);
      return path;
    }
    bool all = true;
    for (int k = 0; k < K; ++k) {
      auto& bk = best[static_cast<std::size_t>(k)];
      if (bk < threshold_) continue;
      // --merge-scale motion: differences relative to the two chains' mean change per step.
      float motion = 0;
      if (opt_.merge_scale == MergeScale::motion) {
        for (std::int64_t t = 0; t < L; ++t)
          motion +=
              (F[static_cast<std::size_t>(t + 1)].row(k) - F[static_cast<std::size_t>(t)].row(k))
                  .norm() +
              (B[static_cast<std::size_t>(t + 1)].row(k) - B[static_cast<std::size_t>(t)].row(k))
                  .norm();
        motion = std::max(motion / static_cast<float>(2 * L), 1e-12f);
      }
      // F_i is i steps after a, B_j j steps before b: same time i+j = L, adjacent i+j = L−1.
      float diff = std::numeric_limits<float>::infinity();
      std::int64_t bi = 0;
      for (std::int64_t i = 0; i <= L; ++i)
        for (std::int64_t j : {L - i, L - 1 - i}) {
          if (j < 0) continue;
          const auto& fi = F[static_cast<std::size_t>(i)];
          const auto& bj = B[static_cast<std::size_t>(j)];
          const float e =
              motion > 0 ? (fi.row(k) - bj.row(k)).norm() / motion : relative_difference(fi, bj, k);
          if (e < diff) diff = e, bi = i;
        }
      if (diff < bk) {
        bk = diff;
        path[static_cast<std::size_t>(k)] = merged_path(F, B, k, bi, opt_.blend);
      }
      all = all && bk < threshold_;
    }
    if (all) break;
  }
  for (float bk : best) {
    worst_merge_ = std::max(worst_merge_, static_cast<double>(bk));
    if (bk >= threshold_) ++unmerged_;
  }
  return path;
}

std::vector<GeneratedSequence> ChainRunner::complete(const GenerationCase& c) {
  const int K = opt_.samples;
  auto g = named_samples(c.name, K);
  // Gap by gap; every sample's path starts with the first keyframe.
  for (auto& s : g) push(s, d_.features.row(c.frames[0]), c.frames[0], 0);
  for (std::size_t gi = 0; gi + 1 < c.frames.size(); ++gi) {
    const std::int64_t a = c.frames[gi], b = c.frames[gi + 1], L = (b - a) / q_;
    const auto path = complete_gap(a, b);
    for (int k = 0; k < K; ++k) {
      const auto& p = path[static_cast<std::size_t>(k)];
      if (static_cast<std::int64_t>(p.size()) != L)
        throw Error("internal: completion path of the wrong length");
      for (std::int64_t t = 1; t <= L; ++t)
        push(g[static_cast<std::size_t>(k)], p[static_cast<std::size_t>(t - 1)], source_of(a, t),
             t == L ? 0 : static_cast<std::int32_t>(t));  // keyframes are given: step 0
    }
  }
  return g;
}

}  // namespace df::models
