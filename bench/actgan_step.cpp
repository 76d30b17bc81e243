// Benchmark of ActGAN's training iterations at the shapes of the PyTorch peer
// ../shared/peers/torch/actgan.py: poses of 60 values, clips of 50 frames, 10 classes, batch 32,
// noise 64, latent 12, LSTMs of 256, FC 1024;
//   gan       one iteration of Algorithm 1: 1 discriminator step + 2 generator/classifier steps
//   gan-all   the same with the authors' discriminator (--disc-input motion --disc-pool all: frames
//             and differences, every step's BiLSTM outputs to its head; the peer's pool=concat
//             case, whose classifier reads every step too, ours its last states)
//   pretrain  one WGAN-GP iteration of the frame decoder: 5 critic steps + 1 decoder step (64
//   poses)
// on 64 random clips (the peer's inputs are random too).
//   bench_actgan [--case gan|gan-all|pretrain] [--threads N] [--iters 5]
#include <cstdio>
#include <memory>

#include "core/tool.h"
#include "models/actgan/train.h"
#include "profile.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_actgan", "Time one ActGAN training iteration (see bench/run.sh).");
  std::string which = "gan";
  int iters = 5, warmup = 1;
  tool.app().add_option("--case", which)->check(CLI::IsMember({"gan", "gan-all", "pretrain"}));
  tool.app().add_option("--iters", iters, "Timed iterations")->default_val(iters);
  tool.app().add_option("--warmup", warmup, "Untimed iterations first")->default_val(warmup);
  df::bench::ProfileOptions profile;
  profile.add_to(tool.app());
  return tool.run(argc, argv, [&] {
    df::models::ActganModel m;
    m.config.pose = 60;
    m.config.classes = 10;
    m.length = 50;
    if (which == "gan-all") {
      m.config.disc_input = df::models::DiscInput::motion;
      m.config.disc_pool = df::models::DiscPool::all;
    }
    m.initialize();
    df::models::ActionClips clips;
    clips.length = 50;
    clips.pose = 60;
    df::Rng rng(9);
    for (int c = 0; c < 64; ++c) {
      clips.labels.push_back(c % 10);
      for (int k = 0; k < 50 * 60; ++k) clips.frames.push_back(static_cast<float>(rng.normal()));
    }
    auto tape = std::make_unique<df::nn::Tape<float>>();
    auto step = [&] {
      if (which == "pretrain")
        df::models::actgan_pretrain_iteration(m, clips, *tape);
      else
        df::models::actgan_gan_iteration(m, clips, *tape);
    };
    const auto t = df::bench::time_iterations(warmup, iters, step);
    const std::size_t params = m.gen->store().size() + m.discriminator_store().size() +
                               m.cls->store().size() +
                               (which == "pretrain" ? m.critic->store().size() : 0);
    const char* label = which == "gan"       ? "ActGAN 1D+2G (B 32, T 50)"
                        : which == "gan-all" ? "ActGAN 1D+2G, authors' discriminator (B 32, T 50)"
                                             : "ActGAN WGAN-GP 5C+1G (B 64)";
    std::printf("| %s | %zu | %.1f | %.1f |\n", label, params, t.median_ms, t.min_ms);
    if (profile.steps > 0)
      df::bench::print_profile(
          label, profile.steps,
          [&] {
            tape = std::make_unique<df::nn::Tape<float>>();  // made while profiling is on
            step();
          },
          profile.limits);
  });
}
