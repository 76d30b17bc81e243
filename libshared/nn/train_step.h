// One training iteration: clear the tape, zero the gradients, bind the parameters, build the
// loss, backpropagate, collect the gradients into the store and take an Adam step.
#pragma once

#include <functional>

#include "nn/adam.h"
#include "nn/parameters.h"

namespace df::nn {

/// @param loss  records the forward pass on the tape and returns a 1×1 loss
/// @return the loss value
template <class T>
T train_step(Tape<T>& tape, ParameterStore<T>& store, Adam<T>& adam,
             const std::function<Var<T>(Tape<T>&, const Bound<T>&)>& loss) {
  tape.clear();
  store.zero_grad();
  Bound<T> p = store.bind(tape);
  Var<T> l = loss(tape, p);
  tape.backward(l);
  store.collect(p);
  adam.step(store.values(), store.grads());
  return l.value()(0, 0);
}

}  // namespace df::nn
