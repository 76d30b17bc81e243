// The reusable gradient checker (dlib's test_layer / mlpack's CheckGradient idea), in double:
//   * the output is reduced to a scalar by a random projection P (s = Σ P ∘ f(x)),
//   * analytic gradients come from one backward pass seeded with P, into gradient buffers
//     pre-filled with a sentinel: an op that forgets an input, or overwrites instead of
//     accumulating, is caught,
//   * numeric gradients are central differences of s for every input element,
//   * the error per input is ‖analytic − numeric‖ / (‖analytic‖ + ‖numeric‖).
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/rng.h"
#include "nn/tape.h"

namespace df::nn {

struct GradientCheck {
  double max_error = 0;  ///< worst relative error over the inputs
  int worst_input = -1;
  std::string report;  ///< one line per input
};

/// @param f       builds the computation from the inputs and returns its output (any shape)
/// @param inputs  values of the inputs (each gets a gradient)
inline GradientCheck gradient_check(
    const std::function<Var<double>(Tape<double>&, const std::vector<Var<double>>&)>& f,
    const std::vector<Matrix<double>>& inputs, std::uint64_t seed = 0, double h = 1e-6) {
  constexpr double kSentinel = 0.25;
  Rng rng(seed, 77);
  GradientCheck result;

  // Analytic.
  Tape<double> tape;
  std::vector<Var<double>> vars;
  for (const auto& x : inputs) vars.push_back(tape.variable(x));
  Var<double> out = f(tape, vars);
  Matrix<double> P(out.rows(), out.cols());
  for (Eigen::Index k = 0; k < P.size(); ++k) P.data()[k] = rng.uniform(-1.0, 1.0);
  for (auto& v : vars) v.grad().setConstant(kSentinel);
  tape.backward(out, P);
  std::vector<Matrix<double>> analytic;
  for (auto& v : vars) analytic.push_back(v.grad().array() - kSentinel);

  // Numeric.
  auto projected = [&](const std::vector<Matrix<double>>& xs) {
    Tape<double> t;
    std::vector<Var<double>> vs;
    for (const auto& x : xs) vs.push_back(t.constant(x));
    return f(t, vs).value().cwiseProduct(P).sum();
  };
  std::vector<Matrix<double>> xs = inputs;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    Matrix<double> numeric(xs[k].rows(), xs[k].cols());
    for (Eigen::Index e = 0; e < xs[k].size(); ++e) {
      const double x0 = xs[k].data()[e];
      xs[k].data()[e] = x0 + h;
      const double up = projected(xs);
      xs[k].data()[e] = x0 - h;
      const double down = projected(xs);
      xs[k].data()[e] = x0;
      numeric.data()[e] = (up - down) / (2 * h);
    }
    const double diff = (analytic[k] - numeric).norm(), scale = analytic[k].norm() + numeric.norm();
    const double err = scale < 1e-12 ? diff : diff / scale;
    result.report += "input " + std::to_string(k) + ": |analytic| " +
                     std::to_string(analytic[k].norm()) + " |numeric| " +
                     std::to_string(numeric.norm()) + " relative error " + std::to_string(err) +
                     "\n";
    if (!(err <= result.max_error)) {
      result.max_error = err;
      result.worst_input = static_cast<int>(k);
    }
  }
  return result;
}

/// A random matrix with entries uniform in [lo, hi].
inline Matrix<double> random_matrix(Eigen::Index rows, Eigen::Index cols, Rng& rng, double lo = -1,
                                    double hi = 1) {
  Matrix<double> m(rows, cols);
  for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = rng.uniform(lo, hi);
  return m;
}

/// The same in [-1, 1] as T from a seed of its own (tests of the product kernels).
template <class T>
Matrix<T> seeded_matrix(Eigen::Index rows, Eigen::Index cols, std::uint64_t seed) {
  Rng rng(seed, 3);
  return random_matrix(rows, cols, rng).cast<T>();
}

}  // namespace df::nn
