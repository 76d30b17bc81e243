#include "models/bdlstm/generate.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/file_header.h"
#include "io/schema.h"
#include "models/bdlstm/model.h"

namespace df::models {
namespace {

using Matrix = nn::Matrix<float>;
using Eigen::Index;

// Runs one chain of the network step by step without keeping the activations: parameters are
// bound once, every step's nodes are dropped after it.
class Stepper {
 public:
  Stepper(const BdlstmNet<float>& net, int chain) : net_(net), chain_(chain), bound_(net.store().bind(tape_)) {
    mark_ = tape_.size();
  }
  /// Initial states of `rows` rows: every h and c entry is `value` (+ N(0, sigma²) when sigma > 0).
  void reset(Index rows, float value, double sigma, Rng& rng) {
    const auto hidden = static_cast<Index>(net_.config().hidden);
    h_.assign(static_cast<std::size_t>(net_.config().lstm_layers), Matrix::Constant(rows, hidden, value));
    c_ = h_;
    if (sigma > 0)
      for (auto* states : {&h_, &c_})
        for (auto& m : *states)
          for (Index k = 0; k < m.size(); ++k) m.data()[k] += static_cast<float>(sigma * rng.normal());
  }
  Matrix step(const Matrix& x) {
    tape_.truncate(mark_);
    auto states = net_.states_from(tape_, h_, c_);
    auto y = net_.step(bound_, chain_, tape_.constant(x), states, nullptr, nullptr);
    for (std::size_t l = 0; l < states.size(); ++l) h_[l] = states[l].h.value(), c_[l] = states[l].c.value();
    return y.value();
  }

 private:
  const BdlstmNet<float>& net_;
  int chain_;
  nn::Tape<float> tape_;
  nn::Bound<float> bound_;
  std::size_t mark_ = 0;
  std::vector<Matrix> h_, c_;
};

struct Data {
  Matrix features;  // [N, 9V] normalized with the model's numbers
  std::vector<std::int64_t> offsets;
  std::vector<std::string> sequences;
  std::string history;
  std::size_t sequence_of(std::int64_t f) const {
    return static_cast<std::size_t>(std::upper_bound(offsets.begin(), offsets.end(), f) - offsets.begin() - 1);
  }
};

Data read_data(const std::string& path, const BdlstmModel& m) {
  io::Dimensions dims;
  h5::File in = io::open_input(path, "acap", &dims);
  Data d;
  const auto nv = m.tmpl.vertices.rows();
  if (static_cast<Index>(dims.at("V")) != nv)
    throw InvalidInput(fmt::format("has {} vertices, the model's template {}: model and data must share the template",
                                   dims.at("V"), nv),
                       path);
  if (in.read_matrix<int>("/template/faces") != m.tmpl.faces)
    throw InvalidInput("its template faces differ from the model's: model and data must share the template", path);
  d.offsets = in.read<std::int64_t>("/sequences/offsets").data;
  d.sequences = in.read_strings("/sequences/names");
  d.history = io::read_history(in);
  const auto n = static_cast<Index>(dims.at("N"));
  d.features.resize(n, 9 * nv);
  const bool has_norm = in.exists("/features/normalized");
  bool same = false;
  if (has_norm) {
    auto nz = geometry::read_normalization(in);
    same = nz.min == m.normalization.min && nz.max == m.normalization.max;
  }
  if (same) {
    in.read_rows<float>("/features/normalized", 0, static_cast<std::size_t>(n), d.features.data());
  } else if (in.exists("/features/raw")) {  // renormalize with the model's numbers
    std::vector<double> raw(static_cast<std::size_t>(d.features.size()));
    in.read_rows<double>("/features/raw", 0, static_cast<std::size_t>(n), raw.data());
    for (std::size_t k = 0; k < raw.size(); ++k)
      d.features.data()[k] = static_cast<float>(m.normalization.normalize(static_cast<int>(k % 9), raw[k]));
  } else {
    throw InvalidInput("its features are normalized with other numbers than the model's and it has no "
                       "/features/raw to renormalize",
                       path);
  }
  io::check_finite_rows(d.features.data(), 0, static_cast<std::size_t>(n), static_cast<std::size_t>(d.features.cols()),
                        in.where("/features"));
  return d;
}

// "123" (global) or "SEQUENCE:K".
std::int64_t parse_frame(const std::string& s, const Data& d) {
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
      throw UsageError(fmt::format("frame '{}': sequence '{}' has {} frames", s, seq, d.offsets[k + 1] - d.offsets[k]));
  }
  if (f < 0 || f >= d.offsets.back())
    throw UsageError(fmt::format("frame {} is outside the data's 0-{}", s, d.offsets.back() - 1));
  return f;
}

// One output sequence.
struct Generated {
  std::string name;
  std::vector<Matrix> frames;  // each [1, 9V]
  std::vector<std::int64_t> source;
  std::vector<std::int32_t> step;
};

struct Case {
  std::string name;
  std::vector<std::int64_t> frames;  // predict: the given frames; complete: the keyframes
};

float relative_difference(const Matrix& a, const Matrix& b, Index row) {
  const float n = a.row(row).norm();
  return (a.row(row) - b.row(row)).norm() / std::max(n, 1e-12f);
}

}  // namespace

