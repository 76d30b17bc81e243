#include "models/common/training.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/log.h"

namespace df::models {

void run_training_loop(const TrainingLoop& loop, const std::vector<std::string>& names,
                       std::int64_t& iteration, std::vector<double>& log,
                       const std::function<LossTerms(std::int64_t)>& step,
                       const std::function<void()>& checkpoint,
                       const std::vector<std::string>& evaluate_names,
                       const std::function<LossTerms()>& evaluate) {
  std::vector<double> sum(names.size(), 0.0);
  int in_interval = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const std::int64_t first_iteration = iteration;
  std::int64_t last_checkpoint = iteration;
  while (iteration < loop.iterations) {
    const std::int64_t done = iteration + 1;  // counting this one
    const LossTerms terms = step(done);
    if (!std::isfinite(terms.at(0)))
      throw Error(fmt::format("training diverged at iteration {} (loss {}); try a smaller --lr",
                              done, terms[0]));
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += terms.at(k);
    ++in_interval;
    iteration =
        done;  // before any checkpoint: the file must say how many iterations its state holds
    if (done % loop.print_every != 0 && done != loop.iterations) continue;
    log.push_back(static_cast<double>(done));
    std::string detail;
    for (std::size_t k = 0; k < sum.size(); ++k) {
      const double mean = sum[k] / in_interval;
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
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double per = secs / static_cast<double>(done - first_iteration);
    log::info("iteration {}/{}: {} {:.4g} ({}); {:.3f} s/iteration, {:.0f} s left", done,
              loop.iterations, names[0], sum[0] / in_interval, detail, per,
              per * static_cast<double>(loop.iterations - done));
    std::fill(sum.begin(), sum.end(), 0.0);
    in_interval = 0;
    if (loop.checkpoint_every &&
        done / loop.checkpoint_every > last_checkpoint / loop.checkpoint_every &&
        done < loop.iterations) {
      last_checkpoint = done;
      checkpoint();
    }
  }
}

void check_training_output(const std::string& output, const std::string& input, bool force) {
  std::error_code ec;
  if (std::filesystem::exists(output, ec) && !force)
    throw IOError("output exists; use --force to overwrite it", output);
  if (std::filesystem::exists(input, ec) && std::filesystem::equivalent(input, output, ec))
    throw IOError("output would overwrite the input", output);
}

}  // namespace df::models
