#include "nn/adam.h"

#include <cmath>

#include "core/error.h"

namespace df::nn {

template <class T>
double Adam<T>::learning_rate() const {
  const double t = static_cast<double>(t_);
  switch (opt_.schedule) {
    case AdamOptions::Schedule::exponential: return opt_.lr * std::pow(opt_.decay_rate, t / opt_.decay_steps);
    case AdamOptions::Schedule::step: return opt_.lr * std::pow(opt_.decay_rate, std::floor(t / opt_.decay_steps));
    default: return opt_.lr;
  }
}

template <class T>
void Adam<T>::step(Vector<T>& values, Vector<T>& grads) {
  if (values.size() != m_.size() || grads.size() != m_.size()) throw Error("internal: Adam sized for another model");
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
  values.array() -= step * (m_.array() / c1) / ((v_.array() / c2).sqrt() + eps);
}

template class Adam<float>;
template class Adam<double>;

}  // namespace df::nn