void generate_bdlstm(const BdlstmGenerateOptions& opt, const CommonOptions& common) {
  if (opt.mode != "predict" && opt.mode != "complete") throw UsageError("--mode must be predict or complete, not '" + opt.mode + "'");
  if (opt.method != "bdlstm" && opt.method != "linear" && opt.method != "static")
    throw UsageError("--method must be bdlstm, linear or static");
  if (opt.method == "static" && opt.mode != "predict") throw UsageError("--method static is a prediction baseline");
  if (opt.initial < 1) throw UsageError("--initial must be at least 1");
  if (opt.length < 1 || opt.gap < 1 || opt.samples < 1 || opt.retries < 1)
    throw UsageError("--length, --gap, --samples and --retries must be positive");
  if (opt.method == "linear" && opt.mode == "predict" && opt.initial < 2)
    throw UsageError("linear extrapolation needs --initial 2 or more (it continues the last two frames)");
  if (opt.mode == "predict" && !opt.keyframes.empty()) throw UsageError("--keyframes is for --mode complete");
  if (opt.mode == "complete" && !opt.from.empty()) throw UsageError("--from is for --mode predict");
  const auto& frames = opt.mode == "predict" ? opt.from : opt.keyframes;
  if (frames.empty() == (opt.test_every == 0))
    throw UsageError(opt.mode == "predict" ? "give --from or --test-every, one of them"
                                           : "give --keyframes or --test-every, one of them");

  BdlstmModel m = load_bdlstm_model(opt.model);
  const BdlstmNet<float>& net = *m.net;
  if (opt.mode == "complete" && opt.method == "bdlstm" && m.config.directions == Directions::unidirectional)
    throw UsageError("the model was trained unidirectional; completion needs a bidirectional model");
  Data d = read_data(opt.data, m);
  const int window = opt.window ? opt.window : m.training.window;
  if (window < 2) throw UsageError("--window must be at least 2");
  if (opt.stride < 0) throw UsageError("--stride must not be negative");
  const std::int64_t q = opt.stride ? opt.stride : m.training.stride;  // data frames per step

  // The cases.
  std::vector<Case> cases;
  const std::int64_t u = opt.initial;
  if (opt.test_every) {
    // Cases inside the model's held-out parts of the data's sequences (matched by name).
    for (std::size_t k = 0; k < m.split.sequences.size(); ++k) {
      auto it = std::find(d.sequences.begin(), d.sequences.end(), m.split.sequences[k]);
      if (it == d.sequences.end()) continue;
      const auto s = static_cast<std::size_t>(it - d.sequences.begin());
      const std::int64_t shift = d.offsets[s] - (m.split.train_begin[k] < m.split.test_begin[k] ? m.split.train_begin[k]
                                                                                                 : m.split.test_begin[k]);
      const std::int64_t b = m.split.test_begin[k] + shift, e = m.split.test_end[k] + shift;
      // In steps of q frames: predict: the first predicted frame runs from b + context; the
      // given frames are the u before it. complete: keyframes a and a + gap + 1.
      const std::int64_t context = opt.mode == "predict" ? std::max<std::int64_t>(opt.test_context, u) : 0;
      const std::int64_t need = opt.mode == "predict" ? context + opt.length : opt.gap + 2;
      for (std::int64_t a = b; a + (need - 1) * q < e; a += opt.test_every) {
        Case c;
        if (opt.mode == "predict")
          for (std::int64_t t = context - u; t < context; ++t) c.frames.push_back(a + t * q);
        else
          c.frames = {a, a + (opt.gap + 1) * q};
        c.name = fmt::format("{}-{}", d.sequences[s], c.frames.back() - d.offsets[s]);
        cases.push_back(std::move(c));
      }
    }
    if (cases.empty())
      throw InvalidInput(fmt::format("no held-out part of the model's split is long enough for a case of {} frames{}",
                                     opt.mode == "predict" ? std::max<std::int64_t>(opt.test_context, u) + opt.length
                                                           : opt.gap + 2,
                                     q > 1 ? fmt::format(" {} apart", q) : ""),
                         opt.data);
  } else if (opt.mode == "predict") {
    for (const auto& spec : frames) {
      const std::int64_t last = parse_frame(spec, d);
      const std::size_t s = d.sequence_of(last);
      if ((last - d.offsets[s]) / q + 1 < u)
        throw UsageError(fmt::format("--from {}: only {} frames of '{}' up to it{}, --initial asks for {}", spec,
                                     (last - d.offsets[s]) / q + 1, d.sequences[s],
                                     q > 1 ? fmt::format(" at the model's stride {}", q) : "", u));
      Case c;
      for (std::int64_t t = u - 1; t >= 0; --t) c.frames.push_back(last - t * q);
      c.name = fmt::format("{}-{}", d.sequences[s], last - d.offsets[s]);
      cases.push_back(std::move(c));
    }
  } else {
    Case c;
    for (const auto& spec : frames) c.frames.push_back(parse_frame(spec, d));
    if (c.frames.size() < 2) throw UsageError("--keyframes needs at least two frames");
    for (std::size_t k = 1; k < c.frames.size(); ++k) {
      if (c.frames[k] <= c.frames[k - 1])
        throw UsageError("--keyframes must be increasing (a gap runs forward from one keyframe to the next)");
      if ((c.frames[k] - c.frames[k - 1]) % q != 0)
        throw UsageError(fmt::format("keyframes {} and {} are {} frames apart, not a multiple of the stride {} the "
                                     "model steps by (--stride)",
                                     c.frames[k - 1], c.frames[k], c.frames[k] - c.frames[k - 1], q));
    }
    c.name = fmt::format("{}-{}", d.sequences[d.sequence_of(c.frames[0])], c.frames[0] - d.offsets[d.sequence_of(c.frames[0])]);
    cases.push_back(std::move(c));
  }

  const int K = opt.samples;
  const bool random_states = K > 1;
  Rng rng(common.seed, 2);
  const auto init = static_cast<float>(m.config.init_state);
  auto source_of = [&](std::int64_t from, std::int64_t k) -> std::int64_t {  // data frame k steps after `from`
    const std::size_t s = d.sequence_of(from);
    return from + k * q < d.offsets[s + 1] ? from + k * q : -1;
  };
  std::vector<Generated> out;
  Progress progress(opt.mode == "predict" ? "predicting" : "completing", cases.size());
  Stepper forward(net, 0);
  std::unique_ptr<Stepper> backward_own;
  if (net.n_chains() == 2) backward_own = std::make_unique<Stepper>(net, 1);
  Stepper& backward = backward_own ? *backward_own : forward;
  int unmerged = 0;
  double worst_merge = 0;

  for (const auto& c : cases) {
    std::vector<Generated> g(static_cast<std::size_t>(K));
    for (int k = 0; k < K; ++k) g[static_cast<std::size_t>(k)].name = K == 1 ? c.name : fmt::format("{}~{}", c.name, k);
    auto push = [&](Generated& s, const Matrix& row, std::int64_t source, std::int32_t step) {
      s.frames.push_back(row);
      s.source.push_back(source);
      s.step.push_back(step);
    };
    if (opt.mode == "predict") {
      const std::int64_t last = c.frames.back();
      for (auto& s : g)
        for (std::int64_t t = 0; t < u; ++t) push(s, d.features.row(c.frames[static_cast<std::size_t>(t)]), c.frames[static_cast<std::size_t>(t)], 0);
      if (opt.method == "static") {  // zero motion: the last given frame, repeated
        for (auto& s : g)
          for (int k = 1; k <= opt.length; ++k) push(s, d.features.row(last), source_of(last, k), k);
      } else if (opt.method == "linear") {
        const Matrix a = d.features.row(c.frames[static_cast<std::size_t>(u - 2)]), b = d.features.row(last);
        for (auto& s : g)
          for (int k = 1; k <= opt.length; ++k) push(s, b + static_cast<float>(k) * (b - a), source_of(last, k), k);
      } else {
        // Rows = samples. Feed the given frames, then free-run; restart every window.
        std::vector<Matrix> recent;  // the last u frames (each [K, 9V])
        for (std::int64_t t = 0; t < u; ++t) recent.push_back(Matrix(d.features.row(c.frames[static_cast<std::size_t>(t)])).replicate(K, 1));
        int produced = 0;
        while (produced < opt.length) {
          forward.reset(K, init, random_states ? opt.state_sigma : 0, rng);
          Matrix y;
          for (const auto& x : recent) y = forward.step(x);
          int in_run = static_cast<int>(u);
          while (true) {
            ++produced;
            for (int k = 0; k < K; ++k) push(g[static_cast<std::size_t>(k)], y.row(k), source_of(last, produced), produced);
            recent.erase(recent.begin());
            recent.push_back(y);
            if (produced == opt.length || in_run >= window - 1) break;
            y = forward.step(y);
            ++in_run;
          }
        }
      }
    } else {
      // Completion, gap by gap; every sample's path starts with the first keyframe.
      for (auto& s : g) push(s, d.features.row(c.frames[0]), c.frames[0], 0);
      for (std::size_t gi = 0; gi + 1 < c.frames.size(); ++gi) {
        const std::int64_t a = c.frames[gi], b = c.frames[gi + 1], L = (b - a) / q;  // steps
        std::vector<std::vector<Matrix>> path(static_cast<std::size_t>(K));  // steps 1 .. L
        if (opt.method == "linear") {
          for (int k = 0; k < K; ++k)
            for (std::int64_t t = 1; t <= L; ++t)
              path[static_cast<std::size_t>(k)].push_back(d.features.row(a) + (static_cast<float>(t) / static_cast<float>(L)) *
                                                                                  (d.features.row(b) - d.features.row(a)));
        } else {
          std::vector<float> best(static_cast<std::size_t>(K), std::numeric_limits<float>::infinity());
          for (int attempt = 0; attempt < opt.retries; ++attempt) {
            const bool rnd = random_states || attempt > 0;
            forward.reset(K, init, rnd ? opt.state_sigma : 0, rng);
            std::vector<Matrix> F{Matrix(d.features.row(a)).replicate(K, 1)};
            for (std::int64_t t = 0; t < L; ++t) F.push_back(forward.step(F.back()));
            backward.reset(K, -init, rnd ? opt.state_sigma : 0, rng);
            std::vector<Matrix> B{Matrix(d.features.row(b)).replicate(K, 1)};
            for (std::int64_t t = 0; t < L; ++t) B.push_back(backward.step(B.back()));
            bool all = true;
            for (int k = 0; k < K; ++k) {
              auto& bk = best[static_cast<std::size_t>(k)];
              if (bk < opt.threshold) continue;
              // F_i is i steps after a, B_j j steps before b: same time i+j = L, adjacent i+j = L−1.
              float diff = std::numeric_limits<float>::infinity();
              std::int64_t bi = 0;
              for (std::int64_t i = 0; i <= L; ++i)
                for (std::int64_t j : {L - i, L - 1 - i}) {
                  if (j < 0) continue;
                  const float e = relative_difference(F[static_cast<std::size_t>(i)], B[static_cast<std::size_t>(j)], k);
                  if (e < diff) diff = e, bi = i;
                }
              if (diff < bk) {
                bk = diff;
                // Step t comes from the forward chain up to the merge, then from the
                // backward chain (B_0 = the keyframe b).
                auto& p = path[static_cast<std::size_t>(k)];
                p.clear();
                for (std::int64_t t = 1; t <= L; ++t)
                  p.push_back(t < L && t <= bi ? Matrix(F[static_cast<std::size_t>(t)].row(k))
                                               : Matrix(B[static_cast<std::size_t>(L - t)].row(k)));
              }
              all = all && bk < opt.threshold;
            }
            if (all) break;
          }
          for (float bk : best) {
            worst_merge = std::max(worst_merge, static_cast<double>(bk));
            if (bk >= opt.threshold) ++unmerged;
          }
        }
        for (int k = 0; k < K; ++k) {
          auto& p = path[static_cast<std::size_t>(k)];
          if (static_cast<std::int64_t>(p.size()) != L) throw Error("internal: completion path of the wrong length");
          for (std::int64_t t = 1; t <= L; ++t)
            push(g[static_cast<std::size_t>(k)], p[static_cast<std::size_t>(t - 1)], source_of(a, t),
                 t == L ? 0 : static_cast<std::int32_t>(t));  // keyframes are given: step 0
        }
      }
    }
    for (auto& s : g) out.push_back(std::move(s));
    progress.advance();
  }
  progress.finish();
  if (unmerged)
    log::warn("{} completion(s) did not merge below --threshold {} after {} attempts (worst relative difference {:.3g}); "
              "the closest pair was used",
              unmerged, opt.threshold, opt.retries, worst_merge);
  else if (opt.mode == "complete" && opt.method == "bdlstm")
    log::info("every completion merged (worst relative difference {:.3g})", worst_merge);

  // Output: an acap file with normalized features.
  AtomicOutput dest(opt.output, AtomicOutput::Kind::file, common.force, {opt.model, opt.data});
  {
    h5::File f(dest.temp_path(), h5::File::Mode::create, opt.output);
    io::write_header(f, "acap", {m.history == d.history ? d.history : m.history + "\n" + d.history});
    f.write_matrix("/template/vertices", m.tmpl.vertices);
    f.write_matrix("/template/faces", m.tmpl.faces);
    geometry::write_normalization(f, m.normalization);
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
    const auto n = static_cast<std::size_t>(offsets.back()), nv = static_cast<std::size_t>(m.tmpl.vertices.rows());
    f.write_strings("/frames/names", names);
    f.write<std::int64_t>("/frames/source", source, {n});
    f.write<std::int32_t>("/frames/step", step, {n});
    f.set_attr("/frames/source", "data", opt.data);
    f.write<std::int64_t>("/sequences/offsets", offsets, {offsets.size()});
    f.write_strings("/sequences/names", seqs);
    f.create<float>("/features/normalized", {n, nv, 9});
    std::size_t row = 0;
    for (const auto& s : out)
      for (const auto& fr : s.frames) f.write_rows<float>("/features/normalized", row++, 1, fr.data());
    f.close();
  }
  dest.commit();
  log::info("wrote {} sequence(s), {} frames to {}", out.size(), [&] {
    std::size_t n = 0;
    for (const auto& s : out) n += s.frames.size();
    return n;
  }(), opt.output);
}

}  // namespace df::models
