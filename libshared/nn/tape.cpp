#include "nn/tape.h"

#include <utility>

#include "core/error.h"

namespace df::nn {

template <class T>
Var<T> Tape<T>::constant(Matrix<T> value) {
  nodes_.push_back({std::move(value), {}, false, {}, {}, {}});
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Var<T> Tape<T>::variable(Matrix<T> value) {
  nodes_.push_back({std::move(value), {}, true, {}, {}, {}});
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Var<T> Tape<T>::record(Matrix<T> value, bool requires_grad, std::function<void()> backward) {
  nodes_.push_back({std::move(value), {}, requires_grad, requires_grad ? std::move(backward) : nullptr, {}, {}});
  return {this, static_cast<int>(nodes_.size()) - 1};
}

template <class T>
Matrix<T>& Tape<T>::grad(int id) {
  Node& n = nodes_[static_cast<std::size_t>(id)];
  if (n.grad.size() == 0 && n.value.size() > 0) n.grad = Matrix<T>::Zero(n.value.rows(), n.value.cols());
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
  if (value(from.id).size() != 1) throw Error("internal: backward() from a non-scalar node needs a seed gradient");
  backward(from, Matrix<T>::Ones(1, 1));
}

template <class T>
void Tape<T>::backward(Var<T> from, const Matrix<T>& seed) {
  if (seed.rows() != value(from.id).rows() || seed.cols() != value(from.id).cols())
    throw Error("internal: seed gradient shape differs from the node's");
  grad(from.id) += seed;
  for (int id = from.id; id >= 0; --id) {
    Node& n = nodes_[static_cast<std::size_t>(id)];
    if (n.pending) std::exchange(n.pending, nullptr)();
    if (n.backward && n.grad.size() > 0) n.backward();
  }
}

template <class T>
void Tape<T>::clear() {
  nodes_.clear();
}

template class Tape<float>;
template class Tape<double>;

}  // namespace df::nn
