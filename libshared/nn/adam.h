// Adam (Kingma & Ba) over a ParameterStore's flat vectors, with bias correction, learning-rate
// schedules (exponential decay, step), an L2 weight penalty (added to the gradient) and
// gradient-norm clipping (global L2 norm). Its state (moments, step) is plain vectors, so a
// model file can save it and training resumes bit-exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "nn/parameters.h"

namespace df::nn {

struct AdamOptions {
  double lr = 1e-3, beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  double weight_decay = 0;  ///< L2 penalty λ: g += λ θ
  double clip_norm = 0;     ///< 0 = no clipping; else scale g so that ‖g‖₂ ≤ clip_norm
  enum class Schedule { constant, exponential, step } schedule = Schedule::constant;
  double decay_rate =
      1.0;  ///< exponential: lr·rate^(step/decay_steps); step: lr·rate^⌊step/decay_steps⌋
  double decay_steps = 1.0;
  /// 0 = none; else the rate rises linearly over the first N steps: × min(1, (step + 1) / N)
  double warmup_steps = 0;
  /// Coordinates [offset, offset + size) that step at `scale` × the rate (a part of the model
  /// that learns slower than the rest); the ranges must not overlap. Empty: every coordinate alike.
  struct RateScale {
    Eigen::Index offset = 0, size = 0;
    double scale = 1;
  };
  std::vector<RateScale> scaled;
};

template <class T>
class Adam {
 public:
  /// Throws when opt.scaled's ranges overlap or leave the n_parameters (kept sorted by offset).
  Adam(std::size_t n_parameters, AdamOptions opt);

  /// One update of `values` from `grads` (grads may be modified: penalty, clipping).
  void step(Vector<T>& values, Vector<T>& grads);
  /// The learning rate used by the next step.
  double learning_rate() const;

  /// Adam's diagonal preconditioner after the last step(): coordinate j moved by
  /// (m̂_j / c₁) · size(j), size(j) = rate / (√(v_j / c₂) + ε). A proximal step on a penalty that
  /// was left out of the gradient scales its threshold by it. All zero before the first step.
  struct StepSizes {
    const Vector<T>* v = nullptr;
    T rate = 0, c2 = 1, eps = 0;
    const std::vector<AdamOptions::RateScale>* scaled = nullptr;
    T operator()(Eigen::Index j) const { return at_rate(j, rate_of(j)); }
    /// Coordinate j's step size given its rate.
    T at_rate(Eigen::Index j, T r) const { return r / (std::sqrt((*v)(j) / c2) + eps); }
    /// The rate of coordinate j (AdamOptions::scaled applied; the ranges sorted by offset).
    T rate_of(Eigen::Index j) const {
      T r;
      rates_of(j, 1, &r);
      return r;
    }
    /// rate_of(j) for j in [first, first + n), into out: one search, then a walk over the ranges.
    void rates_of(Eigen::Index first, Eigen::Index n, T* out) const {
      if (!scaled) {
        std::fill(out, out + n, rate);
        return;
      }
      auto r = std::upper_bound(scaled->begin(), scaled->end(), first,
                                [](Eigen::Index i, const auto& range) { return i < range.offset; });
      if (r != scaled->begin()) --r;  // the last range starting at or before first, if any
      for (Eigen::Index j = first; j < first + n; ++j) {
        while (r != scaled->end() && j >= r->offset + r->size) ++r;
        out[j - first] =
            r != scaled->end() && j >= r->offset ? rate * static_cast<T>(r->scale) : rate;
      }
    }
  };
  StepSizes last_step_sizes() const;

  long steps() const { return t_; }
  Vector<T>& first_moment() { return m_; }
  Vector<T>& second_moment() { return v_; }
  const Vector<T>& first_moment() const { return m_; }
  const Vector<T>& second_moment() const { return v_; }
  void set_steps(long t) { t_ = t; }
  const AdamOptions& options() const { return opt_; }

 private:
  AdamOptions opt_;
  Vector<T> m_, v_;
  long t_ = 0;
};

extern template class Adam<float>;
extern template class Adam<double>;

}  // namespace df::nn
