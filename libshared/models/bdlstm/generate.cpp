#include "models/bdlstm/generate.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/acap_file.h"
#include "models/bdlstm/model.h"
#include "models/common/model_data.h"

namespace df::models {
namespace {

using Matrix = nn::Matrix<float>;
using Eigen::Index;

// "123" (global) or "SEQUENCE:K".
std::int64_t parse_frame(const std::string& s, const GenerationData& d) {
  auto number = [&](const std::string& t) -> std::int64_t {
    if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos)
      throw UsageError("bad frame '" + s + "' (expected a global index or SEQUENCE:K)");
    return std::stoll(t);
  };
  const auto colon = s.rfind(':');
  std::int64_t f;
  if (colon == std::string::npos) {
    f = number(s);
  } else {
    const std::string seq = s.substr(0, colon);
    auto it = std::find(d.sequences.begin(), d.sequences.end(), seq);
    if (it == d.sequences.end()) throw UsageError(fmt::format("no sequence '{}' in the data", seq));
    const auto k = static_cast<std::size_t>(it - d.sequences.begin());
    f = d.offsets[k] + number(s.substr(colon + 1));
    if (f >= d.offsets[k + 1])
      throw UsageError(fmt::format("frame '{}': sequence '{}' has {} frames", s, seq,
                                   d.offsets[k + 1] - d.offsets[k]));
  }
  if (f < 0 || f >= d.offsets.back())
    throw UsageError(fmt::format("frame {} is outside the data's 0-{}", s, d.offsets.back() - 1));
  return f;
}

float relative_difference(const Matrix& a, const Matrix& b, Index row) {
  const float n = a.row(row).norm();
  return (a.row(row) - b.row(row)).norm() / std::max(n, 1e-12f);
}

void check_options(const BdlstmGenerateOptions& opt) {
  if (opt.mode != "predict" && opt.mode != "complete")
    throw UsageError("--mode must be predict or complete, not '" + opt.mode + "'");
  if (opt.method != "bdlstm" && opt.method != "linear" && opt.method != "static")
    throw UsageError("--method must be bdlstm, linear or static");
  if (opt.method == "static" && opt.mode != "predict")
    throw UsageError("--method static is a prediction baseline");
  if (opt.initial < 1) throw UsageError("--initial must be at least 1");
  if (opt.length < 1 || opt.gap < 1 || opt.samples < 1 || opt.retries < 1)
    throw UsageError("--length, --gap, --samples and --retries must be positive");
  if (opt.method == "linear" && opt.mode == "predict" && opt.initial < 2)
    throw UsageError(
        "linear extrapolation needs --initial 2 or more (it continues the last two frames)");
  if (opt.mode == "predict" && !opt.keyframes.empty())
    throw UsageError("--keyframes is for --mode complete");
  if (opt.mode == "complete" && !opt.from.empty()) throw UsageError("--from is for --mode predict");
  const auto& frames = opt.mode == "predict" ? opt.from : opt.keyframes;
  if (frames.empty() == (opt.test_every == 0))
    throw UsageError(opt.mode == "predict" ? "give --from or --test-every, one of them"
                                           : "give --keyframes or --test-every, one of them");
  if (opt.stride < 0) throw UsageError("--stride must not be negative");
  if (opt.part != "test" && opt.part != "validation")
    throw UsageError("--part must be test or validation");
  if (opt.restart != "window" && opt.restart != "never")
    throw UsageError("--restart must be window or never");
  if (opt.latent != "mean" && opt.latent != "sample")
    throw UsageError("--latent must be mean or sample");
  if (opt.merge_scale != "features" && opt.merge_scale != "motion")
    throw UsageError("--merge-scale must be features or motion");
  if (opt.blend < 0) throw UsageError("--blend must not be negative");
  if (opt.merge != "closest" && opt.merge != "weighted")
    throw UsageError("--merge must be closest or weighted");
  if (!(opt.state_sigma >= 0)) throw UsageError("--state-sigma must not be negative");
  if (!(opt.threshold >= 0)) throw UsageError("--threshold must not be negative");
}

}  // namespace

ChainStepper::ChainStepper(const BdlstmNet<float>& net, int chain)
    : net_(net), chain_(chain), bound_(net.store().bind(tape_)), mark_(tape_.size()) {}

void ChainStepper::reset(Index rows, float value, double sigma, Rng& rng) {
  const auto hidden = static_cast<Index>(net_.config().hidden);
  h_.assign(static_cast<std::size_t>(net_.config().lstm_layers),
            Matrix::Constant(rows, hidden, value));
  c_ = h_;
  if (sigma > 0)
    for (auto* states : {&h_, &c_})
      for (auto& m : *states)
        for (Index k = 0; k < m.size(); ++k)
          m.data()[k] += static_cast<float>(sigma * rng.normal());
}

