// nn/ops.h's operations on float (definitions: ops_impl.h).
#include "nn/ops_impl.h"

namespace df::nn {
DF_NN_OPS(float)
}  // namespace df::nn
