// The definitions of nn/ops.h, included only by ops_float.cpp and ops_double.cpp, each of which
// instantiates them for one element type with DF_NN_OPS: two translation units that compile in
// parallel (as one they were the library's longest compile, 86 s of a 2-core build's path).
#pragma once

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>

#include "core/error.h"
#include "nn/ops.h"
#include "nn/parallel_product.h"

namespace df::nn {
namespace {
using detail::parallel_product;
using detail::product_into_grad;
using Eigen::Index;

template <class T>
Tape<T>& same_tape(Var<T> a, Var<T> b) {
  if (a.tape != b.tape || !a.tape) throw Error("internal: operands on different tapes");
  return *a.tape;
}

template <class T>
[[noreturn]] void shape_error(const char* op, Var<T> a, Var<T> b) {
  throw Error(fmt::format("internal: {} of [{},{}] and [{},{}]: incompatible shapes", op, a.rows(),
                          a.cols(), b.rows(), b.cols()));
}

// Broadcast result shape: each axis equal, or one side 1.
template <class T>
std::pair<Index, Index> broadcast_shape(const char* op, Var<T> a, Var<T> b) {
  auto axis = [&](Index x, Index y) -> Index {
    if (x == y || y == 1) return x;
    if (x == 1) return y;
    shape_error(op, a, b);
  };
  return {axis(a.rows(), b.rows()), axis(a.cols(), b.cols())};
}

template <class T>
Matrix<T> expand(const Matrix<T>& m, Index rows, Index cols) {
  if (m.rows() == rows && m.cols() == cols) return m;
  if (m.rows() == 1 && m.cols() == 1) return Matrix<T>::Constant(rows, cols, m(0, 0));
  if (m.rows() == 1) return m.replicate(rows, 1);
  return m.replicate(1, cols);
}

// f(a, b) element-wise on arrays, b broadcast to a's shape [rows, cols] when it is smaller:
// without copying operands of the full shape (the common cases: equal shapes, a bias row).
template <class T, class F>
Matrix<T> broadcast_apply(const Matrix<T>& a, const Matrix<T>& b, Index rows, Index cols, F f) {
  const bool a_full = a.rows() == rows && a.cols() == cols,
             b_full = b.rows() == rows && b.cols() == cols;
  if (a_full && b_full) return f(a.array(), b.array()).matrix();
  if (a_full && b.rows() == 1 && b.cols() == cols) {
    Matrix<T> out(rows, cols);
    for (Index r = 0; r < rows; ++r) out.row(r).array() = f(a.row(r).array(), b.row(0).array());
    return out;
  }
  return f(expand(a, rows, cols).array(), expand(b, rows, cols).array()).matrix();
}

// Sums g over the axes along which a [rows, cols] operand was broadcast.
template <class T>
Matrix<T> reduce_to(const Matrix<T>& g, Index rows, Index cols) {
  if (g.rows() == rows && g.cols() == cols) return g;
  if (rows == 1 && cols == 1) return Matrix<T>::Constant(1, 1, g.sum());
  if (rows == 1) return g.colwise().sum();
  return g.rowwise().sum();
}

// Adds g (reduced to the node's shape) into node id's gradient, if it wants one.
template <class T, class Expr>
void accumulate(Tape<T>& t, int id, const Expr& g) {
  if (!t.requires_grad(id)) return;
  const Index rows = t.value(id).rows(), cols = t.value(id).cols();
  if (g.rows() == rows && g.cols() == cols)
    t.add_to_grad(id, g);
  else
    t.add_to_grad(id, reduce_to(Matrix<T>(g), rows, cols));
}

// The id the next recorded node will get (closures capture it before recording).
template <class T>
int next_id(const Tape<T>& t) {
  return static_cast<int>(t.size());
}

// Element-wise unary op on Eigen arrays (vectorised): out = f(A); dA += G ∘ d(A, OUT), where
// f and d return array expressions.
// Large arrays are processed in fixed chunks in parallel (element-wise: any split gives the
// same bits).
constexpr Index kChunk = 1 << 15;

template <class Fn>
void for_chunks(Index n, Fn fn) {
  if (n <= 2 * kChunk) {
    fn(Index{0}, n);
    return;
  }
  tbb::parallel_for(Index{0}, (n + kChunk - 1) / kChunk,
                    [&](Index c) { fn(c * kChunk, std::min(kChunk, n - c * kChunk)); });
}

template <class T, class F, class D>
Var<T> unary(Var<T> a, F f, D d, const char* where = __builtin_FUNCTION()) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  Matrix<T> out(a.rows(), a.cols());
  {
    using Flat = Eigen::Map<Eigen::Array<T, Eigen::Dynamic, 1>>;
    using ConstFlat = Eigen::Map<const Eigen::Array<T, Eigen::Dynamic, 1>>;
    const T* x = a.value().data();
    T* y = out.data();
    for_chunks(out.size(), [&](Index k, Index n) { Flat(y + k, n) = f(ConstFlat(x + k, n)); });
  }
  return t.record(
      std::move(out), a.requires_grad(),
      [&t, ia, io, d] {
        using Flat = Eigen::Map<Eigen::Array<T, Eigen::Dynamic, 1>>;
        using ConstFlat = Eigen::Map<const Eigen::Array<T, Eigen::Dynamic, 1>>;
        bool add = false;
        T* ga = t.grad_to_update(ia, add).data();
        const T *go = t.grad(io).data(), *x = t.value(ia).data(), *y = t.value(io).data();
        for_chunks(t.value(io).size(), [&](Index k, Index n) {
          if (add)
            Flat(ga + k, n) += ConstFlat(go + k, n) * d(ConstFlat(x + k, n), ConstFlat(y + k, n));
          else
            Flat(ga + k, n) = ConstFlat(go + k, n) * d(ConstFlat(x + k, n), ConstFlat(y + k, n));
        });
      },
      {}, where);
}

}  // namespace

