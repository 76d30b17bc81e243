#include "nn/tape.h"

#include <utility>

#include "core/error.h"

namespace df::nn {

template <class T>
void Tape<T>::profile_forward(const Node& n, double flops) {
  profile_->add_forward(n.where, profile_->lap(), flops,
                        static_cast<double>(n.value.size() * sizeof(T)));
}

template <class T>
Var<T> Tape<T>::constant(Matrix<T> value) {
  Node& n = nodes_.emplace_back();
  n.value = std::move(value);
  if (profile_) profile_forward(n, 0);
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Var<T> Tape<T>::variable(Matrix<T> value) {
  Node& n = nodes_.emplace_back();
  n.value = std::move(value);
  n.requires_grad = true;
  if (profile_) profile_forward(n, 0);
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Var<T> Tape<T>::record(Matrix<T> value, bool requires_grad, std::function<void()> backward,
                       OpCost cost, const char* where) {
  Node& n = nodes_.emplace_back();
  n.value = std::move(value);
  n.requires_grad = requires_grad;
  if (requires_grad) n.backward = std::move(backward);
  n.where = where;
  n.backward_flops = cost.backward_flops;
  if (profile_) profile_forward(n, cost.forward_flops);
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Matrix<T>& Tape<T>::grad(int id) {
  Node& n = nodes_[static_cast<std::size_t>(id)];
  if (n.grad.size() == 0 && n.value.size() > 0)
    n.grad = Matrix<T>::Zero(n.value.rows(), n.value.cols());
  return n.grad;
}

template <class T>
Matrix<T>& Tape<T>::grad_to_update(int id, bool& add) {
  Node& n = nodes_[static_cast<std::size_t>(id)];
  add = n.grad.size() > 0 || n.value.size() == 0;
  if (!add) n.grad.resize(n.value.rows(), n.value.cols());
  return n.grad;
}

template <class T>
void Tape<T>::backward(Var<T> from) {
  if (value(from.id).size() != 1)
    throw Error("internal: backward() from a non-scalar node needs a seed gradient");
  backward(from, Matrix<T>::Ones(1, 1));
}

template <class T>
void Tape<T>::backward(Var<T> from, const Matrix<T>& seed) {
  if (seed.rows() != value(from.id).rows() || seed.cols() != value(from.id).cols())
    throw Error("internal: seed gradient shape differs from the node's");
  grad(from.id) += seed;
  for (int id = from.id; id >= 0; --id) run_backward(nodes_[static_cast<std::size_t>(id)]);
}

template <class T>
void Tape<T>::run_backward(Node& n) {
  if (!profile_) {
    if (n.pending) std::exchange(n.pending, nullptr)();
    if (n.backward && n.grad.size() > 0) n.backward();
    return;
  }
  if (n.pending) {
    profile_->mark();
    std::exchange(n.pending, nullptr)();
    profile_->add_backward(n.pending_where, profile_->lap(), 0, 0);
  }
  if (n.backward && n.grad.size() > 0) {
    profile_->mark();
    n.backward();
    profile_->add_backward(n.where, profile_->lap(), n.backward_flops,
                           static_cast<double>(n.grad.size() * sizeof(T)));
  }
}

template <class T>
void Tape<T>::clear() {
  nodes_.clear();
  if (profile_) profile_->mark();
}

template class Tape<float>;
template class Tape<double>;

}  // namespace df::nn
