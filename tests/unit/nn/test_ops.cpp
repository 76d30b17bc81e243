// Every op is gradient-checked in double (relative error ≤ 1e-6, sentinel-prefilled buffers),
// plus closed-form forward checks.
#include <tbb/global_control.h>

#include <catch2/catch.hpp>

#include "nn/gradient_check.h"
#include "nn/ops.h"

using namespace df::nn;
using M = Matrix<double>;
using Vars = std::vector<Var<double>>;

namespace {
constexpr double kTolerance = 1e-6;

void require_gradients(const std::function<Var<double>(Tape<double>&, const Vars&)>& f,
                       const std::vector<M>& inputs, std::uint64_t seed = 0) {
  auto r = gradient_check(f, inputs, seed);
  INFO(r.report);
  REQUIRE(r.max_error <= kTolerance);
}

M rnd(Eigen::Index r, Eigen::Index c, std::uint64_t seed, double lo = -1, double hi = 1) {
  df::Rng rng(seed, 5);
  return random_matrix(r, c, rng, lo, hi);
}
}  // namespace

TEST_CASE("nn ops: matmul, transposed matmul, sparse matmul, transpose", "[nn]") {
  require_gradients([](Tape<double>&, const Vars& x) { return matmul(x[0], x[1]); },
                    {rnd(4, 3, 1), rnd(3, 5, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return matmul_transposed(x[0], x[1]); },
                    {rnd(4, 3, 1), rnd(6, 3, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return transpose(x[0]); }, {rnd(4, 3, 1)});
  auto S = std::make_shared<SparseMatrix<double>>(3, 4);
  S->insert(0, 1) = 0.5;
  S->insert(1, 0) = -2;
  S->insert(1, 3) = 1.5;
  S->insert(2, 2) = 0.25;
  S->makeCompressed();
  require_gradients(
      [S](Tape<double>&, const Vars& x) {
        return sparse_matmul(std::shared_ptr<const SparseMatrix<double>>(S), x[0]);
      },
      {rnd(4, 5, 3)});
  Tape<double> t;
  auto y =
      sparse_matmul(std::shared_ptr<const SparseMatrix<double>>(S), t.constant(M::Identity(4, 4)));
  CHECK(y.value() == M(*S));
}

TEST_CASE("nn ops: element-wise binary ops with every broadcast", "[nn]") {
  using Op = Var<double> (*)(Var<double>, Var<double>);
  for (Op op :
       {static_cast<Op>(add<double>), static_cast<Op>(sub<double>), static_cast<Op>(mul<double>)}) {
    auto f = [op](Tape<double>&, const Vars& x) { return op(x[0], x[1]); };
    require_gradients(f, {rnd(4, 3, 1), rnd(4, 3, 2)});  // same shape
    require_gradients(f, {rnd(4, 3, 1), rnd(1, 3, 2)});  // row vector over rows
    require_gradients(f, {rnd(4, 3, 1), rnd(4, 1, 2)});  // column over columns
    require_gradients(f, {rnd(4, 3, 1), rnd(1, 1, 2)});  // scalar
    require_gradients(f, {rnd(1, 3, 1), rnd(4, 3, 2)});  // broadcast on the left
  }
  auto fdiv = [](Tape<double>&, const Vars& x) { return div(x[0], x[1]); };
  require_gradients(fdiv, {rnd(4, 3, 1), rnd(4, 3, 2, 0.5, 2)});
  require_gradients(fdiv, {rnd(4, 3, 1), rnd(1, 3, 2, 0.5, 2)});
  require_gradients(fdiv, {rnd(1, 1, 1), rnd(4, 3, 2, 0.5, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return mul(x[0], x[0]); },
                    {rnd(3, 3, 4)});  // shared input
  Tape<double> t;
  M a(2, 2), b(1, 2);
  a << 1, 2, 3, 4;
  b << 10, 20;
  CHECK(add(t.constant(a), t.constant(b)).value() == (M(2, 2) << 11, 22, 13, 24).finished());
  CHECK_THROWS(add(t.constant(a), t.constant(M::Zero(3, 2))));
}

TEST_CASE("nn ops: element-wise functions", "[nn]") {
  using Op = Var<double> (*)(Var<double>);
  for (Op op : {static_cast<Op>(tanh<double>), static_cast<Op>(sigmoid<double>),
                static_cast<Op>(relu<double>), static_cast<Op>(exp<double>),
                static_cast<Op>(abs<double>), static_cast<Op>(square<double>)})
    require_gradients([op](Tape<double>&, const Vars& x) { return op(x[0]); },
                      {rnd(5, 4, 7, -2, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return log(x[0]); }, {rnd(5, 4, 7, 0.2, 3)});
  require_gradients([](Tape<double>&, const Vars& x) { return sqrt(x[0]); },
                    {rnd(5, 4, 7, 0.2, 3)});
  require_gradients([](Tape<double>&, const Vars& x) { return leaky_relu(x[0], 0.2); },
                    {rnd(5, 4, 7, -2, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return clamp(x[0], -0.5, 0.7); },
                    {rnd(5, 4, 7, -2, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return scale(x[0], -3.0); }, {rnd(2, 3, 1)});
  require_gradients([](Tape<double>&, const Vars& x) { return add_scalar(x[0], 2.0); },
                    {rnd(2, 3, 1)});
  Tape<double> t;
  M x(1, 4);
  x << -1000, -1, 0, 1000;
  M s = sigmoid(t.constant(x)).value();
  CHECK(s.allFinite());  // stable at extreme inputs
  CHECK(s(0, 2) == 0.5);
  CHECK(relu(t.constant(x)).value() == (M(1, 4) << 0, 0, 0, 1000).finished());
}

TEST_CASE("nn ops: reductions", "[nn]") {
  using Op = Var<double> (*)(Var<double>);
  for (Op op : {static_cast<Op>(sum<double>), static_cast<Op>(mean<double>),
                static_cast<Op>(sum_rows<double>), static_cast<Op>(sum_cols<double>),
                static_cast<Op>(mean_rows<double>), static_cast<Op>(mean_cols<double>),
                static_cast<Op>(max_rows<double>), static_cast<Op>(max_cols<double>)})
    require_gradients([op](Tape<double>&, const Vars& x) { return op(x[0]); }, {rnd(5, 4, 9)});
  Tape<double> t;
  M a(2, 3);
  a << 1, 5, 3, 4, 2, 6;
  CHECK(max_rows(t.constant(a)).value() == (M(1, 3) << 4, 5, 6).finished());
  CHECK(max_cols(t.constant(a)).value() == (M(2, 1) << 5, 6).finished());
  CHECK(sum_cols(t.constant(a)).value() == (M(2, 1) << 9, 12).finished());
}

TEST_CASE("nn ops: slicing, concatenation, reshape, gather/scatter, group norm", "[nn]") {
  require_gradients([](Tape<double>&, const Vars& x) { return slice_rows(x[0], 1, 3); },
                    {rnd(5, 4, 1)});
  require_gradients([](Tape<double>&, const Vars& x) { return slice_cols(x[0], 2, 2); },
                    {rnd(5, 4, 1)});
  require_gradients(
      [](Tape<double>&, const Vars& x) {
        return concat_rows<double>({x[0], x[1], x[0]});
      },
      {rnd(2, 3, 1), rnd(4, 3, 2)});
  require_gradients(
      [](Tape<double>&, const Vars& x) {
        return concat_cols<double>({x[1], x[0]});
      },
      {rnd(3, 2, 1), rnd(3, 5, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return reshape(x[0], 2, 6); },
                    {rnd(3, 4, 1)});
  require_gradients(
      [](Tape<double>&, const Vars& x) {
        return gather_rows(x[0], {2, 0, 2, 1});
      },
      {rnd(3, 4, 1)});
  require_gradients(
      [](Tape<double>&, const Vars& x) {
        return scatter_rows(x[0], {2, 0, 2}, 4);
      },
      {rnd(3, 4, 1)});
  require_gradients([](Tape<double>&, const Vars& x) { return group_norm(x[0], 3); },
                    {rnd(4, 9, 1)});
  const M w = (M(4, 1) << 3, 0, 1, 2).finished(), c = rnd(4, 5, 3);
  require_gradients([](Tape<double>&, const Vars& x) { return sum_squares(x[0]); }, {rnd(4, 5, 1)});
  require_gradients([w](Tape<double>&, const Vars& x) { return sum_squares(x[0], &w); },
                    {rnd(4, 5, 1)});
  require_gradients([c](Tape<double>&, const Vars& x) { return dot_constant(x[0], c); },
                    {rnd(4, 5, 1)});
  Tape<double> t;
  const M s = rnd(4, 5, 4);
  CHECK(sum_squares(t.constant(s)).value()(0, 0) == Approx(s.squaredNorm()));
  CHECK(sum_squares(t.constant(s), &w).value()(0, 0) ==
        Approx((s.rowwise().squaredNorm().array() * w.col(0).array()).sum()));
  CHECK(dot_constant(t.constant(s), c).value()(0, 0) == Approx((s.array() * c.array()).sum()));
  M a(1, 6);
  a << 3, 4, 0, 0, 0, 0;
  CHECK(group_norm(t.constant(a), 3).value() == (M(1, 2) << 5, 0).finished());
  M b = rnd(3, 4, 2);
  CHECK(reshape(t.constant(b), 4, 3).value().row(1) ==
        (M(1, 3) << b(0, 3), b(1, 0), b(1, 1)).finished());
}

TEST_CASE("nn ops: losses", "[nn]") {
  std::vector<int> labels{2, 0, 1, 2};
  require_gradients(
      [labels](Tape<double>&, const Vars& x) { return softmax_cross_entropy(x[0], labels); },
      {rnd(4, 3, 1, -3, 3)});
  M targets = rnd(4, 3, 9, 0, 1);
  require_gradients(
      [targets](Tape<double>&, const Vars& x) { return bce_with_logits(x[0], targets); },
      {rnd(4, 3, 1, -3, 3)});
  require_gradients([](Tape<double>&, const Vars& x) { return mse(x[0], x[1]); },
                    {rnd(4, 3, 1), rnd(4, 3, 2)});
  require_gradients([](Tape<double>&, const Vars& x) { return gaussian_kl(x[0], x[1]); },
                    {rnd(4, 3, 1), rnd(4, 3, 2)});
  require_gradients(
      [](Tape<double>&, const Vars& x) { return sum(square(gaussian_kl_elements(x[0], x[1]))); },
      {rnd(4, 3, 1), rnd(4, 3, 2)});
  M eps = rnd(4, 3, 3);
  require_gradients([eps](Tape<double>&, const Vars& x) { return reparameterize(x[0], x[1], eps); },
                    {rnd(4, 3, 1), rnd(4, 3, 2)});
  // Closed forms.
  Tape<double> t;
  M logits(1, 3);
  logits << 1000, 0, -1000;  // stable: no overflow
  CHECK(softmax_cross_entropy(t.constant(logits), {0}).value()(0, 0) == Approx(0).margin(1e-12));
  CHECK(softmax_cross_entropy(t.constant(M::Zero(2, 4)), {1, 3}).value()(0, 0) ==
        Approx(std::log(4.0)));
  CHECK(bce_with_logits(t.constant(M::Zero(1, 1)), M(M::Constant(1, 1, 1))).value()(0, 0) ==
        Approx(std::log(2.0)));
  CHECK(gaussian_kl(t.constant(M::Zero(2, 5)), t.constant(M::Zero(2, 5))).value()(0, 0) == 0.0);
  // N(1, 1) against N(0, 1): ½ μ² = 0.5 per element.
  CHECK(gaussian_kl_elements(t.constant(M::Ones(2, 3)), t.constant(M::Zero(2, 3))).value() ==
        M::Constant(2, 3, 0.5));
  CHECK(mse(t.constant(M::Ones(2, 2)), t.constant(M::Zero(2, 2))).value()(0, 0) == 1.0);
}

TEST_CASE("nn ops: matmul_repeated (a weight multiplied at every step) has matmul's gradients",
          "[nn]") {
  // A recurrence h_{t+1} = tanh(h_t W + x_t U) over 4 steps: W and U are each used at every step,
  // W also by a plain matmul and a penalty, so its gradient collects the deferred product over all
  // steps and the others. U is computed (2·u), not a leaf: the deferred product must reach U's
  // gradient before U's own backward passes it on to u.
  auto recurrence = [](bool repeated) {
    return [repeated](Tape<double>&, const Vars& x) {
      auto mm = [repeated](Var<double> a, Var<double> b) {
        return repeated ? matmul_repeated(a, b) : matmul(a, b);
      };
      Var<double> w = x[1], u = scale(x[2], 2.0), h = x[0];
      for (int t = 0; t < 4; ++t) h = tanh(add(mm(h, w), mm(slice_rows(x[3], 3 * t, 3), u)));
      return add(matmul(h, w), scale(sum(square(w)), 0.01));
    };
  };
  const std::vector<M> inputs{rnd(3, 5, 1), rnd(5, 5, 2), rnd(4, 5, 3), rnd(12, 4, 4)};
  require_gradients(recurrence(true), inputs);
  // The same values and gradients as with matmul (float rounding apart).
  auto run = [&](bool repeated) {
    Tape<double> t;
    Vars v;
    for (const auto& x : inputs) v.push_back(t.variable(x));
    Var<double> y = recurrence(repeated)(t, v);
    t.backward(sum(y));
    std::vector<M> out{y.value()};
    for (auto& x : v) out.push_back(x.grad());
    return out;
  };
  const auto a = run(true), b = run(false);
  for (std::size_t k = 0; k < a.size(); ++k) CHECK((a[k] - b[k]).cwiseAbs().maxCoeff() < 1e-13);
  // The weight as a constant (generation): only the input gets a gradient.
  Tape<double> t;
  Var<double> x = t.variable(inputs[0]), w = t.constant(inputs[1]);
  t.backward(sum(matmul_repeated(matmul_repeated(x, w), w)));
  CHECK((x.grad() - M::Ones(3, 5) * (inputs[1] * inputs[1]).transpose()).cwiseAbs().maxCoeff() <
        1e-13);
  CHECK_FALSE(t.has_grad(w.id));
}

TEST_CASE("nn ops: matmul_repeated does not depend on the thread count", "[nn]") {
  auto run = [](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          static_cast<std::size_t>(threads));
    df::Rng rng(12);
    const Matrix<float> x0 = random_matrix(16, 600, rng, -1.0, 1.0).cast<float>();
    const Matrix<float> w0 = random_matrix(600, 600, rng, -0.05, 0.05).cast<float>();
    Tape<float> t;
    Var<float> h = t.variable(x0), w = t.variable(w0);
    for (int s = 0; s < 5; ++s) h = tanh(matmul_repeated(h, w));
    Var<float> l = mean(h);
    t.backward(l);
    return std::tuple{l.value()(0, 0), Matrix<float>(t.grad(0)), Matrix<float>(w.grad())};
  };
  auto [l1, gx1, gw1] = run(1);
  auto [l2, gx2, gw2] = run(2);
  CHECK(l1 == l2);
  CHECK(gx1 == gx2);
  CHECK(gw1 == gw2);
}

TEST_CASE("nn tape: composite graphs, gradients accumulate over uses, float instantiation",
          "[nn]") {
  // A small two-layer network with every kind of op chained.
  require_gradients(
      [](Tape<double>& t, const Vars& x) {
        Var<double> h = tanh(add(matmul(x[0], x[1]), x[2]));
        Var<double> y = sigmoid(matmul(h, transpose(x[1])));
        return add(mean_rows(y), scale(sum(square(x[1])), 0.01));
        (void)t;
      },
      {rnd(5, 4, 1), rnd(4, 4, 2), rnd(1, 4, 3)});
  Tape<float> tf;
  Var<float> a = tf.variable(Matrix<float>::Constant(2, 2, 1.5f));
  Var<float> l = sum(mul(a, a));
  tf.backward(l);
  CHECK(a.grad()(0, 0) == 3.0f);
  tf.clear();
  CHECK(tf.size() == 0);
}

TEST_CASE("gradient_check: catches wrong, overwriting and missing gradients", "[nn]") {
  auto check = [](auto backward_kind) {
    return gradient_check(
        [backward_kind](Tape<double>& t, const Vars& x) {
          // y = 2x, recorded by hand with a deliberately faulty backward.
          const int ix = x[0].id, io = static_cast<int>(t.size());
          return t.record(2 * x[0].value(), x[0].requires_grad(), [&t, ix, io, backward_kind] {
            if (backward_kind == 0) t.grad(ix) += 2 * t.grad(io);  // correct
            if (backward_kind == 1) t.grad(ix) += 3 * t.grad(io);  // wrong derivative
            if (backward_kind == 2)
              t.grad(ix) = 2 * t.grad(io);  // overwrites instead of accumulating
            // backward_kind == 3: forgets the input
          });
        },
        {rnd(3, 2, 1)});
  };
  CHECK(check(0).max_error <= kTolerance);
  CHECK(check(1).max_error > 0.1);
  CHECK(check(2).max_error > 0.01);
  CHECK(check(3).max_error > 0.1);
}

TEST_CASE(
    "nn ops: results do not depend on the thread count (blocked products, chunked element-wise)",
    "[nn]") {
  auto run = [](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          static_cast<std::size_t>(threads));
    df::Rng rng(11);
    Matrix<float> a(300, 700), b(700, 90);
    for (Eigen::Index k = 0; k < a.size(); ++k) a.data()[k] = static_cast<float>(rng.normal());
    for (Eigen::Index k = 0; k < b.size(); ++k) b.data()[k] = static_cast<float>(rng.normal());
    Tape<float> t;
    Var<float> x = t.variable(a), w = t.variable(b);
    Var<float> l = mean(tanh(matmul(tanh(x), w)));
    t.backward(l);
    return std::tuple{l.value()(0, 0), Matrix<float>(x.grad()), Matrix<float>(w.grad())};
  };
  auto [l1, gx1, gw1] = run(1);
  auto [l2, gx2, gw2] = run(2);
  CHECK(l1 == l2);
  CHECK(gx1 == gx2);
  CHECK(gw1 == gw2);
}
