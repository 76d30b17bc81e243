// One LSTM layer over a whole sequence as one tape node (see layers.h). Forward: the input
// products of all steps are one matrix product, then the steps run in order, each adding
// h_{t-1} W_h. Backward: back through time for the gate gradients dZ (each step one product
// with W_hᵀ), then the weight and input gradients of all steps as one product each. Every
// product's right-hand side is packed once (packed_product.h): W_x, W_h for the forward steps,
// W_hᵀ for the backward steps, dZ for both weight gradients, W_xᵀ for the input gradient.
#include <fmt/format.h>

#include "core/error.h"
#include "nn/layers.h"
#include "nn/packed_product.h"

namespace df::nn {
namespace {
using detail::pack_rhs;
using detail::packed_product;
using detail::packed_product_into_grad;
using Eigen::Index;

// Activates the pre-activations z [B, 4H] in place: i, f, o sigmoid; g tanh.
template <class Z>
void activate_gates(Z&& z, Index H) {
  z.leftCols(2 * H).array() = z.leftCols(2 * H).array().logistic();
  z.middleCols(2 * H, H).array() = z.middleCols(2 * H, H).array().tanh();
  z.rightCols(H).array() = z.rightCols(H).array().logistic();
}

// The order in which the steps run: step s is time index step_index(s).
struct StepOrder {
  Index steps;
  bool reverse;
  Index operator()(Index s) const { return reverse ? steps - 1 - s : s; }
};

// One step back through time: the gate gradients dz of a step (gates z, activated; its cell and
// the previous one) from dh and dc, the gradients reaching its output and its cell; dc is then
// carried to the previous step.
template <class Zs, class Cp, class Cs, class Dh, class Dc, class Dz>
void step_back(const Zs& z, const Cp& c_prev, const Cs& cell, const Dh& dh, Dc& dc, Dz&& dz,
               Index H) {
  using T = typename Dh::Scalar;
  const auto i = z.leftCols(H).array(), f = z.middleCols(H, H).array(),
             g = z.middleCols(2 * H, H).array(), o = z.rightCols(H).array();
  const Eigen::Array<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> tc = cell.array().tanh();
  dc.array() += dh.array() * o * (T(1) - tc.square());
  dz.leftCols(H).array() = dc.array() * g * i * (T(1) - i);
  dz.middleCols(H, H).array() = dc.array() * c_prev.array() * f * (T(1) - f);
  dz.middleCols(2 * H, H).array() = dc.array() * i * (T(1) - g.square());
  dz.rightCols(H).array() = dh.array() * tc * o * (T(1) - o);
  dc.array() *= f;
}

}  // namespace

template <class T>
Var<T> lstm_sequence(Var<T> x, Var<T> wx, Var<T> wh, Var<T> b, Var<T> h0, Var<T> c0, bool reverse) {
  Tape<T>& t = *x.tape;
  const Index B = h0.rows(), H = wh.rows(), TB = x.rows();
  if (B == 0 || TB % B != 0 || wx.rows() != x.cols() || wx.cols() != 4 * H || wh.cols() != 4 * H ||
      b.rows() != 1 || b.cols() != 4 * H || h0.cols() != H || c0.rows() != B || c0.cols() != H)
    throw Error(fmt::format(
        "internal: lstm_sequence of x [{},{}], W_x [{},{}], W_h [{},{}], h0 [{},{}]", x.rows(),
        x.cols(), wx.rows(), wx.cols(), wh.rows(), wh.cols(), h0.rows(), h0.cols()));
  const StepOrder order{TB / B, reverse};
  // Gates of every step [T·B, 4H] (activated) and cells [T·B, H], kept for backward.
  auto gates = std::make_shared<Matrix<T>>(TB, 4 * H);
  auto cells = std::make_shared<Matrix<T>>(TB, H);
  Matrix<T> out(TB, H);
  packed_product<T>(*gates, x.value(), pack_rhs(wx.value(), false), false);
  gates->rowwise() += b.value().row(0);
  const auto wh_packed = pack_rhs(wh.value(), false);
  for (Index s = 0; s < order.steps; ++s) {
    const Index r = order(s) * B, rp = s ? order(s - 1) * B : -1;
    auto z = gates->middleRows(r, B);
    if (s)
      packed_product<T>(z, out.middleRows(rp, B), wh_packed, true);
    else
      packed_product<T>(z, h0.value(), wh_packed, true);
    activate_gates(z, H);
    const Eigen::Map<const Matrix<T>> c_prev(s ? cells->data() + rp * H : c0.value().data(), B, H);
    cells->middleRows(r, B) = z.middleCols(H, H).cwiseProduct(c_prev) +
                              z.leftCols(H).cwiseProduct(z.middleCols(2 * H, H));
    out.middleRows(r, B) =
        z.rightCols(H).cwiseProduct(cells->middleRows(r, B).array().tanh().matrix());
  }
  const int ix = x.id, iwx = wx.id, iwh = wh.id, ib = b.id, ih = h0.id, ic = c0.id,
            io = static_cast<int>(t.size());
  const double flops = 2.0 * double(TB) * double(x.cols() + H) * double(4 * H);  // the products
  const bool rg = x.requires_grad() || wx.requires_grad() || wh.requires_grad() ||
                  b.requires_grad() || h0.requires_grad() || c0.requires_grad();
  return t.record(
      std::move(out), rg,
      [&t, gates, cells, order, B, H, ix, iwx, iwh, ib, ih, ic, io] {
        const Matrix<T>& G = t.grad(io);
        const Matrix<T>& Hs = t.value(io);
        const Index TB = G.rows();
        Matrix<T> dZ(TB, 4 * H), dh = Matrix<T>::Zero(B, H), dc = Matrix<T>::Zero(B, H);
        const auto wht_packed = pack_rhs(t.value(iwh), true);
        for (Index s = order.steps - 1; s >= 0; --s) {
          const Index r = order(s) * B, rp = s ? order(s - 1) * B : -1;
          const Eigen::Map<const Matrix<T>> c_prev(s ? cells->data() + rp * H : t.value(ic).data(),
                                                   B, H);
          dh += G.middleRows(r, B);
          step_back(gates->middleRows(r, B), c_prev, cells->middleRows(r, B), dh, dc,
                    dZ.middleRows(r, B), H);
          if (s || t.requires_grad(ih))
            packed_product<T>(dh, dZ.middleRows(r, B), wht_packed, false);
        }
        if (t.requires_grad(ih)) t.grad(ih) += dh;
        if (t.requires_grad(ic)) t.grad(ic) += dc;
        const detail::PackedRhs<T> dz_packed = t.requires_grad(iwh) || t.requires_grad(iwx)
                                                   ? pack_rhs(dZ, false)
                                                   : detail::PackedRhs<T>{};
        if (t.requires_grad(
                iwh)) {  // Σ_t h_{t-1}ᵀ dZ_t as one product: the previous h of every step
          Matrix<T> h_prev(TB, H);
          for (Index s = 0; s < order.steps; ++s)
            h_prev.middleRows(order(s) * B, B) =
                s ? Hs.middleRows(order(s - 1) * B, B) : t.value(ih);
          packed_product_into_grad(t, iwh, h_prev.transpose(), dz_packed);
        }
        if (t.requires_grad(iwx))
          packed_product_into_grad(t, iwx, t.value(ix).transpose(), dz_packed);
        if (t.requires_grad(ib)) t.add_to_grad(ib, dZ.colwise().sum());
        if (t.requires_grad(ix)) packed_product_into_grad(t, ix, dZ, pack_rhs(t.value(iwx), true));
      },
      {flops, 2 * flops});
}

template Var<float> lstm_sequence(Var<float>, Var<float>, Var<float>, Var<float>, Var<float>,
                                  Var<float>, bool);
template Var<double> lstm_sequence(Var<double>, Var<double>, Var<double>, Var<double>, Var<double>,
                                   Var<double>, bool);

}  // namespace df::nn
