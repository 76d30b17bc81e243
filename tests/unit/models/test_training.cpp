#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "models/common/training.h"

using df::models::LossTerms;
using df::models::run_training_loop;

TEST_CASE("training loop: interval means in the log, checkpoints on printing boundaries",
          "[models]") {
  std::int64_t iteration = 0;
  std::vector<double> log;
  std::vector<std::int64_t> steps, checkpoints;
  auto step = [&](std::int64_t k) -> LossTerms {
    steps.push_back(k);
    return {static_cast<double>(k), 2.0 * static_cast<double>(k)};
  };
  run_training_loop({10, 4, 3}, {"loss", "twice"}, iteration, log, step,
                    [&] { checkpoints.push_back(iteration); });
  CHECK(iteration == 10);
  CHECK(steps == std::vector<std::int64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10});
  // Rows [k, mean loss, mean twice] at 4, 8 and the last iteration 10.
  CHECK(log == std::vector<double>{4, 2.5, 5, 8, 6.5, 13, 10, 9.5, 19});
  // Multiples of 3 passed by iterations 4 and 8; none at the end (the output is written then).
  CHECK(checkpoints == std::vector<std::int64_t>{4, 8});

  // Resuming at 8 runs 9 and 10 only and logs the same last row.
  std::vector<double> resumed;
  iteration = 8;
  steps.clear();
  run_training_loop({10, 4, 3}, {"loss", "twice"}, iteration, resumed, step, [] {});
  CHECK(steps == std::vector<std::int64_t>{9, 10});
  CHECK(resumed == std::vector<double>{10, 9.5, 19});
}

TEST_CASE("training loop: a non-finite loss stops with the iteration named", "[models]") {
  std::int64_t iteration = 0;
  std::vector<double> log;
  auto step = [](std::int64_t k) -> LossTerms {
    return {k == 3 ? std::numeric_limits<double>::quiet_NaN() : 1.0};
  };
  try {
    run_training_loop({5, 1, 0}, {"loss"}, iteration, log, step, [] {});
    FAIL("no error");
  } catch (const df::Error& e) {
    CHECK(std::string(e.what()).find("diverged at iteration 3") != std::string::npos);
  }
  CHECK(iteration == 2);
}