Matrix ChainStepper::step(const Matrix& x) {
  Rng unused;
  return step(x, LatentInput::mean, unused);
}

Matrix ChainStepper::step(const Matrix& x, LatentInput latent, Rng& rng) {
  tape_.truncate(mark_);
  auto states = net_.states_from(tape_, h_, c_);
  const nn::Var<float> xin = tape_.constant(x);
  nn::Var<float> z;
  if (latent == LatentInput::mean || latent == LatentInput::sample) {
    auto [mu, logvar] = net_.encode(bound_, chain_, xin);
    z = mu;
    if (latent == LatentInput::sample && net_.config().kl) {  // z ~ q(z|x), as in training (a
      Matrix eps(x.rows(), net_.config().latent);             // deterministic encoder: the mean)
      for (Index k = 0; k < eps.size(); ++k) eps.data()[k] = static_cast<float>(rng.normal());
      z = nn::reparameterize(mu, logvar, eps);
    }
  } else {
    Matrix eps = Matrix::Zero(x.rows(), net_.config().latent);
    if (latent == LatentInput::prior)
      for (Index k = 0; k < eps.size(); ++k) eps.data()[k] = static_cast<float>(rng.normal());
    z = tape_.constant(eps);
  }
  const Matrix y = net_.decode_step(bound_, chain_, xin, z, states).value();
  for (std::size_t l = 0; l < states.size(); ++l)
    h_[l] = states[l].h.value(), c_[l] = states[l].c.value();
  return y;
}

std::vector<double> probe_prediction_error(const BdlstmNet<float>& net, const Matrix& X,
                                           const std::vector<std::int64_t>& starts, int initial,
                                           int length, std::int64_t q, const LatentInput* latent,
                                           Rng& rng) {
  const auto rows = static_cast<Index>(starts.size());
  auto frame = [&](int t) {  // frame t of every window, [rows, 9V]
    Matrix x(rows, X.cols());
    for (Index r = 0; r < rows; ++r) x.row(r) = X.row(starts[static_cast<std::size_t>(r)] + t * q);
    return x;
  };
  auto error = [&](const Matrix& pred, const Matrix& truth) {
    double e = 0;
    for (Index r = 0; r < rows; ++r)
      e += (pred.row(r) - truth.row(r)).norm() / std::max(truth.row(r).norm(), 1e-12f);
    return e / static_cast<double>(rows);
  };
  std::vector<double> err;
  if (!latent) {  // zero motion: the last given frame
    const Matrix last = frame(initial - 1);
    for (int k = 1; k <= length; ++k) err.push_back(error(last, frame(initial - 1 + k)));
    return err;
  }
  ChainStepper chain(net, 0);
  chain.reset(rows, static_cast<float>(net.config().init_state), 0, rng);
  auto step = [&](const Matrix& x) { return chain.step(x, *latent, rng); };
  Matrix y;
  for (int t = 0; t < initial; ++t) y = step(frame(t));
  for (int k = 1; k <= length; ++k) {
    err.push_back(error(y, frame(initial - 1 + k)));
    if (k < length) y = step(y);
  }
  return err;
}

std::size_t GenerationData::sequence_of(std::int64_t f) const {
  return static_cast<std::size_t>(std::upper_bound(offsets.begin(), offsets.end(), f) -
                                  offsets.begin() - 1);
}

GenerationData read_generation_data(const std::string& path, const BdlstmModel& m) {
  const ModelData data(path, m.tmpl);
  GenerationData d;
  d.offsets = data.file().offsets();
  d.sequences = data.file().sequence_names();
  d.history = data.file().history();
  d.features = data.all_features(m.normalization);
  return d;
}

