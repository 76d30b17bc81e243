// Where a training step's time goes, op by op (the benchmarks' --profile; never on in training).
// A Tape with a profile attached times every node it records and every backward closure it
// runs, and adds them up per op (the function that recorded the node, e.g. `matmul`, `tanh`):
//   forward  — the wall time from the previous node's recording to this one's, i.e. the op's
//              own work plus whatever the model did between two ops (usually nothing);
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

  /// `where` is a std::source_location::function_name() (static storage); the op's name is taken
  /// from it ("df::nn::Var<T> df::nn::matmul(...) [with T = float]" → "matmul").
  void add_forward(const char* where, double seconds, double flops, double bytes);
  void add_backward(const char* where, double seconds, double flops, double bytes);

  /// Rows sorted by total time, largest first.
  std::vector<std::pair<std::string, Row>> rows() const;
  void clear() { rows_.clear(); }

  static std::string op_name(const char* where);

 private:
  Row& row(const char* where);
  std::map<const char*, std::string> names_;  // function_name pointer → op name (cache)
  std::map<std::string, Row> rows_;
};

}  // namespace df::nn