// --- linear algebra

template <class T>
Var<T> matmul(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  if (a.cols() != b.rows()) shape_error("matmul", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out(a.rows(), b.cols());
  parallel_product<T>(out, a.value(), b.value(), false);
  const double flops = 2.0 * double(a.rows()) * double(a.cols()) * double(b.cols());
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(),
                  [&t, ia, ib, io] {
                    const Matrix<T>& g = t.grad(io);
                    if (t.requires_grad(ia)) product_into_grad(t, ia, g, t.value(ib).transpose());
                    if (t.requires_grad(ib)) product_into_grad(t, ib, t.value(ia).transpose(), g);
                  },
                  {flops, flops * (a.requires_grad() + b.requires_grad())});
}

template <class T>
Var<T> matmul_transposed(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  if (a.cols() != b.cols()) shape_error("matmul_transposed", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out(a.rows(), b.rows());
  parallel_product<T>(out, a.value(), b.value().transpose(), false);
  const double flops = 2.0 * double(a.rows()) * double(a.cols()) * double(b.rows());
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(),
                  [&t, ia, ib, io] {
                    const Matrix<T>& g = t.grad(io);
                    if (t.requires_grad(ia)) product_into_grad(t, ia, g, t.value(ib));
                    if (t.requires_grad(ib)) product_into_grad(t, ib, g.transpose(), t.value(ia));
                  },
                  {flops, flops * (a.requires_grad() + b.requires_grad())});
}

template <class T>
Var<T> sparse_matmul(std::shared_ptr<const SparseMatrix<T>> s, Var<T> x) {
  Tape<T>& t = *x.tape;
  if (s->cols() != x.rows())
    throw Error(fmt::format("internal: sparse_matmul of [{},{}] and [{},{}]", s->rows(), s->cols(),
                            x.rows(), x.cols()));
  const int ix = x.id, io = next_id(t);
  Matrix<T> out = (*s) * x.value();
  const double flops = 2.0 * double(s->nonZeros()) * double(x.cols());
  return t.record(std::move(out), x.requires_grad(),
                  [&t, s, ix, io] { t.grad(ix).noalias() += s->transpose() * t.grad(io); },
                  {flops, flops});
}