std::vector<GenerationCase> plan_cases(const BdlstmGenerateOptions& opt, const BdlstmModel& m,
                                       const GenerationData& d, std::int64_t q) {
  std::vector<GenerationCase> cases;
  const std::int64_t u = opt.initial;
  const auto& frames = opt.mode == "predict" ? opt.from : opt.keyframes;
  if (opt.test_every) {
    // Cases inside the model's held-out parts of the data's sequences (matched by name).
    for (std::size_t k = 0; k < m.split.sequences.size(); ++k) {
      auto it = std::find(d.sequences.begin(), d.sequences.end(), m.split.sequences[k]);
      if (it == d.sequences.end()) continue;
      const auto s = static_cast<std::size_t>(it - d.sequences.begin());
      const std::int64_t shift =
          d.offsets[s] - (m.split.train_begin[k] < m.split.test_begin[k] ? m.split.train_begin[k]
                                                                         : m.split.test_begin[k]);
      const bool validation = opt.part == "validation";
      const std::int64_t b =
          (validation ? m.split.validation_begin[k] : m.split.test_begin[k]) + shift;
      const std::int64_t e = (validation ? m.split.validation_end[k] : m.split.test_end[k]) + shift;
      // In steps of q frames: predict: the first predicted frame runs from b + context; the
      // given frames are the u before it. complete: keyframes a and a + gap + 1.
      const std::int64_t context =
          opt.mode == "predict" ? std::max<std::int64_t>(opt.test_context, u) : 0;
      const std::int64_t need = opt.mode == "predict" ? context + opt.length : opt.gap + 2;
      for (std::int64_t a = b; a + (need - 1) * q < e; a += opt.test_every) {
        GenerationCase c;
        if (opt.mode == "predict")
          for (std::int64_t t = context - u; t < context; ++t) c.frames.push_back(a + t * q);
        else
          c.frames = {a, a + (opt.gap + 1) * q};
        c.name = fmt::format("{}-{}", d.sequences[s], c.frames.back() - d.offsets[s]);
        cases.push_back(std::move(c));
      }
    }
    if (cases.empty())
      throw InvalidInput(
          fmt::format("no {} part of the model's split is long enough for a case of {} frames{}",
                      opt.part == "validation" ? "validation" : "held-out",
                      opt.mode == "predict"
                          ? std::max<std::int64_t>(opt.test_context, u) + opt.length
                          : opt.gap + 2,
                      q > 1 ? fmt::format(" {} apart", q) : ""),
          opt.data);
  } else if (opt.mode == "predict") {
    for (const auto& spec : frames) {
      const std::int64_t last = parse_frame(spec, d);
      const std::size_t s = d.sequence_of(last);
      if ((last - d.offsets[s]) / q + 1 < u)
        throw UsageError(
            fmt::format("--from {}: only {} frames of '{}' up to it{}, --initial asks for {}", spec,
                        (last - d.offsets[s]) / q + 1, d.sequences[s],
                        q > 1 ? fmt::format(" at the model's stride {}", q) : "", u));
      GenerationCase c;
      for (std::int64_t t = u - 1; t >= 0; --t) c.frames.push_back(last - t * q);
      c.name = fmt::format("{}-{}", d.sequences[s], last - d.offsets[s]);
      cases.push_back(std::move(c));
    }
  } else {
    GenerationCase c;
    for (const auto& spec : frames) c.frames.push_back(parse_frame(spec, d));
    if (c.frames.size() < 2) throw UsageError("--keyframes needs at least two frames");
    for (std::size_t k = 1; k < c.frames.size(); ++k) {
      if (c.frames[k] <= c.frames[k - 1])
        throw UsageError(
            "--keyframes must be increasing (a gap runs forward from one keyframe to the next)");
      if ((c.frames[k] - c.frames[k - 1]) % q != 0)
        throw UsageError(fmt::format(
            "keyframes {} and {} are {} frames apart, not a multiple of the stride {} the "
            "model steps by (--stride)",
            c.frames[k - 1], c.frames[k], c.frames[k] - c.frames[k - 1], q));
    }
    c.name = fmt::format("{}-{}", d.sequences[d.sequence_of(c.frames[0])],
                         c.frames[0] - d.offsets[d.sequence_of(c.frames[0])]);
    cases.push_back(std::move(c));
  }
  return cases;
}

