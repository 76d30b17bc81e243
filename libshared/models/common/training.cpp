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

}  // namespace

void run_training_loop(const TrainingLoop& loop, TrainingProgress& state) {
  const std::vector<std::string>& names = loop.names;
  const std::vector<std::string>& evaluate_names = loop.validation.names;
  const std::function<LossTerms()>& evaluate = loop.validation.measure;
  std::int64_t& iteration = state.iteration;
  std::vector<double>& log = state.log;
  std::vector<double>& unprinted = state.unprinted;
  Interval interval(names.size(), unprinted);
  unprinted.clear();
  // The pace of the last printed interval (not since the start: a run's phases, e.g. ActGAN's
  // pre-training and GAN, differ by 50x in cost per iteration).
  auto interval_start = std::chrono::steady_clock::now();
  std::int64_t timed = 0;  // iterations run since interval_start (a resumed interval holds more)
  std::int64_t last_checkpoint = iteration;
  // Until the first loss line, a line of pace once the run has taken kFirstWord (a large model
  // may take minutes to reach its first loss line, and a silent trainer looks hung), and another
  // kSecondWord after the first iteration, measured without it: it holds the run's set-up (on a
  // large set 20 times a later iteration's time, so the first estimate runs far too long).
  constexpr double kFirstWord = 2.0, kSecondWord = 30.0;  // seconds
  const auto run_start = interval_start;
  int spoken = 0;               // pace lines so far (2: a loss line came or both were said)
  auto first_done = run_start;  // when this run's first iteration ended
  if (iteration < loop.iterations)
    log::info("training iterations {}-{}: a loss line every {}; lines of pace before the first",
              iteration + 1, loop.iterations, loop.print_every);
  while (iteration < loop.iterations) {
    const std::int64_t done = iteration + 1;  // counting this one
    const LossTerms terms = loop.step(done);
    if (!std::isfinite(terms.at(0)))
      throw Error(fmt::format("training diverged at iteration {} (loss {}); try a smaller --lr",
                              done, terms[0]));
    for (std::size_t k = 0; k < interval.sum.size(); ++k) interval.sum[k] += terms.at(k);
    ++interval.iterations;
    ++timed;
    iteration = done;  // before any checkpoint: the file must say how many iterations it holds
    const bool row_due = done % loop.print_every == 0 || done == loop.iterations;
    if (spoken < 2 && timed == 1) first_done = std::chrono::steady_clock::now();
    if (!row_due && spoken < 2) {
      const auto now = std::chrono::steady_clock::now();
      const double so_far = std::chrono::duration<double>(now - run_start).count();
      const bool second = spoken == 1 && timed > 1 &&
                          std::chrono::duration<double>(now - first_done).count() >= kSecondWord;
      if ((spoken == 0 && so_far >= kFirstWord) || second) {
        ++spoken;
        const double per = second ? std::chrono::duration<double>(now - first_done).count() /
                                        static_cast<double>(timed - 1)
                                  : so_far / static_cast<double>(timed);
        const std::int64_t next_row =
            std::min(loop.iterations, (done / loop.print_every + 1) * loop.print_every);
        log::info(
            "iteration {}/{}: {:.3g} s/iteration {}; the next loss line at iteration {} (in "
            "~{:.0f} s), {:.0f} s left in all",
            done, loop.iterations, per, second ? "since the first" : "so far", next_row,
            per * static_cast<double>(next_row - done),
            per * static_cast<double>(loop.iterations - done));
      }
    }
    if (row_due) {
      spoken = 2;
      const std::string detail =
          append_log_row(done, interval, names, evaluate_names, evaluate, log);
      const auto now = std::chrono::steady_clock::now();
      const double per =
          std::chrono::duration<double>(now - interval_start).count() / static_cast<double>(timed);
      interval_start = now;
      timed = 0;
      log::info("iteration {}/{}: {} {:.4g} ({}); {:.3f} s/iteration, {:.0f} s left", done,
                loop.iterations, names[0],
                interval.sum[0] / static_cast<double>(interval.iterations), detail, per,
                per * static_cast<double>(loop.iterations - done));
      interval = Interval(names.size(), {});
      if (loop.after_row) {
        const std::size_t width = names.size() + 1 + evaluate_names.size();
        loop.after_row(
            std::vector<double>(log.end() - static_cast<std::ptrdiff_t>(width), log.end()));
      }
      if (loop.checkpoint_every &&
          done / loop.checkpoint_every > last_checkpoint / loop.checkpoint_every &&
          done < loop.iterations) {
        last_checkpoint = done;
        loop.checkpoint();
      }
    }
    if (const int sig = stop_requested(); sig && done < loop.iterations) {
      unprinted = interval.saved();
      loop.checkpoint();
      throw Stopped(
          fmt::format("stopped by SIG{} after iteration {} of {}; checkpoint {} holds "
                      "it: run the same command with --resume to continue",
                      sigabbrev_np(sig), done, loop.iterations, loop.checkpoint_path));
    }
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
                          t.save(ckpt, true);
                          log::debug("checkpoint {} at iteration {}", ckpt, state.iteration);
                        },
                    .validation = t.validation ? t.validation() : Validation{},
                    .after_row = t.after_row};
  run_training_loop(loop, state);
  if (t.finished) t.finished();
  t.save(t.output, force);
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

void add_training_run_options(CLI::Option_group& g, TrainingRun& run) {
  g.add_option("--print-every", run.print_every, "Iterations between loss lines (and log rows)")
      ->default_val(run.print_every);
  g.add_option("--checkpoint", run.checkpoint,
               "Checkpoint file (default OUTPUT.ckpt, removed at the end; a file named here is\n"
               "kept). Any model file of this tool is a checkpoint");
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
