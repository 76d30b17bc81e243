// One training iteration: clear the tape, zero the gradients, bind the parameters, build the
// loss, backpropagate, collect the gradients into the store and take an Adam step — for one
// store, or for several (a GAN's generator trained against a discriminator it only reads).
#pragma once

#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "nn/adam.h"
#include "nn/parameters.h"

namespace df::nn {

/// One parameter store of a training step: trained by `adam` (its gradient zeroed, collected and
/// stepped), or bound as constants when `adam` is null (a network the step reads but does not
/// train). A trained store's parameters named with `frozen_prefix` stay constants too.
template <class T>
struct StepStore {
  ParameterStore<T>* store = nullptr;
  Adam<T>* adam = nullptr;
  std::string_view frozen_prefix = {};
};

/// One step over several stores: clears the tape, zeroes the trained stores' gradients, binds
/// every store in the order given, builds the loss (`loss(tape, bound)`, bound[i] the binding of
/// stores[i]), backpropagates, then collects and steps each trained store in order.
/// @return the loss (a 1×1 variable of `tape`, alive until the tape is cleared)
template <class T>
Var<T> train_step(Tape<T>& tape, std::span<const StepStore<T>> stores,
                  const std::function<Var<T>(Tape<T>&, const std::vector<Bound<T>>&)>& loss) {
  tape.clear();
  for (const StepStore<T>& s : stores)
    if (s.adam) s.store->zero_grad();
  std::vector<Bound<T>> bound;
  bound.reserve(stores.size());
  for (const StepStore<T>& s : stores)
    bound.push_back(!s.adam                   ? s.store->bind_constant(tape)
                    : s.frozen_prefix.empty() ? s.store->bind(tape)
                                              : s.store->bind_except(tape, s.frozen_prefix));
  Var<T> l = loss(tape, bound);
  tape.backward(l);
  for (std::size_t i = 0; i < stores.size(); ++i)
    if (stores[i].adam) {
      stores[i].store->collect(bound[i]);
      stores[i].adam->step(stores[i].store->values(), stores[i].store->grads());
    }
  return l;
}

/// The one-store step. @param loss  records the forward pass on the tape and returns a 1×1 loss
/// @return the loss value
template <class T>
T train_step(Tape<T>& tape, ParameterStore<T>& store, Adam<T>& adam,
             const std::function<Var<T>(Tape<T>&, const Bound<T>&)>& loss) {
  const StepStore<T> one[] = {{&store, &adam}};
  return train_step<T>(tape, one,
                       [&](Tape<T>& t, const std::vector<Bound<T>>& p) { return loss(t, p[0]); })
      .value()(0, 0);
}

}  // namespace df::nn
