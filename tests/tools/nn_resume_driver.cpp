// Test driver (not installed): trains a small MLP regression with Adam on minibatches drawn
// from the RNG, checkpointing every K iterations, optionally resuming. The resume test kills
// it with SIGKILL and checks that the resumed run ends bit-identical to an uninterrupted one.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>

#include "core/tool.h"
#include "models/common/checkpoint.h"
#include "nn/layers.h"
#include "nn/train_step.h"

int main(int argc, char** argv) {
  df::Tool tool("nn_resume_driver", "Train a small MLP with checkpoints (test driver).");
  tool.with_seed(1);
  int iterations = 200, every = 50, delay_ms = 0;
  bool resume = false;
  std::string checkpoint, output;
  tool.app().add_option("--iterations", iterations);
  tool.app().add_option("--every", every);
  tool.app().add_option("--delay-ms", delay_ms, "sleep per iteration (to be killed mid-run)");
  tool.app().add_option("--checkpoint", checkpoint)->required();
  tool.app().add_flag("--resume", resume);
  tool.app().add_option("-o", output)->required();
  return tool.run(argc, argv, [&] {
    using namespace df::nn;
    using namespace df::models;  // the checkpoint files
    df::Rng init(tool.common().seed, 0);
    ParameterStore<float> store;
    Mlp<float> mlp(store, "mlp", {4, 16, 16, 1}, Activation::tanh, init);
    Adam<float> adam(store.size(), {});
    df::Rng rng(tool.common().seed, 1);  // minibatches
    std::int64_t it = 0;
    if (resume && std::filesystem::exists(checkpoint))
      it = load_checkpoint(checkpoint, store, adam, rng);
    Tape<float> tape;
    for (; it < iterations; ++it) {
      Matrix<float> x(32, 4), y(32, 1);
      for (int r = 0; r < 32; ++r) {
        float s = 0;
        for (int c = 0; c < 4; ++c) s += x(r, c) = static_cast<float>(rng.normal());
        y(r, 0) = std::sin(s);
      }
      train_step<float>(tape, store, adam, [&](Tape<float>& t, const Bound<float>& p) {
        return mse(mlp(p, t.constant(x)), t.constant(y));
      });
      if ((it + 1) % every == 0) save_checkpoint(checkpoint, store, adam, rng, it + 1);
      if (delay_ms) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    }
    save_checkpoint(output, store, adam, rng, it);
  });
}