template <class T>
Var<T> transpose(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(a.value().transpose(), a.requires_grad(),
                  [&t, ia, io] { t.grad(ia) += t.grad(io).transpose(); });
}

// --- element-wise with broadcasting

template <class T>
Var<T> add(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  auto [r, c] = broadcast_shape("add", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out = a.rows() == r && a.cols() == c
                      ? broadcast_apply<T>(a.value(), b.value(), r, c,
                                           [](const auto& x, const auto& y) { return x + y; })
                      : broadcast_apply<T>(b.value(), a.value(), r, c,
                                           [](const auto& y, const auto& x) { return x + y; });
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(), [&t, ia, ib, io] {
    accumulate(t, ia, t.grad(io));
    accumulate(t, ib, t.grad(io));
  });
}

template <class T>
Var<T> sub(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  auto [r, c] = broadcast_shape("sub", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out = a.rows() == r && a.cols() == c
                      ? broadcast_apply<T>(a.value(), b.value(), r, c,
                                           [](const auto& x, const auto& y) { return x - y; })
                      : broadcast_apply<T>(b.value(), a.value(), r, c,
                                           [](const auto& y, const auto& x) { return x - y; });
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(), [&t, ia, ib, io] {
    accumulate(t, ia, t.grad(io));
    accumulate(t, ib, -t.grad(io));
  });
}

template <class T>
Var<T> mul(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  auto [r, c] = broadcast_shape("mul", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out = a.rows() == r && a.cols() == c
                      ? broadcast_apply<T>(a.value(), b.value(), r, c,
                                           [](const auto& x, const auto& y) { return x * y; })
                      : broadcast_apply<T>(b.value(), a.value(), r, c,
                                           [](const auto& y, const auto& x) { return x * y; });
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(), [&t, ia, ib, io] {
    const Matrix<T>& g = t.grad(io);
    auto product = [&](int other) {  // g ∘ the other operand, broadcast
      return broadcast_apply<T>(g, t.value(other), g.rows(), g.cols(),
                                [](const auto& x, const auto& y) { return x * y; });
    };
    if (t.requires_grad(ia)) accumulate(t, ia, product(ib));
    if (t.requires_grad(ib)) accumulate(t, ib, product(ia));
  });
}

template <class T>
Var<T> div(Var<T> a, Var<T> b) {
  Tape<T>& t = same_tape(a, b);
  auto [r, c] = broadcast_shape("div", a, b);
  const int ia = a.id, ib = b.id, io = next_id(t);
  Matrix<T> out = expand(a.value(), r, c).cwiseQuotient(expand(b.value(), r, c));
  return t.record(std::move(out), a.requires_grad() || b.requires_grad(), [&t, ia, ib, io] {
    const Matrix<T>& g = t.grad(io);
    Matrix<T> B = expand(t.value(ib), g.rows(), g.cols());
    if (t.requires_grad(ia)) accumulate<T>(t, ia, g.cwiseQuotient(B));
    if (t.requires_grad(ib))  // d(a/b)/db = −(a/b)/b = −out/b
      accumulate<T>(t, ib, -g.cwiseProduct(t.value(io)).cwiseQuotient(B));
  });
}

template <class T>
Var<T> scale(Var<T> a, T s) {
  return unary(
      a, [s](const auto& x) { return s * x; },
      [s](const auto& x, const auto&) { return x * T(0) + s; });
}

template <class T>
Var<T> add_scalar(Var<T> a, T s) {
  return unary(
      a, [s](const auto& x) { return x + s; },
      [](const auto& x, const auto&) { return x * T(0) + T(1); });
}

