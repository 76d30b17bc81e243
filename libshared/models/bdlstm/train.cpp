#include "models/bdlstm/train.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/log.h"
#include "core/rng.h"
#include "io/acap_file.h"
#include "models/bdlstm/chain.h"
#include "models/bdlstm/settings.h"
#include "models/common/training.h"
#include "nn/train_step.h"

namespace df::models {
namespace {

// Refuses to resume a checkpoint made with other settings (the result would be neither run).
void check_resumable(const BdlstmModel& ck, const BdlstmModel& want, const std::string& path) {
  require_same_settings(view(bdlstm_settings(), ck.config, ck.training),
                        view(bdlstm_settings(), want.config, want.training), path);
  require_same_setting("vertices", ck.tmpl.vertices.rows(), want.tmpl.vertices.rows(), path);
  if (ck.split.train_begin != want.split.train_begin ||
      ck.split.train_end != want.split.train_end || ck.split.test_begin != want.split.test_begin ||
      ck.split.test_end != want.split.test_end)
    throw InvalidInput("checkpoint was trained on other data (its train/test split differs)", path);
}

// The error of predicting a part's windows from --teacher-frames given frames (as the pipelines'
// gen-bdlstm --initial) with z = the encoder's mean, relative to zero motion's error on the same
// frames (< 1: ahead of it): the windows of up to kValidationSteps predicted frames that fit in
// the part's ranges, and zero motion's error there.
struct PartProbe {
  std::vector<std::int64_t> starts;
  int given = 1, length = 0;
  double zero_motion = 0;
};
// The mean relative feature error over the windows of a probe (latent nullptr: zero motion's).
double mean_error(const BdlstmModel& m, const nn::Matrix<float>& data, const PartProbe& p,
                  const LatentInput* latent) {
  Rng none;  // z = the mean draws nothing
  const std::vector<double> e = probe_prediction_error(*m.net, data, p.starts, p.given, p.length,
                                                       m.training.stride, latent, none);
  return std::accumulate(e.begin(), e.end(), 0.0) / static_cast<double>(e.size());
}
// The frames a probe window of --teacher-frames given and `length` predicted frames spans.
std::int64_t probe_span(const BdlstmTraining& t, int length) {
  return static_cast<std::int64_t>(t.teacher_frames + length - 1) * t.stride + 1;
}
PartProbe probe_part(const BdlstmModel& m, const nn::Matrix<float>& data,
                     const std::vector<std::int64_t>& begin, const std::vector<std::int64_t>& end,
                     const char* what, const char* option) {
  PartProbe p;
  p.given = m.training.teacher_frames;
  const std::int64_t q = m.training.stride;
  int length = kValidationSteps;
  for (; length >= 1 && p.starts.empty(); --length)
    p.starts = range_starts(begin, end, probe_span(m.training, length));
  p.length = length + 1;
  if (p.starts.empty())
    throw InvalidInput(fmt::format("the {} parts are too short for {} given frames and one "
                                   "predicted (stride {}): raise {}",
                                   what, p.given, q, option),
                       m.split.data);
  p.zero_motion = mean_error(m, data, p, nullptr);
  log::info(
      "{}: {} windows of {} given + {} predicted frames; zero motion's relative feature error "
      "there {:.4g} (the log's {} column is the network's error / this)",
      what, p.starts.size(), p.given, p.length, p.zero_motion, what);
  return p;
}

// A part's measure: the network's error on its windows / zero motion's.
std::function<double()> part_measure(const BdlstmModel& m, const nn::Matrix<float>& data,
                                     PartProbe p) {
  return [&m, &data, p = std::move(p)] {
    const LatentInput mean = LatentInput::mean;
    return mean_error(m, data, p, &mean) / std::max(p.zero_motion, 1e-12);
  };
}

// The log's validation and stopping columns, each when its part exists; `stopping` gets the
// stopping part's measure (empty without one).
Validation part_evaluation(const BdlstmModel& m, const nn::Matrix<float>& data,
                           std::function<double()>& stopping) {
  std::vector<std::function<double()>> measures;
  Validation v;
  if (m.training.validation_fraction > 0) {
    measures.push_back(
        part_measure(m, data,
                     probe_part(m, data, m.split.validation_begin, m.split.validation_end,
                                "validation", "--validation-fraction")));
    v.names.push_back("validation");
  }
  if (m.training.stopping_fraction > 0) {
    stopping =
        part_measure(m, data,
                     probe_part(m, data, m.split.stopping_begin, m.split.stopping_end, "stopping",
                                "--stopping-fraction (or 0: keep the last weights)"));
    measures.push_back(stopping);
    v.names.push_back("stopping");
  }
  if (measures.empty()) return {};
  v.measure = [measures]() -> LossTerms {
    LossTerms out;
    for (const auto& measure : measures) out.push_back(measure());
    return out;
  };
  return v;
}

// The first frames where a part of n frames fits in the last sequence's training frames, clear
// of its parts carved so far (none when n is 0).
std::vector<std::int64_t> clear_places(const BdlstmSplit& split, std::int64_t n) {
  std::vector<std::int64_t> places;
  if (n > 0)
    for (const std::int64_t v : window_starts(split, n))
      if (v >= split.train_begin.back()) places.push_back(v);
  return places;
}

// Where the stopping part goes: at an end of a stretch of free training frames (beside the
// held-out or validation part, or at an end of the training frames; inside a stretch it would
// cut it in two), in the stretch that leaves the longest one whole, so long windows still fit.
std::vector<std::int64_t> places_keeping_longest_run(const BdlstmSplit& split, std::int64_t n) {
  if (n <= 0) return {};
  // The sequence's free stretches (its clear places of one frame, grouped), the two longest.
  struct Run {
    std::int64_t begin, end;
  };
  std::vector<Run> runs;
  for (const std::int64_t f : clear_places(split, 1))
    if (!runs.empty() && runs.back().end == f)
      ++runs.back().end;
    else
      runs.push_back({f, f + 1});
  std::int64_t first = 0, second = 0;
  for (const Run& r : runs) {
    const std::int64_t len = r.end - r.begin;
    if (len > first)
      second = first, first = len;
    else if (len > second)
      second = len;
  }
  // A part at either end of run r leaves len − n of it and every other run whole.
  std::vector<std::int64_t> best;
  std::int64_t longest = -1;
  for (const Run& r : runs) {
    const std::int64_t len = r.end - r.begin;
    if (len < n) continue;
    const std::int64_t left = std::max(len == first ? second : first, len - n);
    if (left > longest) best.clear(), longest = left;
    if (left < longest) continue;
    best.push_back(r.begin);
    if (r.end - n != r.begin) best.push_back(r.end - n);
  }
  return best;
}

}  // namespace

void split_sequences(const std::vector<std::int64_t>& offsets, double fraction, TestPart part,
                     std::uint64_t seed, BdlstmSplit& split, double validation_fraction,
                     double stopping_fraction) {
  if (!(fraction >= 0 && fraction < 1)) throw UsageError("--test-fraction must be in [0, 1)");
  if (!(validation_fraction >= 0 && stopping_fraction >= 0 &&
        fraction + validation_fraction + stopping_fraction < 1))
    throw UsageError(
        "--validation-fraction and --stopping-fraction must be at least 0 and leave training "
        "frames beside --test-fraction");
  Rng rng(seed, 0x5e9117);  // its own stream: the placement does not shift the training draws
  Rng validation_rng(seed, 0x7a1);  // and the validation part's does not move the test part
  Rng stopping_rng(seed, 0x5709);   // nor the stopping part's the other two
  for (std::size_t s = 0; s + 1 < offsets.size(); ++s) {
    const std::int64_t b = offsets[s], e = offsets[s + 1];
    const auto n_test =
        static_cast<std::int64_t>(std::llround(fraction * static_cast<double>(e - b)));
    if (part == TestPart::end) {
      split.train_begin.push_back(b), split.train_end.push_back(e - n_test);
      split.test_begin.push_back(e - n_test), split.test_end.push_back(e);
    } else if (part == TestPart::start) {
      split.test_begin.push_back(b), split.test_end.push_back(b + n_test);
      split.train_begin.push_back(b + n_test), split.train_end.push_back(e);
    } else {  // inside: the training part is the sequence minus the held-out part
      const std::int64_t room = e - b - n_test;
      const std::int64_t at =
          part == TestPart::middle
              ? room / 2
              : static_cast<std::int64_t>(rng.below(static_cast<std::uint64_t>(room + 1)));
      split.train_begin.push_back(b), split.train_end.push_back(e);
      split.test_begin.push_back(b + at), split.test_end.push_back(b + at + n_test);
    }
    // The validation part, then the stopping part: a contiguous stretch of this sequence's
    // training frames clear of the parts carved before (window_starts' rule: a part not yet
    // carved for this sequence holds nothing), drawn uniformly among `places`.
    const auto carve = [&](std::int64_t n, std::vector<std::int64_t> places, Rng& part_rng,
                           const char* what, std::vector<std::int64_t>& begin,
                           std::vector<std::int64_t>& end) {
      if (n > 0 && places.empty())
        throw InvalidInput(fmt::format(
            "sequence {} has no {} contiguous training frames for the {} part", s, n, what));
      const std::int64_t v =
          places.empty() ? split.train_begin.back()
                         : places[part_rng.below(static_cast<std::uint64_t>(places.size()))];
      begin.push_back(v), end.push_back(v + n);
    };
    const auto frames = [&](double part_fraction) {
      return static_cast<std::int64_t>(std::llround(part_fraction * static_cast<double>(e - b)));
    };
    const std::int64_t n_validation = frames(validation_fraction);
    carve(n_validation, clear_places(split, n_validation), validation_rng, "validation",
          split.validation_begin, split.validation_end);
    const std::int64_t n_stopping = frames(stopping_fraction);
    carve(n_stopping, places_keeping_longest_run(split, n_stopping), stopping_rng, "stopping",
          split.stopping_begin, split.stopping_end);
  }
}

std::vector<std::int64_t> window_starts(const BdlstmSplit& split, std::int64_t span) {
  // A window from f is clear of part s's range [b, e) (empty when absent).
  auto clear_of = [&](std::int64_t f, const std::vector<std::int64_t>& b,
                      const std::vector<std::int64_t>& e, std::size_t s) {
    return b.size() <= s || b[s] >= e[s] || f + span <= b[s] || f >= e[s];
  };
  std::vector<std::int64_t> starts;
  for (std::size_t s = 0; s < split.train_begin.size(); ++s)
    for (std::int64_t f = split.train_begin[s]; f + span <= split.train_end[s]; ++f)
      if (clear_of(f, split.test_begin, split.test_end, s) &&
          clear_of(f, split.validation_begin, split.validation_end, s) &&
          clear_of(f, split.stopping_begin, split.stopping_end, s))
        starts.push_back(f);
  return starts;
}

void play_window(const nn::Matrix<float>& data, std::int64_t first, int stride, double speed,
                 std::vector<nn::Matrix<float>>& window, Eigen::Index row) {
  for (std::size_t t = 0; t < window.size(); ++t) {
    const double at = static_cast<double>(t) * stride * speed;
    const auto whole = static_cast<std::int64_t>(std::floor(at));
    const auto part = static_cast<float>(at - static_cast<double>(whole));
    auto out = window[t].row(row);
    out = data.row(first + whole);
    if (part > 0) out += part * (data.row(first + whole + 1) - data.row(first + whole));
  }
}

std::vector<std::int64_t> range_starts(const std::vector<std::int64_t>& begin,
                                       const std::vector<std::int64_t>& end, std::int64_t span) {
  std::vector<std::int64_t> starts;
  for (std::size_t s = 0; s < begin.size(); ++s)
    for (std::int64_t f = begin[s]; f + span <= end[s]; ++f) starts.push_back(f);
  return starts;
}

std::vector<std::int64_t> part_starts(const BdlstmSplit& split, FramePart part, std::int64_t span) {
  if (part == FramePart::train) return window_starts(split, span);
  return part == FramePart::test ? range_starts(split.test_begin, split.test_end, span)
                                 : range_starts(split.validation_begin, split.validation_end, span);
}

bool latent_collapsed(double kl_per_frame, double recon, double first_recon, double threshold) {
  return kl_per_frame < threshold && !(recon < 0.9 * first_recon);
}

namespace {
void warn_collapse(const BdlstmModel& m, double first_recon, double recon) {
  log::warn(
      "the latent has collapsed: {:.3g} nats per frame (below --collapse-threshold {}) and the "
      "reconstruction has not improved ({:.4g} -> {:.4g}), so the model predicts what the prior "
      "does (little or no motion). Train with the remedies (the defaults: --kl-warmup 500 "
      "--kl-free-bits 0.1 --l2-scope weights --l2-weight 0.125 --decoder-init small "
      "--motion-input; not --paper-form) and see what z carries with inspect-bdlstm MODEL DATA",
      m.kl_per_frame, m.training.collapse_threshold, first_recon, recon);
}
}  // namespace

void apply_learning_defaults(BdlstmConfig& net, BdlstmTraining& training) {
  training.kl_warmup = 500;
  net.free_bits = 0.1;
  net.l2_scope = L2Scope::weights;
  net.l2_weight = 0.125;
  net.decoder_init = DecoderInit::small;
  net.motion_input = true;
  training.speeds = {0, 0.5, 1, 1.5};  // the pace is read off the given frames (issue 67)
  training.stopping_fraction = 0.1;    // the iteration count chosen on unseen frames (issue 67),
  training.stopping_every = 25;        // checked often enough to catch a model before it drifts
}

void apply_paper_form(BdlstmConfig& net, BdlstmTraining& training) {
  training.kl_warmup = 0;
  net.free_bits = 0;
  net.l2_scope = L2Scope::all;
  net.l2_weight = 1;
  net.decoder_init = DecoderInit::zero;
  net.carry = 0;
  net.carry_fade = 1;
  net.motion_input = false;
  training.speeds = {1};
  training.stopping_fraction = 0;
  training.stopping_every = 0;
}

void check_bdlstm_options(const BdlstmTrainOptions& opt) {
  check_ranges(view(bdlstm_settings(), opt.net, opt.training));
  opt.run.check();
  if (opt.training.teacher_frames >= opt.training.window)
    throw UsageError("--teacher-frames must be smaller than --window");
  if (!(opt.training.collapse_threshold >= 0))
    throw UsageError("--collapse-threshold must not be negative");
  if (opt.training.speeds.empty())
    throw UsageError("--speeds needs one or more speeds (1 = the data's own pace)");
}

namespace {

// The frames a training window spans at the fastest of --speeds (every start leaves room for
// any speed drawn).
std::int64_t window_span(const BdlstmTraining& t) {
  const double fastest = *std::max_element(t.speeds.begin(), t.speeds.end());
  return static_cast<std::int64_t>(
             std::ceil(static_cast<double>(t.window - 1) * t.stride * fastest - 1e-9)) +
         1;
}

// Whether a split's stopping part serves: its windows hold the given frames and one predicted
// frame, and training windows remain beside it.
bool stopping_part_fits(const BdlstmModel& m) {
  return !range_starts(m.split.stopping_begin, m.split.stopping_end, probe_span(m.training, 1))
              .empty() &&
         !window_starts(m.split, window_span(m.training)).empty();
}

// Whether training windows fit beside the held parts, played at speeds up to `fastest`.
bool windows_fit_at(const BdlstmModel& m, double fastest) {
  BdlstmTraining t = m.training;
  t.speeds = {fastest};
  return !window_starts(m.split, window_span(t)).empty();
}

// The default's stopping part on sequences too short for it: none (one asked for with
// --stopping-fraction is an error instead, in training_windows). `split` splits m's sequences.
// Whether the part was dropped.
bool fit_default_stopping(BdlstmModel& m, const std::function<void()>& split) {
  try {
    split();
    if (stopping_part_fits(m)) return false;
  } catch (const InvalidInput&) {
  }
  m.training.stopping_fraction = 0;
  m.training.stopping_every = 0;
  split();
  return true;
}

// The default's speeds on sequences too short for a window at the fastest: the speeds whose
// windows fit, said, as long as the data's own pace does (else the window's error names the
// remedies). Speeds asked for with --speeds are never dropped.
void fit_default_speeds(BdlstmModel& m) {
  std::vector<double>& speeds = m.training.speeds;
  const double fastest = *std::max_element(speeds.begin(), speeds.end());
  if (windows_fit_at(m, fastest) || !windows_fit_at(m, 1)) return;
  std::erase_if(speeds, [&](double s) { return !windows_fit_at(m, s); });
  log::warn(
      "the sequences are too short for windows of {} frames played at speed {} (the "
      "default's fastest): training at speeds {} (--speeds says which and silences this)",
      m.training.window, fastest, fmt::join(speeds, ","));
}

// The model to train as the options and the data describe it: settings, template,
// normalization, the split of every sequence (no weights yet).
BdlstmModel describe_model(const BdlstmTrainOptions& opt, const CommonOptions& common,
                           const io::AcapReader& in) {
  BdlstmModel m;
  m.config = opt.net;
  m.training = opt.training;
  m.training.seed = common.seed;
  m.history = in.history();
  m.tmpl = in.read_template();
  m.normalization = in.normalization();
  const auto split = [&] {
    m.split = BdlstmSplit{};
    m.split.data = opt.input;
    m.split.sequences = in.sequence_names();
    split_sequences(in.offsets(), m.training.test_fraction, m.training.test_part, common.seed,
                    m.split, m.training.validation_fraction, m.training.stopping_fraction);
  };
  const double asked = m.training.stopping_fraction;
  bool dropped = false;
  if (opt.stopping_by_default && asked > 0)
    dropped = fit_default_stopping(m, split);
  else
    split();
  if (opt.speeds_by_default) fit_default_speeds(m);
  // Said where training goes on; else the window's error says what to change.
  if (dropped && !window_starts(m.split, window_span(m.training)).empty())
    log::warn(
        "the sequences are too short for early stopping's part ({} of each sequence, carved "
        "out of the training frames): training without it, so the model keeps the last "
        "iteration's weights (--stopping-fraction 0 says so and silences this)",
        asked);
  return m;
}

// Windows: every start in a training part that leaves room for the whole window; none is an
// InvalidInput that names the longest run of training frames there is.
std::vector<std::int64_t> training_windows(const BdlstmModel& m, const std::string& input) {
  const std::int64_t span = window_span(m.training);
  std::vector<std::int64_t> starts = window_starts(m.split, span);
  if (!starts.empty()) return starts;
  // The longest run of training frames clear of every held part: the widest window that fits.
  std::int64_t longest = 0;
  while (!window_starts(m.split, longest + 1).empty()) ++longest;
  // What would make room: the options in use that take frames or widen the window.
  const bool speeds = m.training.speeds != std::vector<double>{1};
  std::vector<std::string> remedies = {"--window", "--stride"};
  if (speeds) remedies.emplace_back("--speeds");
  remedies.emplace_back("--test-fraction");
  if (m.training.validation_fraction > 0) remedies.emplace_back("--validation-fraction");
  if (m.training.stopping_fraction > 0) remedies.emplace_back("--stopping-fraction");
  const std::string last = remedies.back();
  remedies.pop_back();
  throw InvalidInput(
      fmt::format("no sequence has a training part of {} frames (window {}, stride {}{}); the "
                  "longest has {}: use a smaller {} or {}",
                  span, m.training.window, m.training.stride,
                  speeds ? ", the fastest of --speeds" : "", longest, fmt::join(remedies, ", "),
                  last),
      input);
}

// Row b of the batch: a window from a random start, at a speed drawn from --speeds (no draw at
// the data's own pace alone).
void fill_window(BdlstmModel& m, const nn::Matrix<float>& data,
                 const std::vector<std::int64_t>& starts, int b,
                 std::vector<nn::Matrix<float>>& window) {
  const std::int64_t first = starts[m.rng.below(starts.size())];
  const std::vector<double>& speeds = m.training.speeds;
  const double speed = speeds.size() == 1 ? speeds[0] : speeds[m.rng.below(speeds.size())];
  play_window(data, first, m.training.stride, speed, window, b);
}

// The motion input's scale: 1 / the RMS, per feature, of the change from a training frame to the
// next one a stride on (pairs clear of the test and validation parts); 1 for still frames.
double motion_scale(const BdlstmModel& m, const nn::Matrix<float>& data) {
  const std::int64_t q = m.training.stride;
  double sum = 0;
  std::int64_t pairs = 0;
  for (const std::int64_t f : window_starts(m.split, q + 1)) {
    sum += (data.row(f + q) - data.row(f)).cast<double>().squaredNorm();
    ++pairs;
  }
  const double rms = pairs ? std::sqrt(sum / static_cast<double>(pairs * data.cols())) : 0;
  return rms > 0 ? 1 / rms : 1;
}

// --resume: the checkpoint's weights, training state and the collapse check's verdict.
void resume_from(BdlstmModel& m, const std::string& ckpt) {
  BdlstmModel ck = load_bdlstm_model(ckpt);
  if (!ck.optimizer_state)
    throw InvalidInput(
        "is a finished model file, which leaves out Adam's state: training goes on only from a "
        "checkpoint (one named with --checkpoint FILE is kept, with the final state)",
        ckpt);
  check_resumable(ck, m, ckpt);
  m.config.motion_scale = ck.config.motion_scale;  // the scale its weights were trained with
  m.net = std::move(ck.net);
  // The last check's verdict (a stop between loss lines keeps no partial KL sum: the next line's
  // KL per frame then covers the iterations after the resume).
  m.kl_per_frame = ck.kl_per_frame;
  m.latent_collapsed = ck.latent_collapsed;
  m.best_weights = std::move(ck.best_weights);  // early stopping's kept weights so far
  m.best_iteration = ck.best_iteration;
  m.best_stopping = ck.best_stopping;
  take_training_state(m, std::move(ck));
}

}  // namespace

BdlstmTrainer::BdlstmTrainer(const BdlstmTrainOptions& opt, const CommonOptions& common,
                             const io::AcapReader& in, nn::Matrix<float> features)
    : opt_(opt),
      m_(describe_model(opt, common, in)),
      starts_(training_windows(m_, opt.input)),
      data_(std::move(features)),
      window_(static_cast<std::size_t>(m_.training.window),
              nn::Matrix<float>(m_.training.batch, data_.cols())) {
  if (m_.config.motion_input) m_.config.motion_scale = motion_scale(m_, data_);
}

// One iteration: a batch of windows and the number of teacher frames drawn with the model's RNG,
// the KL weight of the warm-up, one Adam step.
LossTerms BdlstmTrainer::step(std::int64_t done) {
  if (stopping_ && m_.training.stopping_untrained && done == 1) {  // a fresh run's first step
    const double untrained = stopping_();
    log::info("early stopping: the untrained network's stopping error {:.4g} (kept unless beaten)",
              untrained);
    consider_weights(0, untrained);
  }
  for (int b = 0; b < m_.training.batch; ++b) fill_window(m_, data_, starts_, b, window_);
  const int given = m_.training.teacher_frames > 1
                        ? 1 + static_cast<int>(m_.rng.below(
                                  static_cast<std::uint64_t>(m_.training.teacher_frames)))
                        : 1;
  const float kl_weight =
      m_.training.kl_warmup > 0
          ? static_cast<float>(std::min(
                1.0, static_cast<double>(done) / static_cast<double>(m_.training.kl_warmup)))
          : 1.0f;
  BdlstmLossTerms terms;
  nn::train_step<float>(tape_, m_.net->store(), *m_.adam,
                        [&](nn::Tape<float>& t, const nn::Bound<float>& p) {
                          return m_.net->loss(t, p, window_, m_.rng, &terms, given, kl_weight);
                        });
  kl_nats_ += terms.kl_per_frame, ++kl_steps_;
  if (stopping_ && m_.training.stopping_every > 0 && done % m_.training.stopping_every == 0)
    consider_weights(done, stopping_());
  return {terms.total, terms.recon, terms.bidir, terms.kl, terms.l2};
}

// The collapse check at every loss line (the KL per frame of the iterations since the last),
// against the first line's reconstruction (the row is already in the log: log[2] is the first
// row's recon); not before the KL warm-up has ended, nor at the first line.
void BdlstmTrainer::check_collapse(const std::vector<double>& row) {
  if (!m_.config.kl || kl_steps_ == 0) return;
  m_.kl_per_frame = kl_nats_ / static_cast<double>(kl_steps_);
  kl_nats_ = 0, kl_steps_ = 0;
  const std::size_t width = m_.log_columns().size();
  const bool after_warmup = static_cast<std::int64_t>(row[0]) > m_.training.kl_warmup;
  m_.latent_collapsed =
      after_warmup && m_.log.size() > width &&
      latent_collapsed(m_.kl_per_frame, row[2], m_.log[2], m_.training.collapse_threshold);
  if (m_.latent_collapsed) warn_collapse(m_, m_.log[2], row[2]);
}

// Early stopping (--stopping-fraction): the weights with the lowest stopping error so far are
// kept, checked at every loss line (the row's last column) and every --stopping-every
// iterations; the first check's always are.
void BdlstmTrainer::consider_weights(std::int64_t iteration, double error) {
  if (m_.best_weights.size() > 0 && !(error < m_.best_stopping)) return;
  m_.best_weights = m_.net->store().values();
  m_.best_iteration = iteration;
  m_.best_stopping = error;
}
void BdlstmTrainer::keep_best(const std::vector<double>& row) {
  if (m_.training.stopping_fraction <= 0) return;
  const auto iteration = static_cast<std::int64_t>(row[0]);
  // A line on a --stopping-every iteration was checked by step() already (the same weights).
  if (m_.training.stopping_every > 0 && iteration % m_.training.stopping_every == 0) return;
  consider_weights(iteration, row.back());
}

// The model file holds the kept weights (early stopping) in place of the last ones; a checkpoint
// holds the last ones and the kept ones beside them.
void BdlstmTrainer::save(const std::string& path, bool force, BdlstmFile kind) {
  const bool swap = kind == BdlstmFile::model && m_.best_weights.size() > 0;
  if (swap) m_.net->store().values().swap(m_.best_weights);
  try {
    save_bdlstm_model(path, m_, {opt_.input}, force, kind);
  } catch (...) {
    if (swap) m_.net->store().values().swap(m_.best_weights);
    throw;
  }
  if (swap) m_.net->store().values().swap(m_.best_weights);
}

Trainer BdlstmTrainer::hooks() {
  const auto save = [this](BdlstmFile kind) {
    return [this, kind](const std::string& path, bool force) { this->save(path, force, kind); };
  };
  return {
      .output = opt_.output,
      .iterations = m_.training.iterations,
      .initialise = [this] { m_.initialize(); },
      .resume = [this](const std::string& ckpt) { resume_from(m_, ckpt); },
      .prepare =
          [this] {
            log::info(
                "{}: {} frames of {} vertices in {} sequences; training on {} window starts ({} "
                "frames, stride {}), {} parameters, {} directions",
                opt_.input, data_.rows(), m_.tmpl.vertices.rows(), m_.split.sequences.size(),
                starts_.size(), m_.training.window, m_.training.stride, m_.net->store().size(),
                m_.config.directions);
          },
      .validation = [this] { return part_evaluation(m_, data_, stopping_); },
      .names = {"loss", "recon", "bidir", "kl", "l2"},
      .step = [this](std::int64_t done) { return step(done); },
      .after_row =
          [this](const std::vector<double>& row) {
            check_collapse(row);
            keep_best(row);
          },
      .save = save(BdlstmFile::model),
      .save_checkpoint = save(BdlstmFile::checkpoint),
      .finished =
          [this] {
            const std::size_t width = m_.log_columns().size();
            if (m_.latent_collapsed)
              warn_collapse(m_, m_.log[2], m_.log[m_.log.size() - width + 2]);
            if (m_.best_weights.size() == 0) return;
            log::info(
                "early stopping: the model file keeps the weights of iteration {} (stopping "
                "error {:.4g} of zero motion's; at the last iteration, {}: {:.4g})",
                m_.best_iteration, m_.best_stopping, m_.iteration, m_.log.back());
            if (!(m_.best_stopping < 1))
              log::warn(
                  "early stopping: on the stopping part the network was never ahead of zero "
                  "motion (at best {:.4g} of its error, iteration {}): what the training frames "
                  "taught does not carry to frames it did not see, and the kept weights predict "
                  "little motion. gen-bdlstm --method nearest shows whether the training frames "
                  "hold such motion at all (docs/bdlstm.md)",
                  m_.best_stopping, m_.best_iteration);
          }};
}

}  // namespace df::models
