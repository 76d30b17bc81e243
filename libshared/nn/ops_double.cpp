// nn/ops.h's operations on double (definitions: ops_impl.h).
#include "nn/ops_impl.h"

namespace df::nn {
DF_NN_OPS(double)
}  // namespace df::nn
