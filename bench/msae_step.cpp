// Benchmark of one joint MSAE training iteration (forward + backward + Adam) at the shapes of the
// PyTorch peer ../shared/peers/torch/msae.py: AE0 (K_z 10) and 10 attention-masked second-level
// AEs (K_z 5), batch 256 drawn with replacement from 64 random shapes in [-0.95, 0.95], Omega's
// masks a fixed random 0/1 matrix (as the peer's). Two ways to compute the batch:
//   full      every one of the 256 rows (what the peer computes)
//   distinct  the batch's distinct shapes weighted by their count (what train-msae does: the same
//             loss and gradient)
//   bench_msae (--mesh pcow/1.obj | --grid 112) [--mode full|distinct] [--threads N] [--iters 5]
#include <cstdio>

#include "core/error.h"
#include "core/tool.h"
#include "geometry/mesh_topology.h"
#include "io/mesh_io.h"
#include "models/msae/network.h"
#include "nn/adam.h"
#include "profile.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_msae", "Time one joint MSAE training iteration (see bench/run.sh).");
  std::string mesh_path, mode = "full";
  int grid = 0, iters = 5, warmup = 1, batch = 256, shapes = 64;
  tool.app().add_option("--mesh", mesh_path, "Template mesh (the peer uses pcow/1.obj)");
  tool.app().add_option("--grid", grid, "Or an N x N vertex grid (the peer's 'grid' is 112)");
  tool.app()
      .add_option("--mode", mode, "full or distinct")
      ->check(CLI::IsMember({"full", "distinct"}));
  tool.app().add_option("--iters", iters, "Timed iterations")->default_val(iters);
  tool.app().add_option("--warmup", warmup, "Untimed iterations first")->default_val(warmup);
  df::bench::ProfileOptions profile;
  profile.add_to(tool.app());
  tool.app().add_option("--batch", batch)->default_val(batch);
  tool.app()
      .add_option("--shapes", shapes, "Random shapes the batch is drawn from")
      ->default_val(shapes);
  return tool.run(argc, argv, [&] {
    df::Mesh m;
    if (grid > 1) {
      m.vertices.resize(grid * grid, 3);
      for (int y = 0; y < grid; ++y)
        for (int x = 0; x < grid; ++x) m.vertices.row(y * grid + x) << x, y, 0;
      m.faces.resize(2 * (grid - 1) * (grid - 1), 3);
      int f = 0;
      for (int y = 0; y + 1 < grid; ++y)
        for (int x = 0; x + 1 < grid; ++x) {
          const int a = y * grid + x;
          m.faces.row(f++) << a, a + 1, a + grid + 1;
          m.faces.row(f++) << a, a + grid + 1, a + grid;
        }
    } else {
      if (mesh_path.empty()) throw df::UsageError("give --mesh or --grid");
      m = df::io::read_mesh(mesh_path);
    }
    const int V = static_cast<int>(m.vertices.rows());
    const auto topo = df::geometry::mesh_topology(m.faces, V);
    df::models::MsaeNet<float> net({}, V, topo.edges, 0);
    df::Rng rng(0, 5);
    df::nn::Matrix<float> data(shapes, 9 * V);
    for (Eigen::Index k = 0; k < data.size(); ++k)
      data.data()[k] = static_cast<float>(rng.uniform(-0.95, 0.95));
    std::vector<df::nn::Matrix<float>> lambda;
    for (const auto& b : net.blocks()) {
      df::nn::Matrix<float> l(b.kz, V);
      for (Eigen::Index k = 0; k < l.size(); ++k) l.data()[k] = rng.uniform() < 0.5 ? 0.0f : 1.0f;
      lambda.push_back(l);
    }
    df::nn::AdamOptions ao;
    df::nn::Adam<float> adam(net.store().size(), ao);
    df::nn::Matrix<float> x, w;
    auto step = [&] {
      std::vector<int> count(static_cast<std::size_t>(shapes), 0), order;
      for (int b = 0; b < batch; ++b) {
        const int k = static_cast<int>(rng.below(static_cast<std::uint64_t>(shapes)));
        if (mode == "full" || count[static_cast<std::size_t>(k)]++ == 0) order.push_back(k);
        if (mode == "full") count[static_cast<std::size_t>(k)] = 1;
      }
      x.resize(static_cast<Eigen::Index>(order.size()), 9 * V);
      w.resize(static_cast<Eigen::Index>(order.size()), 1);
      for (std::size_t r = 0; r < order.size(); ++r) {
        x.row(static_cast<Eigen::Index>(r)) = data.row(order[r]);
        w(static_cast<Eigen::Index>(r), 0) =
            static_cast<float>(mode == "full" ? 1 : count[static_cast<std::size_t>(order[r])]);
      }
      (void)net.centres();  // what train-msae does every iteration before Omega's masks
      net.store().zero_grad();
      net.loss_and_gradient(x, lambda, {}, &w);
      adam.step(net.store().values(), net.store().grads());
    };
    const auto tm = df::bench::time_iterations(warmup, iters, step);
    const std::string what =
        grid > 1 ? "grid " + std::to_string(grid) + "x" + std::to_string(grid) : mesh_path;
    std::printf("| MSAE %s (%s rows) | %zu | %.1f | %.1f | X[%d,%d,9] |\n", what.c_str(),
                mode.c_str(), net.store().size(), tm.median_ms, tm.min_ms, batch, V);
    if (profile.steps > 0)
      df::bench::print_profile(("MSAE " + what).c_str(), profile.steps, step, profile.limits);
  });
}
