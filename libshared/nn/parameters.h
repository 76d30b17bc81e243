// One flat parameter store per model with named views (CONVENTIONS: mlpack's Parameters()):
// the optimizer updates the flat vectors, save/load go by name. A forward pass binds every
// parameter to a tape leaf once (bind), and after backward the leaves' gradients are added
// into the flat gradient (collect).
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "core/rng.h"
#include "nn/tape.h"

namespace df::nn {

template <class T>
using Vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

/// The tape leaves of one binding of a store; p[i] is parameter i.
template <class T>
struct Bound {
  std::vector<Var<T>> vars;
  Var<T> operator[](int i) const { return vars[static_cast<std::size_t>(i)]; }
};

template <class T>
class ParameterStore {
 public:
  struct View {
    std::string name;
    Eigen::Index offset = 0, rows = 0, cols = 0;
  };

  /// Adds a rows×cols parameter (zero) and returns its index. Names must be unique.
  int add(const std::string& name, Eigen::Index rows, Eigen::Index cols);
  int find(const std::string& name) const;  ///< -1 if absent
  const std::vector<View>& views() const { return views_; }
  std::size_t size() const { return static_cast<std::size_t>(values_.size()); }

  Eigen::Map<Matrix<T>> value(int p);
  Eigen::Map<const Matrix<T>> value(int p) const;
  Eigen::Map<Matrix<T>> grad(int p);
  Vector<T>& values() { return values_; }
  const Vector<T>& values() const { return values_; }
  Vector<T>& grads() { return grads_; }
  void zero_grad() { grads_.setZero(); }

  /// Every parameter as a variable leaf of `tape` (values copied).
  Bound<T> bind(Tape<T>& tape) const;
  /// Every parameter as a constant leaf: a forward pass through a network that is not trained
  /// in this step (its weights get no gradient; inputs still do).
  Bound<T> bind_constant(Tape<T>& tape) const;
  /// Every parameter as a variable leaf but those whose name starts with `frozen_prefix`, which
  /// are constants (a part of the network held fixed in this step: no gradient, no update).
  Bound<T> bind_except(Tape<T>& tape, std::string_view frozen_prefix) const;
  /// Adds the gradients of a binding's leaves into grads() (after tape.backward).
  void collect(const Bound<T>& bound);

  // --- initialisers
  /// Glorot/Xavier uniform: U(±sqrt(6 / (fan_in + fan_out))) with fan_in = rows, fan_out = cols.
  void glorot_uniform(int p, Rng& rng);
  void normal(int p, Rng& rng, double stddev);
  void constant(int p, T value);

 private:
  std::vector<View> views_;
  Vector<T> values_, grads_;
};

extern template class ParameterStore<float>;
extern template class ParameterStore<double>;

}  // namespace df::nn