// --- element-wise functions

template <class T>
Var<T> tanh(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.tanh(); },
      [](const auto&, const auto& y) { return T(1) - y.square(); });
}

template <class T>
Var<T> sigmoid(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.logistic(); },
      [](const auto&, const auto& y) { return y * (T(1) - y); });
}

template <class T>
Var<T> relu(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.max(T(0)); },
      [](const auto& x, const auto&) { return (x > T(0)).template cast<T>(); });
}

template <class T>
Var<T> leaky_relu(Var<T> a, T slope) {
  return unary(
      a, [slope](const auto& x) { return (x > T(0)).select(x, slope * x); },
      [slope](const auto& x, const auto&) {
        return (x > T(0)).select(x * T(0) + T(1), x * T(0) + slope);
      });
}

template <class T>
Var<T> exp(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.exp(); }, [](const auto&, const auto& y) { return y; });
}

template <class T>
Var<T> log(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.log(); },
      [](const auto& x, const auto&) { return x.inverse(); });
}

template <class T>
Var<T> abs(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.abs(); },
      [](const auto& x, const auto&) { return x.sign(); });
}

template <class T>
Var<T> square(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.square(); },
      [](const auto& x, const auto&) { return T(2) * x; });
}

template <class T>
Var<T> sqrt(Var<T> a) {
  return unary(
      a, [](const auto& x) { return x.sqrt(); },
      [](const auto&, const auto& y) { return (y > T(0)).select(T(0.5) * y.inverse(), y * T(0)); });
}

template <class T>
Var<T> clamp(Var<T> a, T lo, T hi) {
  return unary(
      a, [lo, hi](const auto& x) { return x.max(lo).min(hi); },
      [lo, hi](const auto& x, const auto&) { return ((x >= lo) && (x <= hi)).template cast<T>(); });
}

// --- reductions

template <class T>
Var<T> sum(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(Matrix<T>::Constant(1, 1, a.value().sum()), a.requires_grad(),
                  [&t, ia, io] { t.grad(ia).array() += t.grad(io)(0, 0); });
}

// Row sums of f(row r) into a vector (rows in parallel), then their sum in row order: the same
// value at any thread count.
template <class T, class F>
T ordered_row_sum(Index rows, F&& f) {
  std::vector<T> part(static_cast<std::size_t>(rows));
  tbb::parallel_for(Index{0}, rows, [&](Index r) { part[static_cast<std::size_t>(r)] = f(r); });
  T total = 0;
  for (T v : part) total += v;
  return total;
}

template <class T>
Var<T> sum_squares(Var<T> a, const Matrix<T>* row_weights) {
  Tape<T>& t = *a.tape;
  if (row_weights && (row_weights->rows() != a.rows() || row_weights->cols() != 1))
    throw Error("internal: sum_squares row weights must be [rows, 1]");
  const int ia = a.id, io = next_id(t);
  auto w = row_weights ? std::make_shared<const Matrix<T>>(*row_weights) : nullptr;
  const Matrix<T>& A = a.value();
  const T value = ordered_row_sum<T>(
      A.rows(), [&](Index r) { return (w ? (*w)(r, 0) : T(1)) * A.row(r).squaredNorm(); });
  return t.record(Matrix<T>::Constant(1, 1, value), a.requires_grad(), [&t, ia, io, w] {
    const T g = 2 * t.grad(io)(0, 0);
    Matrix<T>& G = t.grad(ia);
    const Matrix<T>& X = t.value(ia);
    tbb::parallel_for(Index{0}, X.rows(),
                      [&](Index r) { G.row(r) += (g * (w ? (*w)(r, 0) : T(1))) * X.row(r); });
  });
}

