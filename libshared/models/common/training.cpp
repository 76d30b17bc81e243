#include "models/common/training.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "io/h5.h"
#include "io/model_file.h"

namespace df::models {
namespace {

// The loss terms summed since the last log row.
struct Interval {
  std::vector<double> sum;
  std::int64_t iterations = 0;

  // Restored from a checkpoint's [count, sums...] (empty: at a row).
  Interval(std::size_t terms, const std::vector<double>& unprinted) : sum(terms, 0.0) {
    if (unprinted.empty()) return;
    if (unprinted.size() != terms + 1)
      throw Error(fmt::format("the checkpoint's unprinted loss terms have {} values, not {}",
                              unprinted.size(), terms + 1));
    iterations = static_cast<std::int64_t>(unprinted[0]);
    std::copy(unprinted.begin() + 1, unprinted.end(), sum.begin());
  }
  std::vector<double> saved() const {
    if (iterations == 0) return {};
    std::vector<double> v{static_cast<double>(iterations)};
    v.insert(v.end(), sum.begin(), sum.end());
    return v;
  }
};

// Appends the row [done, means..., evaluated...] to `log`; returns the printed detail.
std::string append_log_row(std::int64_t done, const Interval& interval,
                           const std::vector<std::string>& names,
                           const std::vector<std::string>& evaluate_names,
                           const std::function<LossTerms()>& evaluate, std::vector<double>& log) {
  log.push_back(static_cast<double>(done));
  std::string detail;
  for (std::size_t k = 0; k < interval.sum.size(); ++k) {
    const double mean = interval.sum[k] / static_cast<double>(interval.iterations);
    log.push_back(mean);
    if (k) detail += fmt::format("{}{} {:.4g}", k > 1 ? ", " : "", names[k], mean);
  }
  if (evaluate) {
    const LossTerms extra = evaluate();
    for (std::size_t k = 0; k < evaluate_names.size(); ++k) {
      log.push_back(extra.at(k));
      detail += fmt::format("; {} {:.4g}", evaluate_names[k], extra[k]);
    }
  }
  return detail;
}

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// Until the first loss line, a line of pace once the run has taken kFirstWord (a large model may
// take minutes to reach its first loss line, and a silent trainer looks hung), and another
// kSecondWord after the first iteration, measured without it: it holds the run's set-up (on a
// large set 20 times a later iteration's time, so the first estimate runs far too long).
class EarlyPace {
 public:
  explicit EarlyPace(Clock::time_point start) : run_start_(start), first_done_(start) {}

  // After iteration `done`, the `timed`-th of this run; no line where a loss line is due.
  void iteration_done(const TrainingLoop& loop, std::int64_t done, std::int64_t timed,
                      bool row_due) {
    if (spoken_ >= 2) return;
    if (timed == 1) first_done_ = Clock::now();
    if (row_due) return;
    const auto now = Clock::now();
    const double so_far = seconds(now - run_start_);
    const bool second = spoken_ == 1 && timed > 1 && seconds(now - first_done_) >= kSecondWord;
    if (!((spoken_ == 0 && so_far >= kFirstWord) || second)) return;
    ++spoken_;
    const double per = second ? seconds(now - first_done_) / static_cast<double>(timed - 1)
                              : so_far / static_cast<double>(timed);
    const std::int64_t next_row =
        std::min(loop.iterations, (done / loop.print_every + 1) * loop.print_every);
    log::info(
        "iteration {}/{}: {:.3g} s/iteration {}; the next loss line at iteration {} (in ~{:.0f} "
        "s), {:.0f} s left in all",
        done, loop.iterations, per, second ? "since the first" : "so far", next_row,
        per * static_cast<double>(next_row - done),
        per * static_cast<double>(loop.iterations - done));
  }
  // A loss line came: it says the pace from now on.
  void loss_line_came() { spoken_ = 2; }

