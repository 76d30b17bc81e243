#include "nn/parameters.h"

#include <cmath>

#include "core/error.h"

namespace df::nn {

template <class T>
int ParameterStore<T>::add(const std::string& name, Eigen::Index rows, Eigen::Index cols) {
  if (find(name) >= 0) throw Error("internal: parameter '" + name + "' defined twice");
  View v{name, values_.size(), rows, cols};
  views_.push_back(v);
  values_.conservativeResize(values_.size() + rows * cols);
  grads_.conservativeResize(values_.size());
  values_.segment(v.offset, rows * cols).setZero();
  grads_.segment(v.offset, rows * cols).setZero();
  return static_cast<int>(views_.size()) - 1;
}

template <class T>
int ParameterStore<T>::find(const std::string& name) const {
  for (std::size_t i = 0; i < views_.size(); ++i)
    if (views_[i].name == name) return static_cast<int>(i);
  return -1;
}

template <class T>
Eigen::Map<Matrix<T>> ParameterStore<T>::value(int p) {
  const View& v = views_[static_cast<std::size_t>(p)];
  return {values_.data() + v.offset, v.rows, v.cols};
}

template <class T>
Eigen::Map<const Matrix<T>> ParameterStore<T>::value(int p) const {
  const View& v = views_[static_cast<std::size_t>(p)];
  return {values_.data() + v.offset, v.rows, v.cols};
}

template <class T>
Eigen::Map<Matrix<T>> ParameterStore<T>::grad(int p) {
  const View& v = views_[static_cast<std::size_t>(p)];
  return {grads_.data() + v.offset, v.rows, v.cols};
}

template <class T>
Bound<T> ParameterStore<T>::bind(Tape<T>& tape) const {
  Bound<T> b;
  for (std::size_t i = 0; i < views_.size(); ++i)
    b.vars.push_back(tape.variable(value(static_cast<int>(i))));
  return b;
}

template <class T>
Bound<T> ParameterStore<T>::bind_constant(Tape<T>& tape) const {
  Bound<T> b;
  for (std::size_t i = 0; i < views_.size(); ++i)
    b.vars.push_back(tape.constant(value(static_cast<int>(i))));
  return b;
}

template <class T>
Bound<T> ParameterStore<T>::bind_except(Tape<T>& tape, std::string_view frozen_prefix) const {
  Bound<T> b;
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const auto p = static_cast<int>(i);
    b.vars.push_back(views_[i].name.starts_with(frozen_prefix) ? tape.constant(value(p))
                                                               : tape.variable(value(p)));
  }
  return b;
}

template <class T>
void ParameterStore<T>::collect(const Bound<T>& bound) {
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const Var<T>& v = bound.vars[i];
    if (v.tape->has_grad(v.id)) grad(static_cast<int>(i)) += v.grad();
  }
}

template <class T>
void ParameterStore<T>::glorot_uniform(int p, Rng& rng) {
  auto m = value(p);
  const double limit = std::sqrt(6.0 / static_cast<double>(m.rows() + m.cols()));
  for (Eigen::Index k = 0; k < m.size(); ++k)
    m.data()[k] = static_cast<T>(rng.uniform(-limit, limit));
}

template <class T>
void ParameterStore<T>::normal(int p, Rng& rng, double stddev) {
  auto m = value(p);
  for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = static_cast<T>(rng.normal(0.0, stddev));
}

template <class T>
void ParameterStore<T>::constant(int p, T x) {
  value(p).setConstant(x);
}

template class ParameterStore<float>;
template class ParameterStore<double>;

}  // namespace df::nn