template <class T>
Var<T> dot_constant(Var<T> a, Matrix<T> c) {
  Tape<T>& t = *a.tape;
  if (c.rows() != a.rows() || c.cols() != a.cols())
    throw Error("internal: dot_constant of different shapes");
  const int ia = a.id, io = next_id(t);
  auto cc = std::make_shared<const Matrix<T>>(std::move(c));
  const Matrix<T>& A = a.value();
  const T value = ordered_row_sum<T>(A.rows(), [&](Index r) { return A.row(r).dot(cc->row(r)); });
  return t.record(Matrix<T>::Constant(1, 1, value), a.requires_grad(), [&t, ia, io, cc] {
    const T g = t.grad(io)(0, 0);
    Matrix<T>& G = t.grad(ia);
    tbb::parallel_for(Index{0}, G.rows(), [&](Index r) { G.row(r) += g * cc->row(r); });
  });
}

template <class T>
Var<T> mean(Var<T> a) {
  return scale(sum(a), T(1) / static_cast<T>(a.value().size()));
}

template <class T>
Var<T> sum_rows(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(a.value().colwise().sum(), a.requires_grad(),
                  [&t, ia, io] { t.grad(ia).rowwise() += t.grad(io).row(0); });
}

template <class T>
Var<T> sum_cols(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(a.value().rowwise().sum(), a.requires_grad(),
                  [&t, ia, io] { t.grad(ia).colwise() += t.grad(io).col(0); });
}

template <class T>
Var<T> mean_rows(Var<T> a) {
  return scale(sum_rows(a), T(1) / static_cast<T>(a.rows()));
}

template <class T>
Var<T> mean_cols(Var<T> a) {
  return scale(sum_cols(a), T(1) / static_cast<T>(a.cols()));
}

template <class T>
Var<T> max_rows(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  std::vector<Index> arg(static_cast<std::size_t>(a.cols()));
  Matrix<T> out(1, a.cols());
  for (Index c = 0; c < a.cols(); ++c)
    out(0, c) = a.value().col(c).maxCoeff(&arg[static_cast<std::size_t>(c)]);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io, arg] {
    for (std::size_t c = 0; c < arg.size(); ++c)
      t.grad(ia)(arg[c], static_cast<Index>(c)) += t.grad(io)(0, static_cast<Index>(c));
  });
}

template <class T>
Var<T> max_cols(Var<T> a) {
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  std::vector<Index> arg(static_cast<std::size_t>(a.rows()));
  Matrix<T> out(a.rows(), 1);
  for (Index r = 0; r < a.rows(); ++r)
    out(r, 0) = a.value().row(r).maxCoeff(&arg[static_cast<std::size_t>(r)]);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io, arg] {
    for (std::size_t r = 0; r < arg.size(); ++r)
      t.grad(ia)(static_cast<Index>(r), arg[r]) += t.grad(io)(static_cast<Index>(r), 0);
  });
}

// --- structure

template <class T>
Var<T> slice_rows(Var<T> a, Index first, Index count) {
  if (first < 0 || count < 0 || first + count > a.rows())
    throw Error("internal: slice_rows out of range");
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(
      a.value().middleRows(first, count), a.requires_grad(),
      [&t, ia, io, first, count] { t.grad(ia).middleRows(first, count) += t.grad(io); });
}

template <class T>
Var<T> slice_cols(Var<T> a, Index first, Index count) {
  if (first < 0 || count < 0 || first + count > a.cols())
    throw Error("internal: slice_cols out of range");
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  return t.record(
      a.value().middleCols(first, count), a.requires_grad(),
      [&t, ia, io, first, count] { t.grad(ia).middleCols(first, count) += t.grad(io); });
}