 private:
  static constexpr double kFirstWord = 2.0, kSecondWord = 30.0;  // seconds
  Clock::time_point run_start_, first_done_;  // first_done_: when this run's first iteration ended
  int spoken_ = 0;                            // pace lines so far (2: a loss line came)
};

// The loss terms of iteration `done` added to the interval's sums; a loss that is not finite
// ends the run.
void add_terms(Interval& interval, const LossTerms& terms, std::int64_t done) {
  if (!std::isfinite(terms.at(0)))
    throw Error(fmt::format("training diverged at iteration {} (loss {}); try a smaller --lr", done,
                            terms[0]));
  for (std::size_t k = 0; k < interval.sum.size(); ++k) interval.sum[k] += terms.at(k);
  ++interval.iterations;
}

// The loss line of iteration `done`: the interval's row appended to the log and printed with the
// pace of the interval (`timed` iterations since `interval_start`; not since the start: a run's
// phases, e.g. ActGAN's pre-training and GAN, differ by 50x in cost per iteration); then the
// trainer's after_row hook sees the row. Returns when the pace was measured: the next interval's
// start.
Clock::time_point loss_line(const TrainingLoop& loop, TrainingProgress& state,
                            const Interval& interval, std::int64_t done,
                            Clock::time_point interval_start, std::int64_t timed) {
  const std::string detail = append_log_row(done, interval, loop.names, loop.validation.names,
                                            loop.validation.measure, state.log);
  const auto now = Clock::now();
  const double per = seconds(now - interval_start) / static_cast<double>(timed);
  log::info("iteration {}/{}: {} {:.4g} ({}); {:.3f} s/iteration, {:.0f} s left", done,
            loop.iterations, loop.names[0],
            interval.sum[0] / static_cast<double>(interval.iterations), detail, per,
            per * static_cast<double>(loop.iterations - done));
  if (loop.after_row) {
    const std::size_t width = loop.names.size() + 1 + loop.validation.names.size();
    loop.after_row(
        std::vector<double>(state.log.end() - static_cast<std::ptrdiff_t>(width), state.log.end()));
  }
  return now;
}

// A stop asked for by a signal after iteration `done`: the unprinted terms and a checkpoint kept,
// then Stopped saying how to go on.
void stop_if_asked(const TrainingLoop& loop, TrainingProgress& state, const Interval& interval,
                   std::int64_t done) {
  const int sig = stop_requested();
  if (!sig || done >= loop.iterations) return;
  state.unprinted = interval.saved();
  loop.checkpoint();
  throw Stopped(fmt::format(
      "stopped by SIG{} after iteration {} of {}; checkpoint {} holds it: run the same command "
      "with --resume to continue",
      sigabbrev_np(sig), done, loop.iterations, loop.checkpoint_path));
}

}  // namespace

void run_training_loop(const TrainingLoop& loop, TrainingProgress& state) {
  Interval interval(loop.names.size(), state.unprinted);
  state.unprinted.clear();
  auto interval_start = Clock::now();
  std::int64_t timed = 0;  // iterations run since interval_start (a resumed interval holds more)
  std::int64_t last_checkpoint = state.iteration;
  EarlyPace early(interval_start);
  if (state.iteration < loop.iterations)
    log::info("training iterations {}-{}: a loss line every {}; lines of pace before the first",
              state.iteration + 1, loop.iterations, loop.print_every);
  while (state.iteration < loop.iterations) {
    const std::int64_t done = state.iteration + 1;  // counting this one
    add_terms(interval, loop.step(done), done);
    ++timed;
    state.iteration =
        done;  // before any checkpoint: the file must say how many iterations it holds
    const bool row_due = done % loop.print_every == 0 || done == loop.iterations;
    early.iteration_done(loop, done, timed, row_due);
    if (row_due) {
      early.loss_line_came();
      interval_start = loss_line(loop, state, interval, done, interval_start, timed);
      interval = Interval(loop.names.size(), {});
      timed = 0;
      if (loop.checkpoint_every &&
          done / loop.checkpoint_every > last_checkpoint / loop.checkpoint_every &&
          done < loop.iterations) {
        last_checkpoint = done;
        loop.checkpoint();
      }
    }
    stop_if_asked(loop, state, interval, done);
  }
}

void run_trainer(const Trainer& t, TrainingProgress& state, const TrainingRun& run, bool force) {
  const std::string ckpt = run.checkpoint_path(t.output);
  if (run.resume && std::filesystem::exists(ckpt)) {
    t.resume(ckpt);
    log::info("resuming from {} at iteration {}", ckpt, state.iteration);
  } else {
    t.initialise();
  }
  if (state.iteration > t.iterations)
    throw UsageError(fmt::format("the checkpoint is at iteration {}, past {} {}", state.iteration,
                                 t.iterations_option, t.iterations));
  if (t.prepare) t.prepare();
  TrainingLoop loop{.iterations = t.iterations,
                    .print_every = run.print_every,
                    .checkpoint_every = run.checkpoint_every,
                    .checkpoint_path = ckpt,
                    .names = t.names,
                    .step = t.step,
                    .checkpoint =
                        [&] {
                          (t.save_checkpoint ? t.save_checkpoint : t.save)(ckpt, true);
                          log::debug("checkpoint {} at iteration {}", ckpt, state.iteration);
                        },
                    .validation = t.validation ? t.validation() : Validation{},
                    .after_row = t.after_row};
  run_training_loop(loop, state);
  if (t.finished) t.finished();
  t.save(t.output, force);
  if (t.save_checkpoint && !run.checkpoint.empty()) {
    t.save_checkpoint(ckpt, true);
    log::info("{} holds the final state: --resume --checkpoint {} with more iterations goes on",
              ckpt, ckpt);
  }
  run.finish(t.output);
  log::info("wrote {} ({} iterations)", t.output, state.iteration);
}

std::string TrainingRun::checkpoint_path(const std::string& output) const {
  return checkpoint.empty() ? output + ".ckpt" : checkpoint;
}

void TrainingRun::check() const {
  if (print_every < 1) throw UsageError("--print-every must be positive");
  if (checkpoint_every < 0) throw UsageError("--checkpoint-every must not be negative");
}

void TrainingRun::finish(const std::string& output) const {
  if (!checkpoint.empty()) return;
  std::error_code ec;
  std::filesystem::remove(checkpoint_path(output), ec);
}

void add_training_run_options(CLI::Option_group& g, TrainingRun& run, bool model_is_checkpoint) {
  g.add_option("--print-every", run.print_every, "Iterations between loss lines (and log rows)")
      ->default_val(run.print_every);
  g.add_option(
      "--checkpoint", run.checkpoint,
      std::string("Checkpoint file (default OUTPUT.ckpt, removed at the end; a file "
                  "named here is\n") +
          (model_is_checkpoint
               ? "kept). Any model file of this tool is a checkpoint"
               : "kept and ends holding the final state: name one to train on later). The\n"
                 "model file is not a checkpoint: it leaves out Adam's state (2/3 of the size)"));
  g.add_option("--checkpoint-every", run.checkpoint_every,
               "Iterations between checkpoints, taken at the next loss line (0 = none)")
      ->default_val(run.checkpoint_every);
  g.add_flag("--resume", run.resume,
             "Continue from the checkpoint if it exists; the result is bit-identical to an\n"
             "uninterrupted run with the same options. SIGTERM or SIGUSR1 (preemption,\n"
             "Slurm's time-limit warning) stops after the iteration in progress with a\n"
             "checkpoint and exit status 75; a second SIGTERM kills at once");
}

namespace {

// "(iteration N of its run)" of a checkpoint, or "" where it cannot be read.
std::string checkpoint_iteration(const std::string& path) {
  try {
    const h5::File f(path, h5::File::Mode::read);
    return fmt::format(" (at iteration {})", io::read_iteration(f));
  } catch (const Error&) {
    return "";
  }
}

}  // namespace

TrainingClaims claim_training_outputs(const std::string& output, const std::string& input,
                                      bool force, const TrainingRun& run) {
  const std::string ckpt = run.checkpoint_path(output);
  TrainingClaims claims{claim_output(output, force, {input}), OutputClaim(ckpt)};
  std::error_code ec;
  if (!run.resume && std::filesystem::exists(ckpt, ec)) {
    if (!force)
      throw IOError(
          fmt::format("a checkpoint of an earlier run is here{}: --resume continues it, --force "
                      "starts over and replaces it",
                      checkpoint_iteration(ckpt)),
          ckpt);
    log::warn("starting over (--force without --resume): the checkpoint {}{} will be replaced",
              ckpt, checkpoint_iteration(ckpt));
  }
  return claims;
}

}  // namespace df::models
