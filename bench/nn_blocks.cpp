// Benchmark of the network engine's building blocks at the shapes of the PyTorch peer's
// blocks.py (../shared/peers/torch): forward + backward + Adam step, float32, 5 warm-up and
// 30 timed iterations, median and min in milliseconds.
//   bench_nn_blocks [--threads N] [--mesh OBJ] [--iters 30]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>

#include "core/tool.h"
#include "geometry/mesh_topology.h"
#include "inputs.h"
#include "io/mesh_io.h"
#include "nn/adam.h"
#include "nn/layers.h"
#include "nn/train_step.h"
#include "synth/meshseq.h"
#include "timing.h"

using namespace df::nn;
using df::bench::randn;

namespace {
struct Case {
  std::string name;
  ParameterStore<float> store;
  std::function<Var<float>(Tape<float>&, const Bound<float>&)> loss;
};

void time_case(Case& c, int iters) {
  Adam<float> adam(c.store.size(), {});
  Tape<float> t;
  const auto tm =
      df::bench::time_iterations(5, iters, [&] { train_step<float>(t, c.store, adam, c.loss); });
  std::printf("| %s | %zu | %.2f | %.2f |\n", c.name.c_str(), c.store.size(), tm.median_ms,
              tm.min_ms);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv) {
  df::Tool tool("bench_nn_blocks", "Time the network building blocks (see bench/run.sh).");
  std::string mesh_path;
  int iters = 30, only = 0;
  tool.app().add_option("--mesh", mesh_path,
                        "Mesh for MeshConv (default: a synthetic 2,904-vertex-like grid)");
  tool.app().add_option("--iters", iters);
  tool.app().add_option("--only", only, "Run only block 1..4 (peak memory per block)");
  return tool.run(argc, argv, [&] {
    df::Rng rng(0);
    if (!only) std::printf("| block | parameters | median ms | min ms |\n|---|---|---|---|\n");
    if (!only || only == 1) {  // stacked LSTM 3 x 128 over 32 steps, batch 8
      Case c{"LSTM 3x128 T=32 B=8", {}, {}};
      auto lstm = std::make_shared<StackedLstm<float>>(c.store, "lstm", 128, 128, 3, rng);
      std::vector<Matrix<float>> x;
      for (int s = 0; s < 32; ++s) x.push_back(randn(8, 128, rng));
      c.loss = [lstm, x](Tape<float>& t, const Bound<float>& p) {
        std::vector<Var<float>> xs;
        for (const auto& m : x) xs.push_back(t.constant(m));
        auto states = lstm->constant_states(t, 8, 0.1f);
        return mean(square(concat_rows(lstm->run(p, xs, states))));
      };
      time_case(c, iters);
    }
    if (!only || only == 2) {  // MeshConv(9->9)+tanh then Linear(9V->128)+tanh, batch 256
      df::Mesh m;
      if (!mesh_path.empty()) {
        m = df::io::read_mesh(mesh_path);
      } else {
        df::synth::MeshSeqParams sp;
        sp.kind = df::synth::MeshSeqKind::bumps;
        sp.resolution = 53;  // 54 x 54 = 2,916 vertices, close to pcow's 2,904
        sp.frames = 1;
        m = df::synth::MeshSequenceGenerator(sp).rest();
      }
      const auto V = m.vertices.rows();
      auto topo = df::geometry::mesh_topology(m.faces, static_cast<int>(V));
      Case c{"MeshConv+FC V=" + std::to_string(V) + " B=256", {}, {}};
      auto conv = std::make_shared<MeshConv<float>>(
          c.store, "conv", 9, 9, neighbour_mean_operator<float>(static_cast<int>(V), topo.edges),
          rng);
      auto fc = std::make_shared<Linear<float>>(c.store, "fc", 9 * V, 128, rng);
      Matrix<float> x = randn(256, 9 * V, rng);
      c.loss = [conv, fc, x](Tape<float>& t, const Bound<float>& p) {
        return mean(square(tanh((*fc)(p, tanh((*conv)(p, t.constant(x)))))));
      };
      time_case(c, iters);
    }
    if (!only || only == 3) {  // bidirectional LSTM 256 over 50 steps of 60-d input, last states ->
                               // FC 1024 -> 1, batch 32
      Case c{"BiLSTM 256 T=50 B=32 +FC1024", {}, {}};
      auto bi = std::make_shared<BidirectionalLstm<float>>(c.store, "bi", 60, 256, 1, rng);
      auto head = std::make_shared<Mlp<float>>(
          c.store, "head", std::vector<Eigen::Index>{512, 1024, 1}, Activation::relu, rng);
      std::vector<Matrix<float>> x;
      for (int s = 0; s < 50; ++s) x.push_back(randn(32, 60, rng));
      c.loss = [bi, head, x](Tape<float>& t, const Bound<float>& p) {
        std::vector<Var<float>> xs;
        for (const auto& m : x) xs.push_back(t.constant(m));
        const auto h = bi->run(p, concat_rows<float>(xs), 32);
        return mean(square((*head)(p, concat_cols<float>({slice_rows(h.forward, 49 * 32, 32),
                                                          slice_rows(h.backward, 0, 32)}))));
      };
      time_case(c, iters);
    }
    if (!only ||
        only == 4) {  // MLP critic 60 -> 1024 -> 1 with WGAN gradient penalty (lambda 10), batch 64
      Case c{"critic MLP + GP B=64", {}, {}};
      auto d = std::make_shared<Mlp<float>>(c.store, "D", std::vector<Eigen::Index>{60, 1024, 1},
                                            Activation::relu, rng);
      Matrix<float> real = randn(64, 60, rng), fake = randn(64, 60, rng);
      auto draw = std::make_shared<df::Rng>(1);
      c.loss = [d, real, fake, draw](Tape<float>& t, const Bound<float>& p) {
        Matrix<float> eps(64, 1);
        for (int r = 0; r < 64; ++r) eps(r, 0) = static_cast<float>(draw->uniform());
        Matrix<float> xi = (real.array().colwise() * eps.col(0).array() +
                            fake.array().colwise() * (1 - eps.col(0).array()))
                               .matrix();
        Var<float> g = d->input_gradient(p, t.constant(xi));
        Var<float> gp = mean(square(add_scalar(sqrt(sum_cols(square(g))), -1.0f)));
        Var<float> w = sub(mean((*d)(p, t.constant(fake))), mean((*d)(p, t.constant(real))));
        return add(w, scale(gp, 10.0f));
      };
      time_case(c, iters);
    }
  });
}
