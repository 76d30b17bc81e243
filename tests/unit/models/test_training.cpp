#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <csignal>
#include <limits>

#include "core/atomic_output.h"
#include "core/error.h"
#include "models/common/training.h"

using df::models::LossTerms;
using df::models::run_training_loop;

TEST_CASE("training loop: interval means in the log, checkpoints on printing boundaries",
          "[models]") {
  std::int64_t iteration = 0;
  std::vector<double> log, unprinted;
  std::vector<std::int64_t> steps, checkpoints;
  auto step = [&](std::int64_t k) -> LossTerms {
    steps.push_back(k);
    return {static_cast<double>(k), 2.0 * static_cast<double>(k)};
  };
  run_training_loop({10, 4, 3, "c"}, {"loss", "twice"}, iteration, log, unprinted, step,
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
  run_training_loop({10, 4, 3, "c"}, {"loss", "twice"}, iteration, resumed, unprinted, step, [] {});
  CHECK(steps == std::vector<std::int64_t>{9, 10});
  CHECK(resumed == std::vector<double>{10, 9.5, 19});
}

TEST_CASE("training loop: a non-finite loss stops with the iteration named", "[models]") {
  std::int64_t iteration = 0;
  std::vector<double> log, unprinted;
  auto step = [](std::int64_t k) -> LossTerms {
    return {k == 3 ? std::numeric_limits<double>::quiet_NaN() : 1.0};
  };
  try {
    run_training_loop({5, 1, 0, "c"}, {"loss"}, iteration, log, unprinted, step, [] {});
    FAIL("no error");
  } catch (const df::Error& e) {
    CHECK(std::string(e.what()).find("diverged at iteration 3") != std::string::npos);
  }
  CHECK(iteration == 2);
}

// A stop request (here SIGUSR1 raised during iteration 6, between the log rows at 4 and 8) ends
// the loop after that iteration with a checkpoint that carries the unprinted interval; resuming
// from it logs exactly the rows of an uninterrupted run. The signal handler is process-wide, so
// the stopped run happens in a child process, which reports by its exit status.
TEST_CASE("training loop: a stop request checkpoints mid-interval and resumes to the same log",
          "[models]") {
  auto step = [](std::int64_t k) -> LossTerms {
    if (k == 6) raise(SIGUSR1);
    return {static_cast<double>(k), 2.0 * static_cast<double>(k)};
  };
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    df::install_stop_request_handlers();
    std::int64_t iteration = 0;
    std::vector<double> log, unprinted, saved_unprinted;
    std::int64_t saved_iteration = -1;
    int code = 10;
    try {
      run_training_loop({10, 4, 0, "c"}, {"loss", "twice"}, iteration, log, unprinted, step, [&] {
        saved_iteration = iteration;
        saved_unprinted = unprinted;
      });
    } catch (const df::Stopped& e) {
      const bool named =
          std::string(e.what()).find("SIGUSR1 after iteration 6 of 10") != std::string::npos;
      // Iterations 5 and 6 since the row at 4: count 2, sums 11 and 22.
      code = !named                                              ? 11
             : saved_iteration != 6                              ? 12
             : saved_unprinted != std::vector<double>{2, 11, 22} ? 13
             : log != std::vector<double>{4, 2.5, 5}             ? 14
                                                                 : 0;
    }
    _exit(code);
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);

  // Resuming from that checkpoint (no signal now: the parent has default handlers and step 6
  // is not repeated).
  std::int64_t iteration = 6;
  std::vector<double> log{4, 2.5, 5}, unprinted{2, 11, 22};
  run_training_loop({10, 4, 0, "c"}, {"loss", "twice"}, iteration, log, unprinted, step, [] {});
  CHECK(log == std::vector<double>{4, 2.5, 5, 8, 6.5, 13, 10, 9.5, 19});
  CHECK(unprinted.empty());
}
