// x · W for a weight that one tape multiplies many times (ops.h): the per-step layers of a
// recurrent model — BD-LSTM's fully-connected encoder and decoder layers, [26,136 × 256] and
// [128 × 26,136] on pcow, multiplied at each of 31 steps. A plain matmul lets Eigen pack W again
// at every step, forward and backward, and adds each step's weight gradient into the whole
// [26,136 × 256] gradient: Eigen's packing was a quarter of a BD-LSTM iteration. Here W is
// packed once per tape for the forward products and Wᵀ once for the backward ones (the packed
// copies live with W's node), and W's gradient is one product over the stacked inputs and output
// gradients of all its uses, run when the backward pass reaches W (pcow, one thread: 1,843 →
// 1,362 ms per iteration; the packed copies take 80 MB, and the peak grew by 174 MiB).
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/error.h"
#include "nn/ops.h"
#include "nn/packed_product.h"

namespace df::nn {
namespace {
using detail::PackedRhs;
using Eigen::Index;

// Kept with W's node (Tape::op_state).
template <class T>
struct RepeatedWeight {
  std::optional<PackedRhs<T>> w, wt;  // W, Wᵀ: packed on first use
  struct Use {
    int x, out;  // nodes: the product's input and its result
  };
  std::vector<Use> uses;  // of this backward pass, in the order backward reached them
};

template <class T>
RepeatedWeight<T>& state_of(Tape<T>& t, int id) {
  auto& s = t.op_state(id);
  if (!s) s = std::make_shared<RepeatedWeight<T>>();
  return *std::static_pointer_cast<RepeatedWeight<T>>(s);
}

// W's gradient (+)= Σ_uses x_uᵀ · g_u = Xᵀ · G, X and G the uses' rows stacked: one product with
// a depth of all the uses' rows instead of one pass over W's gradient per use. Every element is
// one running sum over the stacked rows in a fixed order, so the bits do not depend on threads.
template <class T>
void weight_gradient(Tape<T>& t, int iw, std::vector<typename RepeatedWeight<T>::Use> uses) {
  Index rows = 0;
  for (const auto& u : uses) rows += t.value(u.x).rows();
  const Index in = t.value(iw).rows(), out = t.value(iw).cols();
  Matrix<T> xt(in, rows), g(rows, out);  // Xᵀ (rows of A contiguous) and G
  Index r = 0;
  for (const auto& u : uses) {
    const Index n = t.value(u.x).rows();
    xt.middleCols(r, n) = t.value(u.x).transpose();
    g.middleRows(r, n) = t.grad(u.out);
    r += n;
  }
  detail::packed_product_into_grad(t, iw, xt, detail::pack_rhs(g, false));
}

}  // namespace

template <class T>
Var<T> matmul_repeated(Var<T> x, Var<T> w) {
  Tape<T>& t = *x.tape;
  if (w.tape != x.tape) throw Error("internal: operands on different tapes");
  if (x.cols() != w.rows())
    throw Error(fmt::format("internal: matmul_repeated of [{},{}] and [{},{}]: incompatible shapes",
                            x.rows(), x.cols(), w.rows(), w.cols()));
  const int ix = x.id, iw = w.id, io = static_cast<int>(t.size());
  RepeatedWeight<T>& s = state_of(t, iw);
  if (!s.w) s.w = detail::pack_rhs(w.value(), false);
  Matrix<T> y(x.rows(), w.cols());
  detail::packed_product<T>(y, x.value(), *s.w, false);
  const double flops = 2.0 * double(x.rows()) * double(x.cols()) * double(w.cols());
  return t.record(std::move(y), x.requires_grad() || w.requires_grad(),
                  [&t, ix, iw, io] {
                    RepeatedWeight<T>& s = state_of(t, iw);
                    if (t.requires_grad(ix)) {
                      if (!s.wt) s.wt = detail::pack_rhs(t.value(iw), true);
                      detail::packed_product_into_grad(t, ix, t.grad(io), *s.wt);
                    }
                    if (t.requires_grad(iw)) {
                      if (s.uses.empty())
                        t.when_backward_reaches(
                            iw,
                            [&t, iw] {
                              RepeatedWeight<T>& s = state_of(t, iw);
                              weight_gradient(t, iw, std::exchange(s.uses, {}));
                            },
                            "matmul_repeated");
                      s.uses.push_back({ix, io});
                    }
                  },
                  {flops, flops * (x.requires_grad() + w.requires_grad())});
}

template Var<float> matmul_repeated(Var<float>, Var<float>);
template Var<double> matmul_repeated(Var<double>, Var<double>);

}  // namespace df::nn
