#include "models/bdlstm/generate.h"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>
#include <optional>

#include "core/error.h"
#include "io/acap_file.h"
#include "models/bdlstm/model.h"
#include "models/bdlstm/train.h"
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

// Where split sequence k of the model's training data lies in d: d's sequence of that name and
// the shift from the training file's global frames to d's; nothing when d has none.
struct Placement {
  std::size_t sequence;
  std::int64_t shift;
};
std::optional<Placement> place_in(const BdlstmSplit& split, std::size_t k,
                                  const GenerationData& d) {
  auto it = std::find(d.sequences.begin(), d.sequences.end(), split.sequences[k]);
  if (it == d.sequences.end()) return std::nullopt;
  const auto s = static_cast<std::size_t>(it - d.sequences.begin());
  return Placement{s, d.offsets[s] - std::min(split.train_begin[k], split.test_begin[k])};
}

}  // namespace

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
  const auto& frames = opt.mode == GenerateMode::predict ? opt.from : opt.keyframes;
  if (opt.test_every) {
    // Cases inside the model's held-out parts of the data's sequences (matched by name).
    for (std::size_t k = 0; k < m.split.sequences.size(); ++k) {
      const auto placed = place_in(m.split, k, d);
      if (!placed) continue;
      const std::size_t s = placed->sequence;
      const std::int64_t shift = placed->shift;
      const bool validation = opt.part == FramePart::validation;
      const std::int64_t b =
          (validation ? m.split.validation_begin[k] : m.split.test_begin[k]) + shift;
      const std::int64_t e = (validation ? m.split.validation_end[k] : m.split.test_end[k]) + shift;
      // In steps of q frames: predict: the first predicted frame runs from b + context; the
      // given frames are the u before it. complete: keyframes a and a + gap + 1.
      const std::int64_t context =
          opt.mode == GenerateMode::predict ? std::max<std::int64_t>(opt.test_context, u) : 0;
      const std::int64_t need =
          opt.mode == GenerateMode::predict ? context + opt.length : opt.gap + 2;
      for (std::int64_t a = b; a + (need - 1) * q < e; a += opt.test_every) {
        GenerationCase c;
        if (opt.mode == GenerateMode::predict)
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
                      opt.part == FramePart::validation ? "validation" : "held-out",
                      opt.mode == GenerateMode::predict
                          ? std::max<std::int64_t>(opt.test_context, u) + opt.length
                          : opt.gap + 2,
                      q > 1 ? fmt::format(" {} apart", q) : ""),
          opt.data);
  } else if (opt.mode == GenerateMode::predict) {
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
        throw UsageError(
            fmt::format("keyframes {} and {} are {} frames apart, not a multiple of the stride {} "
                        "the model steps by (--stride)",
                        c.frames[k - 1], c.frames[k], c.frames[k] - c.frames[k - 1], q));
    }
    c.name = fmt::format("{}-{}", d.sequences[d.sequence_of(c.frames[0])],
                         c.frames[0] - d.offsets[d.sequence_of(c.frames[0])]);
    cases.push_back(std::move(c));
  }
  return cases;
}

std::vector<Matrix> nearest_motion(const BdlstmModel& m, const GenerationData& d,
                                   const std::vector<std::int64_t>& given, int length,
                                   std::int64_t q, int neighbours) {
  const auto u = static_cast<std::int64_t>(given.size());
  const std::int64_t span = (u - 1 + length) * q + 1;
  // The training windows of that span, as d's frames (the split names the training file's).
  std::vector<std::int64_t> starts;
  for (const std::int64_t f : window_starts(m.split, span))
    for (std::size_t k = 0; k < m.split.sequences.size(); ++k)
      if (f >= m.split.train_begin[k] && f < m.split.train_end[k]) {
        if (const auto placed = place_in(m.split, k, d)) starts.push_back(f + placed->shift);
        break;
      }
  if (starts.empty())
    throw InvalidInput(fmt::format("--method nearest: the model's training part (in DATA's "
                                   "sequences) has no window of {} frames{} to match",
                                   u + length, q > 1 ? fmt::format(" {} apart", q) : ""),
                       m.split.data);
  const auto& X = d.features;
  std::vector<double> distance(starts.size());
  for (std::size_t w = 0; w < starts.size(); ++w)
    for (std::int64_t i = 0; i < u; ++i)
      distance[w] += (X.row(starts[w] + i * q) - X.row(given[static_cast<std::size_t>(i)]))
                         .template cast<double>()
                         .squaredNorm();
  std::vector<std::size_t> order(starts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto K = std::min(static_cast<std::size_t>(neighbours), order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(K), order.end(),
                    [&](std::size_t a, std::size_t b) {
                      return distance[a] < distance[b] || (distance[a] == distance[b] && a < b);
                    });
  std::vector<Matrix> out;
  for (int k = 1; k <= length; ++k) {
    Matrix change = Matrix::Zero(1, X.cols());
    for (std::size_t n = 0; n < K; ++n) {
      const std::int64_t at = starts[order[n]] + (u - 1) * q;  // the window's u-th frame
      change += X.row(at + k * q) - X.row(at);
    }
    out.push_back(X.row(given.back()) + change / static_cast<float>(K));
  }
  return out;
}

}  // namespace df::models
