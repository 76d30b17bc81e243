#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/atomic_output.h"
#include "core/error.h"
#include "models/common/training.h"

using df::models::LossTerms;
using df::models::run_training_loop;
using df::models::TrainingLoop;
using df::models::TrainingProgress;

namespace {
TrainingLoop loop_of(std::int64_t iterations, int print_every, int checkpoint_every,
                     std::vector<std::string> names, std::function<LossTerms(std::int64_t)> step,
                     std::function<void()> checkpoint) {
  return {.iterations = iterations,
          .print_every = print_every,
          .checkpoint_every = checkpoint_every,
          .checkpoint_path = "c",
          .names = std::move(names),
          .step = std::move(step),
          .checkpoint = std::move(checkpoint)};
}
}  // namespace

TEST_CASE("training loop: interval means in the log, checkpoints on printing boundaries",
          "[models]") {
  TrainingProgress state;
  std::vector<std::int64_t> steps, checkpoints;
  auto step = [&](std::int64_t k) -> LossTerms {
    steps.push_back(k);
    return {static_cast<double>(k), 2.0 * static_cast<double>(k)};
  };
  run_training_loop(
      loop_of(10, 4, 3, {"loss", "twice"}, step, [&] { checkpoints.push_back(state.iteration); }),
      state);
  CHECK(state.iteration == 10);
  CHECK(steps == std::vector<std::int64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10});
  // Rows [k, mean loss, mean twice] at 4, 8 and the last iteration 10.
  CHECK(state.log == std::vector<double>{4, 2.5, 5, 8, 6.5, 13, 10, 9.5, 19});
  // Multiples of 3 passed by iterations 4 and 8; none at the end (the output is written then).
  CHECK(checkpoints == std::vector<std::int64_t>{4, 8});

  // Resuming at 8 runs 9 and 10 only and logs the same last row.
  TrainingProgress resumed;
  resumed.iteration = 8;
  steps.clear();
  run_training_loop(loop_of(10, 4, 3, {"loss", "twice"}, step, [] {}), resumed);
  CHECK(steps == std::vector<std::int64_t>{9, 10});
  CHECK(resumed.log == std::vector<double>{10, 9.5, 19});
}

TEST_CASE("training loop: a non-finite loss stops with the iteration named", "[models]") {
  TrainingProgress state;
  auto step = [](std::int64_t k) -> LossTerms {
    return {k == 3 ? std::numeric_limits<double>::quiet_NaN() : 1.0};
  };
  try {
    run_training_loop(loop_of(5, 1, 0, {"loss"}, step, [] {}), state);
    FAIL("no error");
  } catch (const df::Error& e) {
    CHECK(std::string(e.what()).find("diverged at iteration 3") != std::string::npos);
  }
  CHECK(state.iteration == 2);
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
    TrainingProgress state;
    std::vector<double> saved_unprinted;
    std::int64_t saved_iteration = -1;
    int code = 10;
    try {
      run_training_loop(loop_of(10, 4, 0, {"loss", "twice"}, step,
                                [&] {
                                  saved_iteration = state.iteration;
                                  saved_unprinted = state.unprinted;
                                }),
                        state);
    } catch (const df::Stopped& e) {
      const bool named =
          std::string(e.what()).find("SIGUSR1 after iteration 6 of 10") != std::string::npos;
      // Iterations 5 and 6 since the row at 4: count 2, sums 11 and 22.
      code = !named                                              ? 11
             : saved_iteration != 6                              ? 12
             : saved_unprinted != std::vector<double>{2, 11, 22} ? 13
             : state.log != std::vector<double>{4, 2.5, 5}       ? 14
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
  TrainingProgress state{.iteration = 6, .log = {4, 2.5, 5}, .unprinted = {2, 11, 22}};
  run_training_loop(loop_of(10, 4, 0, {"loss", "twice"}, step, [] {}), state);
  CHECK(state.log == std::vector<double>{4, 2.5, 5, 8, 6.5, 13, 10, 9.5, 19});
  CHECK(state.unprinted.empty());
}

// The driver every trainer runs: a fresh start or --resume's checkpoint, the refusal of one past
// the iteration count, prepare and validation after the start, checkpoints and the final model
// through the one save hook, the run's own checkpoint removed at the end.
TEST_CASE("trainer driver: start or resume, then the loop, the model written, the checkpoint gone",
          "[models]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / fmt::format("df-trainer-{}", getpid());
  fs::create_directories(dir);
  const std::string out = (dir / "m.h5").string(), ckpt = out + ".ckpt";
  struct Model : df::models::TrainingState<int> {};
  Model m;
  std::vector<std::string> calls;
  auto trainer = [&](std::int64_t iterations) {
    return df::models::Trainer{
        .output = out,
        .iterations = iterations,
        .initialise = [&] { calls.push_back("initialise"), m.restart(1, 7); },
        .resume =
            [&](const std::string& path) {
              calls.push_back("resume " + fs::path(path).filename().string());
              Model ck;
              ck.iteration = 4, ck.log = {4, 1, 0.5}, ck.adam = 2;
              df::models::take_training_state(m, std::move(ck));
            },
        .prepare = [&] { calls.push_back(fmt::format("prepare at {}", m.iteration)); },
        .validation =
            [&] {
              calls.push_back("validation");
              return df::models::Validation{{"v"}, [] { return LossTerms{0.5}; }};
            },
        .names = {"loss"},
        .step = [](std::int64_t) { return LossTerms{1.0}; },
        .save =
            [&](const std::string& path, bool) {
              calls.push_back(
                  fmt::format("save {} at {}", fs::path(path).filename().string(), m.iteration));
              std::ofstream(path) << m.iteration;
            },
        .finished = [&] { calls.push_back("finished"); }};
  };
  df::models::TrainingRun run;
  run.checkpoint_every = 2, run.print_every = 2;
  df::models::run_trainer(trainer(4), m, run, false);
  CHECK(calls == std::vector<std::string>{"initialise", "prepare at 0", "validation",
                                          "save m.h5.ckpt at 2", "finished", "save m.h5 at 4"});
  CHECK(m.log == std::vector<double>{2, 1, 0.5, 4, 1, 0.5});
  CHECK(m.adam == 1);
  CHECK(fs::exists(out));
  CHECK_FALSE(fs::exists(ckpt));  // its own checkpoint, removed after the model was written

  // --resume with a checkpoint there: its state, then the iterations after it.
  std::ofstream(ckpt) << 4;
  calls.clear();
  run.resume = true;
  df::models::run_trainer(trainer(6), m, run, true);
  CHECK(calls == std::vector<std::string>{"resume m.h5.ckpt", "prepare at 4", "validation",
                                          "finished", "save m.h5 at 6"});
  CHECK(m.adam == 2);
  CHECK(m.log == std::vector<double>{4, 1, 0.5, 6, 1, 0.5});

  // A checkpoint past the iteration count is refused before anything is prepared.
  std::ofstream(ckpt) << 4;
  calls.clear();
  CHECK_THROWS_WITH(df::models::run_trainer(trainer(3), m, run, true),
                    Catch::Contains("at iteration 4, past --iterations 3"));
  CHECK(calls == std::vector<std::string>{"resume m.h5.ckpt"});
  fs::remove_all(dir);
}
