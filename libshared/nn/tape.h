// Reverse-mode automatic differentiation over whole matrices (CONVENTIONS: micrograd's idea at
// matrix granularity). Every operation records one node on a Tape in creation order: its value
// and a backward closure that reads the node's gradient and *accumulates* (+=) into its inputs'
// gradients. Tape::backward walks the nodes in reverse. Training uses Tape<float>; the same
// code is instantiated for double, where every op is gradient-checked.
//
// Matrices are row-major: a batch is a matrix with one sample per row.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "nn/op_profile.h"

namespace df::nn {

template <class T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

template <class T>
class Tape;

/// A handle to a node of a tape (cheap to copy). Ops take and return Vars.
template <class T>
struct Var {
  Tape<T>* tape = nullptr;
  int id = -1;

  const Matrix<T>& value() const;
  /// The gradient (allocated as zeros on first use).
  Matrix<T>& grad() const;
  bool requires_grad() const;
  Eigen::Index rows() const { return value().rows(); }
  Eigen::Index cols() const { return value().cols(); }
};

template <class T>
class Tape {
 public:
  Tape() : profile_(profile_every_tape_) {
    if (profile_) profile_->mark();
  }
  Tape(const Tape&) = delete;
  Tape& operator=(const Tape&) = delete;

  /// A leaf that needs no gradient (data, labels, masks).
  Var<T> constant(Matrix<T> value);
  /// A leaf whose gradient is wanted (parameters, inputs of gradient checks).
  Var<T> variable(Matrix<T> value);
  /// Records an op's result. `backward` runs once during backward(); it must only add into the
  /// gradients of inputs that require them. requires_grad = any input requires a gradient.
  /// `cost` and `where` (the recording op) serve only an attached OpProfile.
  Var<T> record(Matrix<T> value, bool requires_grad, std::function<void()> backward,
                OpCost cost = {}, const char* where = __builtin_FUNCTION());

  /// Backpropagates from a 1×1 node (seed 1) or from any node with the given seed gradient.
  void backward(Var<T> from);
  void backward(Var<T> from, const Matrix<T>& seed);

  /// Forgets every node (keeps the capacity for the next iteration).
  void clear();
  /// Forgets the nodes recorded after the first n (e.g. keep bound parameters, drop one
  /// generation step's activations).
  void truncate(std::size_t n) {
    if (n < nodes_.size()) nodes_.resize(n);
  }
  std::size_t size() const { return nodes_.size(); }

  const Matrix<T>& value(int id) const { return nodes_[static_cast<std::size_t>(id)].value; }
  Matrix<T>& grad(int id);
  /// The gradient of node id for an op that is about to add into all of it: on first use it is
  /// allocated but NOT zeroed and `add` is set false (the op writes = instead of +=, sparing a
  /// pass of zeros); afterwards `add` is true. Same values as grad(id) += ..., one pass fewer.
  Matrix<T>& grad_to_update(int id, bool& add);
  /// grad(id) += e, or grad(id) = e on first use (e: an Eigen expression of the node's shape).
  template <class Expr>
  void add_to_grad(int id, const Expr& e) {
    bool add = false;
    Matrix<T>& g = grad_to_update(id, add);
    if (add)
      g += e;
    else
      g = e;
  }
  bool requires_grad(int id) const { return nodes_[static_cast<std::size_t>(id)].requires_grad; }
  bool has_grad(int id) const { return nodes_[static_cast<std::size_t>(id)].grad.size() > 0; }

  /// Data an op keeps with node id for as long as the node lives (matmul_repeated: the node's
  /// value packed once for all of its products); empty until an op sets it.
  std::shared_ptr<void>& op_state(int id) { return nodes_[static_cast<std::size_t>(id)].op_state; }
  /// Runs `f` once when backward() reaches node id — after the backward of every later node,
  /// before id's own — so that work adding into id's gradient from many uses can run as one
  /// (matmul_repeated: one weight-gradient product over all the steps that used the weight).
  /// A second call before backward() reaches id keeps the first `f`.
  /// (In a profile, f's time counts as the op's that asked: `where`.)
  void when_backward_reaches(int id, std::function<void()> f,
                             const char* where = __builtin_FUNCTION()) {
    Node& n = nodes_[static_cast<std::size_t>(id)];
    if (n.pending) return;
    n.pending = std::move(f);
    n.pending_where = where;
  }

  /// Every tape made from now on times its ops into `profile` (nullptr: stop) — the benchmarks'
  /// --profile, for models that make their own tapes. Not for tapes recorded concurrently.
  static void profile_every_tape(OpProfile* profile) { profile_every_tape_ = profile; }

 private:
  struct Node {
    Matrix<T> value, grad;
    bool requires_grad = false;
    std::function<void()> backward;
    std::shared_ptr<void> op_state;
    std::function<void()> pending;
    const char* where = "leaf";  // the recording op (profile)
    double backward_flops = 0;
    const char* pending_where = nullptr;
  };
  void profile_forward(const Node& n, double flops);
  void run_backward(Node& n);
  std::vector<Node> nodes_;
  OpProfile* profile_ = nullptr;
  static inline OpProfile* profile_every_tape_ = nullptr;
};

template <class T>
const Matrix<T>& Var<T>::value() const {
  return tape->value(id);
}
template <class T>
Matrix<T>& Var<T>::grad() const {
  return tape->grad(id);
}
template <class T>
bool Var<T>::requires_grad() const {
  return tape->requires_grad(id);
}

extern template class Tape<float>;
extern template class Tape<double>;

}  // namespace df::nn