namespace {
// Concatenation along rows (stacked) or columns (side by side); the gradient of each part is
// its slice of the output's.
template <class T>
Var<T> concat(const std::vector<Var<T>>& parts, bool along_rows) {
  const char* name = along_rows ? "concat_rows" : "concat_cols";
  if (parts.empty()) throw Error(fmt::format("internal: {} of nothing", name));
  Tape<T>& t = *parts[0].tape;
  auto extent = [along_rows](const Matrix<T>& m) { return along_rows ? m.rows() : m.cols(); };
  auto other = [along_rows](const Matrix<T>& m) { return along_rows ? m.cols() : m.rows(); };
  const Index keep = other(parts[0].value());
  Index total = 0;
  bool rg = false;
  std::vector<int> ids;
  for (const auto& p : parts) {
    if (other(p.value()) != keep || p.tape != &t)
      throw Error(fmt::format("internal: {} of mismatched parts", name));
    total += extent(p.value());
    rg = rg || p.requires_grad();
    ids.push_back(p.id);
  }
  Matrix<T> out = along_rows ? Matrix<T>(total, keep) : Matrix<T>(keep, total);
  Index at = 0;
  for (const auto& p : parts) {
    const Index n = extent(p.value());
    if (along_rows)
      out.middleRows(at, n) = p.value();
    else
      out.middleCols(at, n) = p.value();
    at += n;
  }
  const int io = next_id(t);
  return t.record(std::move(out), rg, [&t, ids, io, along_rows, extent] {
    Index at = 0;
    for (int id : ids) {
      const Index n = extent(t.value(id));
      if (t.requires_grad(id)) {
        if (along_rows)
          t.grad(id) += t.grad(io).middleRows(at, n);
        else
          t.grad(id) += t.grad(io).middleCols(at, n);
      }
      at += n;
    }
  });
}
}  // namespace

template <class T>
Var<T> concat_rows(const std::vector<Var<T>>& parts) {
  return concat(parts, true);
}

template <class T>
Var<T> concat_cols(const std::vector<Var<T>>& parts) {
  return concat(parts, false);
}

template <class T>
Var<T> reshape(Var<T> a, Index rows, Index cols) {
  if (rows * cols != a.value().size())
    throw Error("internal: reshape changes the number of elements");
  Tape<T>& t = *a.tape;
  const int ia = a.id, io = next_id(t);
  Matrix<T> out = Eigen::Map<const Matrix<T>>(a.value().data(), rows, cols);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io] {
    Matrix<T>& ga = t.grad(ia);
    ga += Eigen::Map<const Matrix<T>>(t.grad(io).data(), ga.rows(), ga.cols());
  });
}

template <class T>
Var<T> gather_rows(Var<T> a, std::vector<int> index) {
  Tape<T>& t = *a.tape;
  Matrix<T> out(static_cast<Index>(index.size()), a.cols());
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (index[k] < 0 || index[k] >= a.rows())
      throw Error("internal: gather_rows index out of range");
    out.row(static_cast<Index>(k)) = a.value().row(index[k]);
  }
  const int ia = a.id, io = next_id(t);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io, index] {
    for (std::size_t k = 0; k < index.size(); ++k)
      t.grad(ia).row(index[k]) += t.grad(io).row(static_cast<Index>(k));
  });
}

template <class T>
Var<T> scatter_rows(Var<T> a, std::vector<int> index, Index n) {
  if (static_cast<Index>(index.size()) != a.rows())
    throw Error("internal: scatter_rows needs one index per row");
  Tape<T>& t = *a.tape;
  Matrix<T> out = Matrix<T>::Zero(n, a.cols());
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (index[k] < 0 || index[k] >= n) throw Error("internal: scatter_rows index out of range");
    out.row(index[k]) += a.value().row(static_cast<Index>(k));
  }
  const int ia = a.id, io = next_id(t);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io, index] {
    for (std::size_t k = 0; k < index.size(); ++k)
      t.grad(ia).row(static_cast<Index>(k)) += t.grad(io).row(index[k]);
  });
}

