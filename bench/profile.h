// The benchmarks' --profile: one training step op by op (nn/op_profile.h) as a Markdown table,
// each op's rate set against this machine's limits (bench_roofline: the peak of a dense float
// product, the memory bandwidth) at the thread count of the run.
#pragma once
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>

#include "nn/op_profile.h"
#include "nn/tape.h"
#include "nn/vector_types.h"

namespace df::bench {

struct MachineLimits {
  double peak_gflops = 0;    ///< dense float product, GFLOP/s (0: not given)
  double bandwidth_gbs = 0;  ///< memory, GB/s (0: not given)
};

/// --profile N (profile N steps after the timing; 0: none) and the limits to set them against.
struct ProfileOptions {
  int steps = 0;
  MachineLimits limits;
  void add_to(CLI::App& app) {
    app.add_option("--profile", steps, "Then profile this many steps op by op (a table per op)")
        ->default_val(0);
    app.add_option("--peak-gflops", limits.peak_gflops,
                   "The machine's product peak at these threads (bench_roofline)");
    app.add_option("--bandwidth", limits.bandwidth_gbs,
                   "The machine's memory bandwidth in GB/s (bench_roofline)");
  }
};

/// Runs `step` `iters` times with every tape profiled (after one unprofiled warm-up) and prints
/// the per-op table, per step.
inline void print_profile(const char* title, int iters, const std::function<void()>& step,
                          MachineLimits limits) {
  step();
  nn::OpProfile profile;
  nn::Tape<float>::profile_every_tape(&profile);
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < iters; ++i) step();
  const double step_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / iters;
  nn::Tape<float>::profile_every_tape(nullptr);

  auto pct = [](double part, double whole) { return whole > 0 ? 100 * part / whole : 0.0; };
  fmt::print("#### {}: one step op by op (mean of {}; kernels built for {})\n\n", title, iters,
             nn::detail::kVectorIsa);
  fmt::print(
      "| op | calls | forward ms | backward ms | share | GFLOP | GFLOP/s | % of peak | MB | GB/s "
      "|\n");
  fmt::print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  double in_ops = 0, flops = 0, flop_s = 0, bytes = 0;
  for (const auto& [name, r] : profile.rows()) {
    const double s = (r.forward_s + r.backward_s) / iters,
                 f = (r.forward_flops + r.backward_flops) / iters, b = r.bytes / iters;
    in_ops += s;
    flops += f;
    bytes += b;
    if (f > 0) flop_s += s;
    if (s < 0.0005 * step_s) continue;  // under 0.05% of the step
    const double gfs = s > 0 ? f / s / 1e9 : 0;
    const bool product = f > 0;
    fmt::print("| {} | {:.0f} | {:.2f} | {:.2f} | {:.1f}% | {} | {} | {} | {:.1f} | {:.1f} |\n",
               name, double(r.calls) / iters, 1e3 * r.forward_s / iters, 1e3 * r.backward_s / iters,
               pct(s, step_s), product ? fmt::format("{:.3f}", f / 1e9) : "",
               product ? fmt::format("{:.1f}", gfs) : "",
               product && limits.peak_gflops > 0
                   ? fmt::format("{:.0f}%", pct(gfs, limits.peak_gflops))
                   : "",
               b / 1e6, s > 0 ? b / s / 1e9 : 0.0);
  }
  fmt::print(
      "| (outside the ops: the optimiser, gradient collection, the model's own loops) | | | | "
      "{:.1f}% | | | | | |\n",
      pct(step_s - in_ops, step_s));
  fmt::print("\nstep {:.1f} ms; {:.2f} GFLOP in products taking {:.1f} ms ({:.1f} GFLOP/s)",
             1e3 * step_s, flops / 1e9, 1e3 * flop_s, flop_s > 0 ? flops / flop_s / 1e9 : 0);
  if (limits.peak_gflops > 0 || limits.bandwidth_gbs > 0) {
    // The step's limit: its products at the peak rate, or its bytes at the bandwidth if longer.
    const double limit_s =
        std::max(limits.peak_gflops > 0 ? flops / (limits.peak_gflops * 1e9) : 0.0,
                 limits.bandwidth_gbs > 0 ? bytes / (limits.bandwidth_gbs * 1e9) : 0.0);
    fmt::print(
        "; the machine's limit for it {:.1f} ms (products at {:.0f} GFLOP/s, or {:.0f} MB at "
        "{:.1f} GB/s): the step runs at {:.0f}% of it",
        1e3 * limit_s, limits.peak_gflops, bytes / 1e6, limits.bandwidth_gbs, pct(limit_s, step_s));
  }
  fmt::print("\n\n");
}

}  // namespace df::bench
