#include "nn/adam.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"

namespace df::nn {

namespace {

double scheduled_rate(const AdamOptions& opt, double t) {
  switch (opt.schedule) {
    case AdamOptions::Schedule::exponential:
      return opt.lr * std::pow(opt.decay_rate, t / opt.decay_steps);
    case AdamOptions::Schedule::step:
      return opt.lr * std::pow(opt.decay_rate, std::floor(t / opt.decay_steps));
    default:
      return opt.lr;
  }
}

double rate_at(const AdamOptions& opt, long step) {
  const double t = static_cast<double>(step);
  const double rate = scheduled_rate(opt, t);
  return opt.warmup_steps > 0 ? rate * std::min(1.0, (t + 1) / opt.warmup_steps) : rate;
}

}  // namespace

template <class T>
Adam<T>::Adam(std::size_t n_parameters, AdamOptions opt)
    : opt_(std::move(opt)), m_(Vector<T>::Zero(static_cast<Eigen::Index>(n_parameters))), v_(m_) {
  auto& ranges = opt_.scaled;
  std::sort(ranges.begin(), ranges.end(),
            [](const auto& a, const auto& b) { return a.offset < b.offset; });
  Eigen::Index at = 0;
  for (const auto& r : ranges) {
    if (r.offset < at || r.size < 0 || r.offset + r.size > m_.size())
      throw Error("internal: Adam's scaled ranges overlap or leave the parameters");
    at = r.offset + r.size;
  }
}

template <class T>
double Adam<T>::learning_rate() const {
  return rate_at(opt_, t_);
}

template <class T>
typename Adam<T>::StepSizes Adam<T>::last_step_sizes() const {
  if (t_ == 0) return {&v_, T(0), T(1), T(1), nullptr};
  return {&v_, static_cast<T>(rate_at(opt_, t_ - 1)),
          static_cast<T>(1.0 - std::pow(opt_.beta2, static_cast<double>(t_))),
          static_cast<T>(opt_.eps), opt_.scaled.empty() ? nullptr : &opt_.scaled};
}

template <class T>
void Adam<T>::step(Vector<T>& values, Vector<T>& grads) {
  if (values.size() != m_.size() || grads.size() != m_.size())
    throw Error("internal: Adam sized for another model");
  if (opt_.weight_decay != 0) grads += static_cast<T>(opt_.weight_decay) * values;
  if (opt_.clip_norm > 0) {
    const double norm = static_cast<double>(grads.norm());
    if (norm > opt_.clip_norm) grads *= static_cast<T>(opt_.clip_norm / norm);
  }
  const double lr = learning_rate();
  ++t_;
  const T b1 = static_cast<T>(opt_.beta1), b2 = static_cast<T>(opt_.beta2);
  const T c1 = static_cast<T>(1.0 - std::pow(opt_.beta1, static_cast<double>(t_)));
  const T c2 = static_cast<T>(1.0 - std::pow(opt_.beta2, static_cast<double>(t_)));
  const T step = static_cast<T>(lr), eps = static_cast<T>(opt_.eps);
  m_ = b1 * m_ + (T(1) - b1) * grads;
  v_ = b2 * v_ + (T(1) - b2) * grads.cwiseProduct(grads);
  // Coordinates [begin, end) at rate `rate`: each element's update as one expression, so a
  // coordinate outside every scaled range moves exactly as without them.
  auto update = [&](Eigen::Index begin, Eigen::Index end, T rate) {
    if (end <= begin) return;
    const Eigen::Index n = end - begin;
    values.segment(begin, n).array() -= rate * (m_.segment(begin, n).array() / c1) /
                                        ((v_.segment(begin, n).array() / c2).sqrt() + eps);
  };
  if (opt_.scaled.empty()) {
    update(0, values.size(), step);
    return;
  }
  Eigen::Index at = 0;
  for (const auto& r : opt_.scaled) {  // sorted and checked when constructed
    update(at, r.offset, step);
    update(r.offset, r.offset + r.size, step * static_cast<T>(r.scale));
    at = r.offset + r.size;
  }
  update(at, values.size(), step);
}

template class Adam<float>;
template class Adam<double>;

}  // namespace df::nn
