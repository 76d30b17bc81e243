// Benchmark of eval-metrics' MMD_u^2 (max over the 14 bandwidths) at the shapes of the PyTorch
// peer ../shared/peers/torch/mmd.py: two sets of 1000 sequences of [50 frames, 60 values],
// X ~ N(0, 1), Y ~ N(0.05, 1.1^2), flattened to 3000 values.
//   bench_mmd [--threads N] [--iters 5] [--per-frame]   (--per-frame: MMD_avg's 50 per-frame MMDs)
#include <cstdio>

#include "core/rng.h"
#include "core/tool.h"
#include "eval/skeleton_metrics.h"
#include "timing.h"

int main(int argc, char** argv) {
  df::Tool tool("bench_mmd",
                "Time MMD_u^2 of 1000 x 1000 sequences of [50, 60] (see bench/run.sh).");
  int iters = 5, n = 1000, frames = 50, dims = 60;
  bool per_frame = false;
  tool.app().add_option("--iters", iters, "Timed runs")->default_val(iters);
  tool.app().add_option("--sequences", n, "Sequences on each side")->default_val(n);
  tool.app().add_flag("--per-frame", per_frame, "Time MMD_avg's per-frame MMDs instead");
  return tool.run(argc, argv, [&] {
    df::eval::RowMatrixF X(n, frames * dims), Y(n, frames * dims);
    df::Rng rng(1);
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = static_cast<float>(rng.normal());
    for (Eigen::Index i = 0; i < Y.size(); ++i)
      Y.data()[i] = static_cast<float>(rng.normal(0.05, 1.1));
    double value = 0;
    const auto t = df::bench::time_iterations(1, iters, [&] {
      if (!per_frame) {
        value = df::eval::mmd2_max(X, Y).mmd2;
        return;
      }
      value = 0;
      for (int f = 0; f < frames; ++f)
        value +=
            df::eval::mmd2_max(X.middleCols(f * dims, dims), Y.middleCols(f * dims, dims)).mmd2 /
            frames;
    });
    std::printf("| %s | %d x %d x [%d, %d] | %.1f | %.1f |\n",
                per_frame ? "MMD_avg (50 per-frame MMD_u^2)" : "MMD_u^2 of whole sequences", n, n,
                frames, dims, t.median_ms, t.min_ms);
    std::fprintf(stderr, "value %.6g\n", value);
  });
}
