#include "apps/inspect_bdlstm.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <numeric>
#include <sstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "models/bdlstm/generate.h"
#include "models/bdlstm/train.h"

namespace df::apps {
using namespace df::models;
namespace {

using Matrix = nn::Matrix<float>;
using Eigen::Index;

template <class V>
std::vector<V> evenly(const std::vector<V>& all, std::size_t n) {
  if (all.size() <= n) return all;
  std::vector<V> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(all[i * all.size() / n]);
  return out;
}

// Mean KL(q(z|x) ‖ N(0, I)) per latent dimension over `frames` (nats), encoded in batches, each
// frame as at a chain's first step (with --motion-input: no motion).
std::vector<double> kl_per_dimension(const BdlstmModel& m, const Matrix& X,
                                     const std::vector<std::int64_t>& frames) {
  const auto& net = *m.net;
  std::vector<double> kl(static_cast<std::size_t>(m.config.latent), 0.0);
  nn::Tape<float> tape;
  const auto bound = net.store().bind(tape);
  const std::size_t mark = tape.size();
  for (std::size_t b = 0; b < frames.size(); b += 64) {
    const std::size_t n = std::min<std::size_t>(64, frames.size() - b);
    Matrix x(static_cast<Index>(n), X.cols());
    for (std::size_t k = 0; k < n; ++k) x.row(static_cast<Index>(k)) = X.row(frames[b + k]);
    tape.truncate(mark);
    auto [mu, logvar] = net.encode(bound, 0, tape.constant(x));
    const Matrix& M = mu.value();
    const Matrix& L = logvar.value();
    for (Index r = 0; r < M.rows(); ++r)
      for (Index j = 0; j < M.cols(); ++j) {
        const double u = M(r, j), l = L(r, j);
        kl[static_cast<std::size_t>(j)] +=
            0.5 * (u * u + std::exp(l) - l - 1) / static_cast<double>(frames.size());
      }
  }
  return kl;
}

double mean_of(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// 1. The training log's first and last rows.
void print_training_log(const std::string& path, const BdlstmModel& m) {
  const auto columns = m.log_columns();
  const std::size_t cols = columns.size();
  std::cout << fmt::format("{}: {} iterations, latent {} ({})\n", path, m.iteration,
                           m.config.latent,
                           m.config.kl ? "VAE encoder with KL" : "deterministic encoder");
  if (m.log.size() < cols) return;
  auto row = [&](std::size_t r) {
    std::string s;
    for (std::size_t k = 0; k < cols; ++k)
      s += fmt::format("{} {:.4g}  ", columns[k], m.log[r * cols + k]);
    return s;
  };
  std::cout << "  training log, first row: " << row(0)
            << "\n  training log, last row:  " << row(m.log.size() / cols - 1) << "\n";
}

// The frames of a part (training frames: those of no held-out range), in order.
std::vector<std::int64_t> frames_of_part(const BdlstmSplit& split, FramePart part) {
  std::vector<std::int64_t> frames;
  for (std::size_t s = 0; s < split.train_begin.size(); ++s) {
    const bool train = part == FramePart::train, test = part == FramePart::test;
    const std::int64_t b = train  ? split.train_begin[s]
                           : test ? split.test_begin[s]
                                  : split.validation_begin[s];
    const std::int64_t e = train  ? split.train_end[s]
                           : test ? split.test_end[s]
                                  : split.validation_end[s];
    auto outside = [](std::int64_t f, std::int64_t lo, std::int64_t hi) {
      return f < lo || f >= hi;
    };
    for (std::int64_t f = b; f < e; ++f)
      if (!train || (outside(f, split.test_begin[s], split.test_end[s]) &&
                     outside(f, split.validation_begin[s], split.validation_end[s])))
        frames.push_back(f);
  }
  return frames;
}

// 2. KL per latent dimension over the frames, printed; returned largest first.
std::vector<double> report_kl(const BdlstmModel& m, const GenerationData& d,
                              const std::vector<std::int64_t>& frames, FramePart part) {
  const std::vector<double> kl = kl_per_dimension(m, d.features, frames);
  std::vector<double> sorted = kl;
  std::sort(sorted.rbegin(), sorted.rend());
  const auto active = std::count_if(kl.begin(), kl.end(), [](double v) { return v > 0.01; });
  std::cout << fmt::format(
                   "  KL(q(z|x) || N(0,I)) over {} frames of the {} part: {:.4g} nats in all, {} "
                   "of {} dimensions above 0.01 nats; largest {:.3g}",
                   frames.size(), part, std::accumulate(kl.begin(), kl.end(), 0.0), active,
                   kl.size(),
                   fmt::join(
                       std::vector<double>(sorted.begin(), sorted.begin() + std::min<std::size_t>(
                                                                                5, sorted.size())),
                       " "))
            << (m.config.kl ? "" : " (no KL in training: the log-variance is untrained)") << "\n";
  return sorted;
}

// 3. What z carries: the same windows predicted with z = mean, prior draws, zero; zero motion.
// Each one's relative feature error per step, printed at steps 1, 5, 10 and the last.
std::vector<std::vector<double>> report_latent_probe(const BdlstmInspectOptions& opt,
                                                     const BdlstmModel& m, const GenerationData& d,
                                                     const std::vector<std::int64_t>& starts,
                                                     std::uint64_t seed) {
  const std::int64_t q = m.training.stride;
  Rng rng(seed, 7);
  const LatentInput modes[] = {LatentInput::mean, LatentInput::prior, LatentInput::zero};
  const char* names[] = {"z = encoder mean", "z ~ prior N(0, I)", "z = 0", "zero motion"};
  std::vector<std::vector<double>> errors;
  for (const auto& mode : modes)
    errors.push_back(
        probe_prediction_error(*m.net, d.features, starts, opt.initial, opt.length, q, &mode, rng));
  errors.push_back(
      probe_prediction_error(*m.net, d.features, starts, opt.initial, opt.length, q, nullptr, rng));
  std::vector<int> shown{1};  // steps in the table: 1, 5, 10 (those that exist) and the last
  for (int k : {5, 10, opt.length})
    if (k <= opt.length && k > shown.back()) shown.push_back(k);
  std::cout << fmt::format(
      "  {} windows of the {} part, {} given frames: relative feature error |X^ - X| / |X| at step "
      "{} and mean over 1..{}\n",
      starts.size(), opt.part, opt.initial, fmt::join(shown, " / "), opt.length);
  for (std::size_t k = 0; k < errors.size(); ++k) {
    std::vector<std::string> at;
    for (int step : shown)
      at.push_back(fmt::format("{:.4f}", errors[k][static_cast<std::size_t>(step - 1)]));
    std::cout << fmt::format("    {:<20} {}   mean {:.4f}\n", names[k], fmt::join(at, " / "),
                             mean_of(errors[k]));
  }
  return errors;
}

void write_inspection_tsv(const BdlstmInspectOptions& opt, const BdlstmModel& m,
                          const std::vector<double>& kl_sorted,
                          const std::vector<std::vector<double>>& errors, bool force) {
  const auto columns = m.log_columns();
  const std::size_t cols = columns.size();
  std::ostringstream out;
  out << "# kl_per_dimension: rank, nats (largest first)\n";
  for (std::size_t j = 0; j < kl_sorted.size(); ++j) out << j + 1 << "\t" << kl_sorted[j] << "\n";
  out << "\n\n# error_by_step: step, z_mean, z_prior, z_zero, zero_motion\n";
  for (int k = 0; k < opt.length; ++k) {
    out << k + 1;
    for (const auto& e : errors) out << "\t" << e[static_cast<std::size_t>(k)];
    out << "\n";
  }
  out << "\n\n# training_log: " << fmt::format("{}", fmt::join(columns, ", ")) << "\n";
  for (std::size_t r = 0; r + cols <= m.log.size(); r += cols) {
    for (std::size_t k = 0; k < cols; ++k) out << (k ? "\t" : "") << m.log[r + k];
    out << "\n";
  }
  write_text_output(opt.tsv, out.str(), force, {opt.model, opt.data});
}

}  // namespace

void inspect_bdlstm(const BdlstmInspectOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.tsv}, common.force, {opt.model, opt.data});
  if (opt.part == FramePart::all) throw UsageError("--part must be train, validation or test");
  if (opt.initial < 1 || opt.length < 1 || opt.cases < 1 || opt.max_frames < 1)
    throw UsageError("--initial, --length, --cases and --max-frames must be positive");
  const BdlstmModel m = load_bdlstm_model(opt.model);
  const GenerationData d = read_generation_data(opt.data, m);
  if (d.sequences != m.split.sequences || d.offsets.back() < m.split.train_end.back())
    throw InvalidInput(
        "is not the data the model was trained on (its sequences differ from the model's split)",
        opt.data);
  const std::int64_t q = m.training.stride;
  const std::int64_t span = static_cast<std::int64_t>(opt.initial + opt.length - 1) * q + 1;
  const auto starts =
      evenly(part_starts(m.split, opt.part, span), static_cast<std::size_t>(opt.cases));
  if (starts.empty())
    throw InvalidInput(
        fmt::format("the {} part has no window of {} frames ({} given + {} predicted, stride {})",
                    opt.part, span, opt.initial, opt.length, q),
        opt.data);

  print_training_log(opt.model, m);
  const auto frames =
      evenly(frames_of_part(m.split, opt.part), static_cast<std::size_t>(opt.max_frames));
  const auto kl_sorted = report_kl(m, d, frames, opt.part);
  const auto errors = report_latent_probe(opt, m, d, starts, common.seed);
  if (!opt.tsv.empty()) write_inspection_tsv(opt, m, kl_sorted, errors, common.force);
}

}  // namespace df::apps
