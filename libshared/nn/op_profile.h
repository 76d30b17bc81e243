// Where a training step's time goes, op by op (the benchmarks' --profile; never on in training).
// A Tape with a profile attached times every node it records and every backward closure it
// runs, and adds them up per op (the function that recorded the node, e.g. `matmul`, `tanh`):
//   forward  — the wall time since the previous event on any profiled tape (a node recorded, a
//              backward closure ended, a tape made or cleared), i.e. the op's own work plus
//              whatever the model did between two ops (usually nothing);
//   backward — the node's backward closure, and work an op deferred to a later node
//              (matmul_repeated's one weight-gradient product over all its uses);
//   FLOPs    — stated by the ops that are products (2·m·k·n per product), zero for the rest;
//   bytes    — the op's output value (written forward) and its gradient (read backward): a
//              lower bound of the memory traffic (its inputs and their gradients not counted).
#pragma once

#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace df::nn {

/// What a product op states about its arithmetic, for the profile.
struct OpCost {
  double forward_flops = 0;
  double backward_flops = 0;  ///< when every input that can want a gradient wants one
};

class OpProfile {
 public:
  using Clock = std::chrono::steady_clock;
  struct Row {
    long calls = 0;
    double forward_s = 0, backward_s = 0;
    double forward_flops = 0, backward_flops = 0;
    double bytes = 0;
  };

  /// `where` names the recording function (__builtin_FUNCTION(): static storage), plain
  /// ("matmul") or as a full signature ("df::nn::Var<T> df::nn::matmul(...) [with T = float]").
  void add_forward(const char* where, double seconds, double flops, double bytes);
  void add_backward(const char* where, double seconds, double flops, double bytes);

  /// Rows sorted by total time, largest first.
  std::vector<std::pair<std::string, Row>> rows() const;
  void clear() { rows_.clear(); }

  /// Seconds since the previous event (and marks now as the latest).
  double lap() {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - mark_).count();
    mark_ = now;
    return s;
  }
  void mark() { mark_ = Clock::now(); }

  static std::string op_name(const char* where);

 private:
  Row& row(const char* where);
  std::map<const char*, std::string> names_;  // function_name pointer → op name (cache)
  std::map<std::string, Row> rows_;
  Clock::time_point mark_ = Clock::now();
};

}  // namespace df::nn
