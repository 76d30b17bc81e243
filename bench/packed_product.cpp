// Benchmark of the network engine's packed product (libshared/nn/packed_product.h) against
// Eigen's product of the same operands, at the shapes of the ActGAN LSTMs (B 32, T 50, H 256):
//   step      [32 × 256] · [256 × 1024]    forward step h_{t-1} · W_h
//   step-back [32 × 1024] · [1024 × 256]   backward step dZ_t · W_hᵀ (W packed transposed)
//   weights   [256 × 1600] · [1600 × 1024]   the weight gradient h_prevᵀ · dZ (A stored transposed)
// GFLOP/s of each (2·m·k·n per product), median of --iters timed runs of --reps products each;
// Eigen's figure includes its own packing, ours excludes the one-time pack (timed separately).
//   bench_packed_product [--threads N] [--iters 9] [--reps 200]
#include "nn/packed_product.h"

#include <cstdio>

#include "core/tool.h"
#include "inputs.h"
#include "timing.h"

namespace {
using df::bench::randn;
using df::nn::Matrix;
using Eigen::Index;
}  // namespace

int main(int argc, char** argv) {
  df::Tool tool("bench_packed_product",
                "Time the packed product against Eigen's (see bench/run.sh).");
  int iters = 9, reps = 200;
  tool.app().add_option("--iters", iters, "Timed runs")->default_val(iters);
  tool.app()
      .add_option("--reps", reps, "Products per run (the weights case: reps / 50)")
      ->default_val(reps);
  return tool.run(argc, argv, [&] {
    df::Rng rng(5);
    struct Case {
      const char* name;
      Index m, k, n;
      bool w_transposed, a_transposed;  // not both: no LSTM product has both
    };
    for (const Case& c :
         {Case{"step", 32, 256, 1024, false, false}, Case{"step-back", 32, 1024, 256, true, false},
          Case{"weights", 256, 1600, 1024, false, true}}) {
      const Matrix<float> w = c.w_transposed ? randn(c.n, c.k, rng) : randn(c.k, c.n, rng);
      const Matrix<float> a_stored = c.a_transposed ? randn(c.k, c.m, rng) : randn(c.m, c.k, rng);
      Matrix<float> out = Matrix<float>::Zero(c.m, c.n);
      const int n = c.m * c.k * c.n > 100'000'000 ? std::max(1, reps / 50) : reps;
      const double gflop = 2.0 * static_cast<double>(c.m * c.k * c.n) * n / 1e9;
      const auto eigen = df::bench::time_iterations(1, iters, [&] {
        for (int r = 0; r < n; ++r) {
          if (c.a_transposed)
            out.noalias() = a_stored.transpose() * w;
          else if (c.w_transposed)
            out.noalias() = a_stored * w.transpose();
          else
            out.noalias() = a_stored * w;
        }
      });
      df::nn::detail::PackedRhs<float> packed;
      const auto pack = df::bench::time_iterations(
          1, iters, [&] { packed = df::nn::detail::pack_rhs(w, c.w_transposed); });
      const auto ours = df::bench::time_iterations(1, iters, [&] {
        for (int r = 0; r < n; ++r) {
          if (c.a_transposed)
            df::nn::detail::packed_product<float>(out, a_stored.transpose(), packed, false);
          else
            df::nn::detail::packed_product<float>(out, a_stored, packed, false);
        }
      });
      std::printf(
          "| %s [%ld × %ld] · [%ld × %ld] | Eigen %.1f GFLOP/s | packed %.1f GFLOP/s | pack %.3f "
          "ms |\n",
          c.name, static_cast<long>(c.m), static_cast<long>(c.k), static_cast<long>(c.k),
          static_cast<long>(c.n), gflop / eigen.median_ms * 1e3, gflop / ours.median_ms * 1e3,
          pack.median_ms);
    }
  });
}