template <class T>
Var<T> group_norm(Var<T> a, Index g) {
  if (g <= 0 || a.cols() % g != 0)
    throw Error("internal: group_norm group size must divide the columns");
  Tape<T>& t = *a.tape;
  const Index groups = a.cols() / g;
  Matrix<T> out(a.rows(), groups);
  for (Index r = 0; r < a.rows(); ++r)
    for (Index j = 0; j < groups; ++j) out(r, j) = a.value().row(r).segment(j * g, g).norm();
  const int ia = a.id, io = next_id(t);
  return t.record(std::move(out), a.requires_grad(), [&t, ia, io, g, groups] {
    const Matrix<T>& x = t.value(ia);
    const Matrix<T>& y = t.value(io);
    const Matrix<T>& gy = t.grad(io);
    Matrix<T>& gx = t.grad(ia);
    for (Index r = 0; r < x.rows(); ++r)
      for (Index j = 0; j < groups; ++j)
        if (y(r, j) > 0)
          gx.row(r).segment(j * g, g) += (gy(r, j) / y(r, j)) * x.row(r).segment(j * g, g);
  });
}

// --- losses

template <class T>
Matrix<T> softmax(const Matrix<T>& logits) {
  Matrix<T> p = logits.colwise() - logits.rowwise().maxCoeff();
  p = p.array().exp();
  p.array().colwise() /= p.rowwise().sum().array();
  return p;
}

template <class T>
Var<T> softmax_cross_entropy(Var<T> logits, const std::vector<int>& labels) {
  Tape<T>& t = *logits.tape;
  const Index n = logits.rows();
  if (static_cast<Index>(labels.size()) != n) throw Error("internal: one label per row needed");
  Matrix<T> shifted = logits.value().colwise() - logits.value().rowwise().maxCoeff();
  Eigen::Matrix<T, Eigen::Dynamic, 1> lse = shifted.array().exp().rowwise().sum().log();
  T loss = 0;
  for (Index r = 0; r < n; ++r) {
    int l = labels[static_cast<std::size_t>(r)];
    if (l < 0 || l >= logits.cols()) throw Error("internal: label out of range");
    loss += lse[r] - shifted(r, l);
  }
  const int il = logits.id, io = next_id(t);
  return t.record(Matrix<T>::Constant(1, 1, loss / static_cast<T>(n)), logits.requires_grad(),
                  [&t, il, io, labels] {
                    Matrix<T> p = softmax(t.value(il));
                    for (std::size_t r = 0; r < labels.size(); ++r)
                      p(static_cast<Index>(r), labels[r]) -= 1;
                    t.grad(il) += (t.grad(io)(0, 0) / static_cast<T>(labels.size())) * p;
                  });
}

template <class T>
Var<T> bce_with_logits(Var<T> logits, const Matrix<T>& targets) {
  Tape<T>& t = *logits.tape;
  if (targets.rows() != logits.rows() || targets.cols() != logits.cols())
    throw Error("internal: bce target shape");
  const Matrix<T>& x = logits.value();
  T loss = 0;
  for (Index k = 0; k < x.size(); ++k) {
    T v = x.data()[k];
    loss += std::max(v, T(0)) - v * targets.data()[k] + std::log1p(std::exp(-std::abs(v)));
  }
  const int il = logits.id, io = next_id(t);
  const T n = static_cast<T>(x.size());
  return t.record(
      Matrix<T>::Constant(1, 1, loss / n), logits.requires_grad(), [&t, il, io, targets, n] {
        const Matrix<T>& x = t.value(il);
        Matrix<T> s = x.unaryExpr([](T v) {
          return v >= 0 ? T(1) / (T(1) + std::exp(-v)) : std::exp(v) / (T(1) + std::exp(v));
        });
        t.grad(il) += (t.grad(io)(0, 0) / n) * (s - targets);
      });
}

template <class T>
Var<T> mse(Var<T> a, Var<T> b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) shape_error("mse", a, b);
  return mean(square(sub(a, b)));
}

