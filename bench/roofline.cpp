// This machine's limits, against which bench/run.sh sets the training steps' profiles:
//   peak    — the best rate of a dense float product (2·n³ per product), one square product per
//             thread (n = 512, 1024, 2048) with Eigen's kernel and with the engine's packed
//             product (nn/packed_product, which runs the LSTMs), i.e. what the cores' FMA units
//             give a product that is all arithmetic, at --threads;
//   memory  — a streaming triad a = b + s·c over three 128 MB float arrays, split into fixed
//             chunks over the threads (bytes: two reads and one write per element).
//   bench_roofline [--threads N] [--iters 5]
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>

#include "core/tool.h"
#include "inputs.h"
#include "nn/packed_product.h"
#include "nn/vector_types.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_roofline",
                "Measure the peak product rate and the memory bandwidth (see bench/run.sh).");
  int iters = 5;
  tool.app().add_option("--iters", iters, "Timed runs (the best counts)")->default_val(iters);
  return tool.run(argc, argv, [&] {
    using Mat = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    df::Rng rng(3);
    const int threads = static_cast<int>(
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    double peak = 0;
    std::printf("The engine's kernels built for %s.\n\n", df::nn::detail::kVectorIsa);
    std::printf("| measure | Eigen | engine's packed product |\n|---|---|---|\n");
    for (Eigen::Index n : {512, 1024, 2048}) {
      std::vector<Mat> a, b, c;
      for (int t = 0; t < threads; ++t) {
        a.push_back(df::bench::randn(n, n, rng));
        b.push_back(df::bench::randn(n, n, rng));
        c.emplace_back(n, n);
      }
      const int reps = n >= 2048 ? 1 : n >= 1024 ? 4 : 16;
      std::vector<df::nn::detail::PackedRhs<float>> packed;
      for (int t = 0; t < threads; ++t) packed.push_back(df::nn::detail::pack_rhs(b[t], false));
      const auto eigen = df::bench::time_iterations(1, iters, [&] {
        tbb::parallel_for(
            0, threads,
            [&](int t) {
              for (int r = 0; r < reps; ++r) c[t].noalias() = a[t] * b[t];
            },
            tbb::static_partitioner());
      });
      const auto ours = df::bench::time_iterations(1, iters, [&] {
        tbb::parallel_for(
            0, threads,
            [&](int t) {
              for (int r = 0; r < reps; ++r)
                df::nn::detail::packed_product<float>(c[t], a[t], packed[t], false);
            },
            tbb::static_partitioner());
      });
      const double flop = 2.0 * double(n) * double(n) * double(n) * reps * threads;
      const double e = flop / (eigen.min_ms * 1e6), p = flop / (ours.min_ms * 1e6);
      std::printf("| product %ld² × %ld², one per thread | %.1f GFLOP/s | %.1f GFLOP/s |\n",
                  static_cast<long>(n), static_cast<long>(n), e, p);
      peak = std::max({peak, e, p});
    }
    const Eigen::Index n = Eigen::Index{32} << 20;  // 32 M floats: 128 MB per array
    Eigen::VectorXf a(n), b = Eigen::VectorXf::Constant(n, 1.0f),
                          c = Eigen::VectorXf::Constant(n, 2.0f);
    constexpr Eigen::Index kChunk = Eigen::Index{1} << 18;
    const auto tm = df::bench::time_iterations(1, iters, [&] {
      tbb::parallel_for(Eigen::Index{0}, n / kChunk, [&](Eigen::Index k) {
        a.segment(k * kChunk, kChunk) =
            b.segment(k * kChunk, kChunk) + 0.5f * c.segment(k * kChunk, kChunk);
      });
    });
    const double gbs = 3.0 * double(n) * sizeof(float) / (tm.min_ms * 1e6);
    std::printf("| triad over 3 × 128 MB (memory) | %.1f GB/s | |\n", gbs);
    std::printf("roofline: threads %d peak %.1f GFLOP/s bandwidth %.1f GB/s\n", threads, peak, gbs);
  });
}