ChainRunner::ChainRunner(const BdlstmGenerateOptions& opt, const BdlstmModel& m,
                         const GenerationData& d, std::int64_t stride, std::uint64_t seed)
    : opt_(opt),
      m_(m),
      d_(d),
      q_(stride),
      window_(opt.window ? opt.window : m.training.window),
      restart_(opt.restart == "window"),
      latent_(opt.latent == "sample" ? LatentInput::sample : LatentInput::mean),
      threshold_(opt.threshold > 0 ? opt.threshold : opt.merge_scale == "motion" ? 1.0 : 0.05),
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
std::vector<Matrix> mixed_path(const std::vector<Matrix>& F, const std::vector<Matrix>& B, Index row,
                               W backward) {
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
  if (opt_.method == "static") {  // zero motion: the last given frame, repeated
    for (auto& s : g)
      for (int k = 1; k <= opt_.length; ++k) push(s, X.row(last), source_of(last, k), k);
  } else if (opt_.method == "linear") {
    const Matrix a = X.row(c.frames[static_cast<std::size_t>(u - 2)]), b = X.row(last);
    for (auto& s : g)
      for (int k = 1; k <= opt_.length; ++k)
        push(s, b + static_cast<float>(k) * (b - a), source_of(last, k), k);
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
  if (opt_.method == "linear") {
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
    if (opt_.merge == "weighted") {  // no merge point: each chain weighs most near its keyframe
      for (int k = 0; k < K; ++k) path[static_cast<std::size_t>(k)] = weighted_path(F, B, k);
      return path;
    }
    bool all = true;
    for (int k = 0; k < K; ++k) {
      auto& bk = best[static_cast<std::size_t>(k)];
      if (bk < threshold_) continue;
      // --merge-scale motion: differences relative to the two chains' mean change per step.
      float motion = 0;
      if (opt_.merge_scale == "motion") {
        for (std::int64_t t = 0; t < L; ++t)
          motion += (F[static_cast<std::size_t>(t + 1)].row(k) - F[static_cast<std::size_t>(t)].row(k)).norm() +
                    (B[static_cast<std::size_t>(t + 1)].row(k) - B[static_cast<std::size_t>(t)].row(k)).norm();
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
          const float e = motion > 0 ? (fi.row(k) - bj.row(k)).norm() / motion
                                     : relative_difference(fi, bj, k);
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

void write_generated(const std::vector<GeneratedSequence>& out, const BdlstmGenerateOptions& opt,
                     const BdlstmModel& m, const GenerationData& d, const CommonOptions& common) {
  AtomicOutput dest(opt.output, AtomicOutput::Kind::file, common.force, {opt.model, opt.data});
  {
    io::AcapWriter f(dest.temp_path(), opt.output,
                     {m.history == d.history ? d.history : m.history + "\n" + d.history});
    f.write_template(m.tmpl);
    f.write_normalization(m.normalization);
    std::vector<std::string> names, seqs;
    std::vector<std::int64_t> offsets{0}, source;
    std::vector<std::int32_t> step;
    for (const auto& s : out) {
      seqs.push_back(s.name);
      for (std::size_t t = 0; t < s.frames.size(); ++t) names.push_back(fmt::format("{}", t));
      offsets.push_back(offsets.back() + static_cast<std::int64_t>(s.frames.size()));
      source.insert(source.end(), s.source.begin(), s.source.end());
      step.insert(step.end(), s.step.begin(), s.step.end());
    }
    const auto n = static_cast<std::size_t>(offsets.back()),
               nv = static_cast<std::size_t>(m.tmpl.vertices.rows());
    f.write_frame_names(names);
    f.write_source(source, opt.data);
    f.write_steps(step);
    f.write_sequences(offsets, seqs);
    f.create_normalized(n, nv);
    std::size_t row = 0;
    for (const auto& s : out)
      for (const auto& fr : s.frames) f.write_normalized_rows(row++, 1, fr.data());
    f.close();
  }
  dest.commit();
}

void generate_bdlstm(const BdlstmGenerateOptions& opt, const CommonOptions& common) {
  check_options(opt);
  BdlstmModel m = load_bdlstm_model(opt.model);
  if (opt.mode == "complete" && opt.method == "bdlstm" &&
      m.config.directions == Directions::unidirectional)
    throw UsageError(
        "the model was trained unidirectional; completion needs a bidirectional model");
  const GenerationData d = read_generation_data(opt.data, m);
  const std::int64_t q = opt.stride ? opt.stride : m.training.stride;  // data frames per step
  const std::vector<GenerationCase> cases = plan_cases(opt, m, d, q);

  ChainRunner runner(opt, m, d, q, common.seed);
  std::vector<GeneratedSequence> out;
  Progress progress(opt.mode == "predict" ? "predicting" : "completing", cases.size());
  for (const auto& c : cases) {
    for (auto& s : opt.mode == "predict" ? runner.predict(c) : runner.complete(c))
      out.push_back(std::move(s));
    progress.advance();
  }
  progress.finish();
  if (runner.unmerged())
    log::warn(
        "{} completion(s) did not merge below --threshold {} after {} attempts (worst relative "
        "difference {:.3g}); "
        "the closest pair was used",
        runner.unmerged(), runner.threshold(), opt.retries, runner.worst_merge());
  else if (opt.mode == "complete" && opt.method == "bdlstm")
    log::info("every completion merged (worst relative difference {:.3g})", runner.worst_merge());

  write_generated(out, opt, m, d, common);
  std::size_t frames = 0;
  for (const auto& s : out) frames += s.frames.size();
  log::info("wrote {} sequence(s), {} frames to {}", out.size(), frames, opt.output);
}

}  // namespace df::models