template <class T>
Var<T> gaussian_kl_elements(Var<T> mu, Var<T> logvar) {
  return scale(sub(sub(add_scalar(logvar, T(1)), square(mu)), exp(logvar)), T(-0.5));
}

template <class T>
Var<T> gaussian_kl(Var<T> mu, Var<T> logvar) {
  return scale(sum(gaussian_kl_elements(mu, logvar)), T(1) / static_cast<T>(mu.rows()));
}

template <class T>
Var<T> reparameterize(Var<T> mu, Var<T> logvar, const Matrix<T>& eps) {
  Var<T> e = mu.tape->constant(eps);
  return add(mu, mul(exp(scale(logvar, T(0.5))), e));
}

#define DF_NN_OPS(T)                                                             \
  template Var<T> matmul(Var<T>, Var<T>);                                        \
  template Var<T> matmul_transposed(Var<T>, Var<T>);                             \
  template Var<T> sparse_matmul(std::shared_ptr<const SparseMatrix<T>>, Var<T>); \
  template Var<T> transpose(Var<T>);                                             \
  template Var<T> add(Var<T>, Var<T>);                                           \
  template Var<T> sub(Var<T>, Var<T>);                                           \
  template Var<T> mul(Var<T>, Var<T>);                                           \
  template Var<T> div(Var<T>, Var<T>);                                           \
  template Var<T> scale(Var<T>, T);                                              \
  template Var<T> add_scalar(Var<T>, T);                                         \
  template Var<T> tanh(Var<T>);                                                  \
  template Var<T> sigmoid(Var<T>);                                               \
  template Var<T> relu(Var<T>);                                                  \
  template Var<T> leaky_relu(Var<T>, T);                                         \
  template Var<T> exp(Var<T>);                                                   \
  template Var<T> log(Var<T>);                                                   \
  template Var<T> abs(Var<T>);                                                   \
  template Var<T> square(Var<T>);                                                \
  template Var<T> sqrt(Var<T>);                                                  \
  template Var<T> clamp(Var<T>, T, T);                                           \
  template Var<T> sum(Var<T>);                                                   \
  template Var<T> sum_squares(Var<T>, const Matrix<T>*);                         \
  template Var<T> dot_constant(Var<T>, Matrix<T>);                               \
  template Var<T> mean(Var<T>);                                                  \
  template Var<T> sum_rows(Var<T>);                                              \
  template Var<T> sum_cols(Var<T>);                                              \
  template Var<T> mean_rows(Var<T>);                                             \
  template Var<T> mean_cols(Var<T>);                                             \
  template Var<T> max_rows(Var<T>);                                              \
  template Var<T> max_cols(Var<T>);                                              \
  template Var<T> slice_rows(Var<T>, Eigen::Index, Eigen::Index);                \
  template Var<T> slice_cols(Var<T>, Eigen::Index, Eigen::Index);                \
  template Var<T> concat_rows(const std::vector<Var<T>>&);                       \
  template Var<T> concat_cols(const std::vector<Var<T>>&);                       \
  template Var<T> reshape(Var<T>, Eigen::Index, Eigen::Index);                   \
  template Var<T> gather_rows(Var<T>, std::vector<int>);                         \
  template Var<T> scatter_rows(Var<T>, std::vector<int>, Eigen::Index);          \
  template Var<T> group_norm(Var<T>, Eigen::Index);                              \
  template Var<T> softmax_cross_entropy(Var<T>, const std::vector<int>&);        \
  template Var<T> bce_with_logits(Var<T>, const Matrix<T>&);                     \
  template Var<T> mse(Var<T>, Var<T>);                                           \
  template Var<T> gaussian_kl_elements(Var<T>, Var<T>);                          \
  template Var<T> gaussian_kl(Var<T>, Var<T>);                                   \
  template Var<T> reparameterize(Var<T>, Var<T>, const Matrix<T>&);              \
  template Matrix<T> softmax(const Matrix<T>&);

}  // namespace df::nn
