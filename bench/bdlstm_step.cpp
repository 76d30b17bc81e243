// Benchmark of one full BD-LSTM training iteration (forward + backward + Adam) at the shapes of
// the PyTorch peer ../shared/peers/torch/bdlstm.py: 8 windows of 32 frames of a mesh's 9-d
// ACAP-like features drawn from U(-0.95, 0.95), the paper's network (3 mesh convs, latent 128,
// LSTM 3 x 128, mirrored decoder), both chains free-running 31 steps, loss eq. 3-5.
//   bench_bdlstm --mesh pcow/1.obj [--threads N] [--iters 10] [--warmup 2] [--profile N]
#include <cstdio>
#include <memory>

#include "core/tool.h"
#include "geometry/mesh_topology.h"
#include "io/mesh_io.h"
#include "models/bdlstm/network.h"
#include "nn/train_step.h"
#include "profile.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_bdlstm", "Time one BD-LSTM training iteration (see bench/run.sh).");
  std::string mesh_path;
  int iters = 10, warmup = 2, batch = 8, window = 32;
  tool.app()
      .add_option("--mesh", mesh_path, "Template mesh (the peer uses pcow/1.obj)")
      ->required();
  tool.app().add_option("--iters", iters, "Timed iterations")->default_val(iters);
  tool.app().add_option("--warmup", warmup, "Untimed iterations first")->default_val(warmup);
  tool.app().add_option("--batch", batch)->default_val(batch);
  tool.app().add_option("--window", window)->default_val(window);
  df::bench::ProfileOptions profile;
  profile.add_to(tool.app());
  return tool.run(argc, argv, [&] {
    const df::Mesh m = df::io::read_mesh(mesh_path);
    const int V = static_cast<int>(m.vertices.rows());
    const auto topo = df::geometry::mesh_topology(m.faces, V);
    df::models::BdlstmNet<float> net({}, V, topo.edges, 0);
    df::Rng rng(0, 5);
    std::vector<df::nn::Matrix<float>> seq(static_cast<std::size_t>(window),
                                           df::nn::Matrix<float>(batch, 9 * V));
    for (auto& f : seq)
      for (Eigen::Index k = 0; k < f.size(); ++k)
        f.data()[k] = static_cast<float>(rng.uniform(-0.95, 0.95));
    df::nn::AdamOptions ao;
    ao.lr = 1e-4;
    df::nn::Adam<float> adam(net.store().size(), ao);
    auto tape = std::make_unique<df::nn::Tape<float>>();
    auto step = [&] {
      df::nn::train_step<float>(*tape, net.store(), adam,
                                [&](df::nn::Tape<float>& t, const df::nn::Bound<float>& p) {
                                  return net.loss(t, p, seq, rng);
                                });
    };
    const auto tm = df::bench::time_iterations(warmup, iters, step);
    std::printf("| BD-LSTM %s | %zu | %.1f | %.1f | seq[%d,%d,%d,9] |\n", mesh_path.c_str(),
                net.store().size(), tm.median_ms, tm.min_ms, batch, window, V);
    if (profile.steps > 0)
      df::bench::print_profile(
          "BD-LSTM", profile.steps,
          [&] {
            tape = std::make_unique<df::nn::Tape<float>>();  // made while profiling is on
            step();
          },
          profile.limits);
  });
}
