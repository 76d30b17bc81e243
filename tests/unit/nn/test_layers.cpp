#include <catch2/catch.hpp>
#include <cmath>

#include "nn/adam.h"
#include "nn/gradient_check.h"
#include "nn/layers.h"
#include "nn/train_step.h"

using namespace df::nn;
using M = Matrix<double>;
using Vars = std::vector<Var<double>>;

namespace {
constexpr double kTolerance = 1e-6;

// Gradient-checks a layer w.r.t. its input(s) and every parameter of `store`: the first
// `n_inputs` Vars are inputs, the rest the parameters in store order.
void require_layer_gradients(
    ParameterStore<double>& store, const std::vector<M>& inputs,
    const std::function<Var<double>(const Bound<double>&, const Vars&)>& f) {
  std::vector<M> all = inputs;
  for (const auto& v : store.views()) all.push_back(store.value(store.find(v.name)));
  const std::size_t n_in = inputs.size();
  auto r = gradient_check(
      [&](Tape<double>&, const Vars& x) {
        Bound<double> p{Vars(x.begin() + static_cast<std::ptrdiff_t>(n_in), x.end())};
        return f(p, Vars(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n_in)));
      },
      all);
  INFO(r.report);
  REQUIRE(r.max_error <= kTolerance);
}

M rnd(Eigen::Index r, Eigen::Index c, std::uint64_t seed) {
  df::Rng rng(seed, 9);
  return random_matrix(r, c, rng);
}

// A tetrahedron's edges: every vertex has 3 neighbours.
std::vector<std::array<int, 2>> tetra_edges() {
  return {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
}
}  // namespace

TEST_CASE("nn layers: Linear and MLP gradients", "[nn]") {
  df::Rng rng(1);
  ParameterStore<double> s;
  Linear<double> lin(s, "lin", 4, 3, rng);
  s.normal(lin.b, rng, 0.5);
  require_layer_gradients(s, {rnd(5, 4, 2)},
                          [&](const Bound<double>& p, const Vars& x) { return lin(p, x[0]); });
  for (Activation a :
       {Activation::relu, Activation::tanh, Activation::leaky_relu, Activation::sigmoid}) {
    ParameterStore<double> m;
    Mlp<double> mlp(m, "mlp", {3, 6, 5, 2}, a, rng);
    require_layer_gradients(m, {rnd(4, 3, 3)},
                            [&](const Bound<double>& p, const Vars& x) { return mlp(p, x[0]); });
  }
}

TEST_CASE("nn layers: MeshConv by hand and its gradients (also tied/transposed)", "[nn]") {
  // Closed form on a triangle: y = 2x + 3·mean(neighbours) + 1.
  auto tri = neighbour_mean_operator<double>(3, {{0, 1}, {1, 2}, {0, 2}});
  Tape<double> t;
  M x(1, 3);
  x << 1, 2, 4;
  Var<double> y =
      mesh_conv(t.constant(x), t.constant(M::Constant(1, 1, 2)), t.constant(M::Constant(1, 1, 3)),
                t.constant(M::Constant(1, 1, 1)), tri);
  CHECK(y.value() == (M(1, 3) << 12, 12.5, 13.5).finished());

  df::Rng rng(2);
  auto a = neighbour_mean_operator<double>(4, tetra_edges());
  ParameterStore<double> s;
  MeshConv<double> conv(s, "conv", 3, 2, a, rng);
  s.normal(conv.b, rng, 0.5);
  require_layer_gradients(s, {rnd(2, 4 * 3, 3)},
                          [&](const Bound<double>& p, const Vars& in) { return conv(p, in[0]); });
  require_layer_gradients(
      s, {rnd(2, 4 * 2, 4), rnd(1, 3, 5)},
      [&](const Bound<double>& p, const Vars& in) { return conv.tied_transpose(p, in[0], in[1]); });
}

TEST_CASE("nn layers: LSTM closed form with all weights zero but the forget bias", "[nn]") {
  df::Rng rng(3);
  ParameterStore<double> s;
  LstmCell<double> cell(s, "lstm", 2, 3, rng);
  s.value(cell.wx).setZero();
  s.value(cell.wh).setZero();  // the bias keeps its forget-gate 1
  Tape<double> t;
  Bound<double> p = s.bind(t);
  M c0 = rnd(1, 3, 4);
  LstmState<double> st =
      cell(p, t.constant(rnd(1, 2, 5)), {t.constant(rnd(1, 3, 6)), t.constant(c0)});
  // i = o = σ(0) = ½, f = σ(1), g = tanh(0) = 0: c = σ(1) c0, h = ½ tanh(c).
  const double f = 1 / (1 + std::exp(-1.0));
  for (int k = 0; k < 3; ++k) {
    CHECK(st.c.value()(0, k) == Approx(f * c0(0, k)));
    CHECK(st.h.value()(0, k) == Approx(0.5 * std::tanh(f * c0(0, k))));
  }
}

TEST_CASE("nn layers: LSTM cell, stacked and bidirectional gradients", "[nn]") {
  df::Rng rng(4);
  {
    ParameterStore<double> s;
    LstmCell<double> cell(s, "cell", 3, 4, rng);
    require_layer_gradients(s, {rnd(2, 3, 1), rnd(2, 4, 2), rnd(2, 4, 3)},
                            [&](const Bound<double>& p, const Vars& x) {
                              LstmState<double> st = cell(p, x[0], {x[1], x[2]});
                              return concat_cols<double>({st.h, st.c});
                            });
  }
  {
    ParameterStore<double> s;
    StackedLstm<double> lstm(s, "stack", 3, 4, 2, rng);
    require_layer_gradients(s, {rnd(2, 3, 1), rnd(2, 3, 2), rnd(2, 3, 3)},
                            [&](const Bound<double>& p, const Vars& x) {
                              auto states = lstm.constant_states(*x[0].tape, 2, 0.1);
                              return concat_cols<double>(lstm.run(p, x, states));
                            });
  }
  {
    ParameterStore<double> s;
    BidirectionalLstm<double> bi(s, "bi", 3, 2, 2, rng);
    require_layer_gradients(s, {rnd(6, 3, 1)}, [&](const Bound<double>& p, const Vars& x) {
      auto out = bi.run(p, x[0], 2);
      CHECK(out.forward.rows() == 6);
      CHECK(out.backward.cols() == 2);
      return concat_cols<double>({out.forward, out.backward});
    });
  }
}

TEST_CASE("nn layers: lstm_sequence is the cell step by step, in both directions", "[nn]") {
  df::Rng rng(6);
  ParameterStore<double> s;
  LstmCell<double> cell(s, "cell", 3, 4, rng);
  s.normal(cell.b, rng, 0.5);  // not only the forget gate's 1
  for (bool reverse : {false, true}) {
    INFO("reverse " << reverse);
    // x, h0, c0 and every weight get their gradients through the one node.
    require_layer_gradients(s, {rnd(8, 3, 1), rnd(2, 4, 2), rnd(2, 4, 3)},
                            [&](const Bound<double>& p, const Vars& x) {
                              return cell.sequence(p, x[0], {x[1], x[2]}, reverse);
                            });
    Tape<double> t;
    const Bound<double> p = s.bind(t);
    const Var<double> x = t.constant(rnd(8, 3, 4));
    LstmState<double> st{t.constant(rnd(2, 4, 5)), t.constant(rnd(2, 4, 6))};
    const Matrix<double> fused = cell.sequence(p, x, st, reverse).value();
    for (int k = 0; k < 4; ++k) {
      const int step = reverse ? 3 - k : k;
      st = cell(p, slice_rows(x, 2 * step, 2), st);
      CHECK((fused.middleRows(2 * step, 2) - st.h.value()).cwiseAbs().maxCoeff() < 1e-14);
    }
  }
}

TEST_CASE("nn layers: the share-weight bidirectional pattern (one LSTM, both directions)", "[nn]") {
  df::Rng rng(8);
  ParameterStore<double> s;
  StackedLstm<double> lstm(s, "shared", 3, 4, 2, rng);
  require_layer_gradients(
      s, {rnd(2, 3, 1), rnd(2, 3, 2), rnd(2, 3, 3)}, [&](const Bound<double>& p, const Vars& x) {
        auto bd = shared_bidirectional(lstm, p, x, 0.1, -0.1);
        return concat_cols<double>({bd.forward[2], bd.backward[0], bd.backward[2]});
      });
  // The backward chain is the same network run on the reversed sequence with −0.1 states.
  Tape<double> t;
  Bound<double> p = s.bind(t);
  std::vector<Var<double>> x{t.constant(rnd(2, 3, 4)), t.constant(rnd(2, 3, 5))};
  auto bd = shared_bidirectional(lstm, p, x, 0.1, -0.1);
  auto states = lstm.constant_states(t, 2, -0.1);
  auto manual = lstm.run(p, {x[1], x[0]}, states);
  CHECK(bd.backward[1].value() == manual[1].value());
  CHECK(bd.forward[0].value() != bd.backward[1].value());
}

TEST_CASE("nn layers: critic input gradient is ∇ₓD, and the GP penalty's weight gradients check",
          "[nn]") {
  df::Rng rng(5);
  for (Activation a : {Activation::relu, Activation::leaky_relu, Activation::tanh}) {
    ParameterStore<double> s;
    Mlp<double> critic(s, "D", {4, 7, 5, 1}, a, rng);
    for (const auto& v : s.views()) s.normal(s.find(v.name), rng, 0.6);
    // ∇ₓD against central differences of D.
    M x = rnd(3, 4, 6);
    Tape<double> t;
    Bound<double> p = s.bind(t);
    M g = critic.input_gradient(p, t.constant(x)).value();
    for (Eigen::Index r = 0; r < x.rows(); ++r)
      for (Eigen::Index c = 0; c < x.cols(); ++c) {
        M up = x, down = x;
        up(r, c) += 1e-6;
        down(r, c) -= 1e-6;
        Tape<double> t2;
        Bound<double> p2 = s.bind(t2);
        double d = (critic(p2, t2.constant(up)).value()(r, 0) -
                    critic(p2, t2.constant(down)).value()(r, 0)) /
                   2e-6;
        REQUIRE(g(r, c) == Approx(d).epsilon(1e-6).margin(1e-9));
      }
    // The penalty mean((‖∇ₓD‖ − 1)²), differentiated w.r.t. the critic's weights (and x).
    require_layer_gradients(s, {x}, [&](const Bound<double>& p, const Vars& in) {
      Var<double> grad = critic.input_gradient(p, in[0]);
      Var<double> norm = sqrt(sum_cols(square(grad)));
      return mean(square(add_scalar(norm, -1.0)));
    });
  }
}

TEST_CASE("Adam: first step, bias correction, schedules, warm-up, L2 penalty, clipping", "[nn]") {
  Vector<double> theta(3), g(3);
  theta << 1, -2, 3;
  g << 0.5, -0.1, 0;
  Adam<double> adam(3, {});
  Vector<double> gg = g;
  adam.step(theta, gg);
  // With bias correction, the first step moves each θ by lr·g/(|g| + ε).
  CHECK(theta(0) == Approx(1 - 1e-3 * 0.5 / (0.5 + 1e-8)));
  CHECK(theta(1) == Approx(-2 + 1e-3 * 0.1 / (0.1 + 1e-8)));
  CHECK(theta(2) == 3);
  CHECK(adam.steps() == 1);
  AdamOptions e;
  e.schedule = AdamOptions::Schedule::exponential;
  e.decay_rate = 0.5;
  e.decay_steps = 10;
  Adam<double> ex(1, e);
  ex.set_steps(20);
  CHECK(ex.learning_rate() == Approx(0.25e-3));
  e.schedule = AdamOptions::Schedule::step;
  Adam<double> st(1, e);
  st.set_steps(19);
  CHECK(st.learning_rate() == Approx(0.5e-3));
  // Warm-up: lr/N at the first step, rising linearly, the schedule's rate from step N - 1 on.
  AdamOptions w = e;
  w.schedule = AdamOptions::Schedule::exponential;
  w.warmup_steps = 4;
  Adam<double> warm(1, w);
  CHECK(warm.learning_rate() == Approx(1e-3 / 4));
  warm.set_steps(1);
  CHECK(warm.learning_rate() == Approx(1e-3 * std::pow(0.5, 0.1) * 2 / 4));
  warm.set_steps(20);
  CHECK(warm.learning_rate() == Approx(0.25e-3));
  Vector<double> one(1), grad(1);
  one << 0;
  grad << 7;
  Adam<double> first(1, w);
  first.step(one, grad);
  CHECK(one(0) == Approx(-1e-3 / 4 * 7 / (7 + 1e-8)));  // the first step a quarter of the rate
  AdamOptions c;
  c.clip_norm = 1;
  c.weight_decay = 0.1;
  Adam<double> clip(2, c);
  Vector<double> th(2), gr(2);
  th << 10, 0;
  gr << 3, 4;
  clip.step(th, gr);
  CHECK(gr.norm() == Approx(1.0));  // (3 + 0.1·10, 4) clipped to norm 1
}

TEST_CASE("Adam: scaled ranges step at their fraction of the rate, the rest exactly as before",
          "[nn]") {
  Vector<double> g(6);
  g << 0.5, -0.1, 2, -3, 0.25, 1;
  Vector<double> plain = Vector<double>::LinSpaced(6, -1, 1), slow = plain;
  AdamOptions o;
  o.schedule = AdamOptions::Schedule::exponential;
  o.decay_rate = 0.5;
  o.decay_steps = 3;
  Adam<double> a(6, o);
  o.scaled = {{4, 1, 0.5}, {1, 2, 0.1}};  // unsorted on purpose
  Adam<double> b(6, o);
  for (int step = 0; step < 5; ++step) {
    Vector<double> ga = g * (step + 1), gb = ga;
    const Vector<double> before_a = plain, before_b = slow;
    a.step(plain, ga);
    b.step(slow, gb);
    for (int j : {0, 3, 5}) CHECK(slow(j) - before_b(j) == plain(j) - before_a(j));  // bit for bit
    for (int j : {1, 2}) CHECK(slow(j) - before_b(j) == Approx(0.1 * (plain(j) - before_a(j))));
    CHECK(slow(4) - before_b(4) == Approx(0.5 * (plain(4) - before_a(4))));
  }
  // The proximal step's sizes carry the same fractions.
  const auto sa = a.last_step_sizes(), sb = b.last_step_sizes();
  CHECK(sb(0) == sa(0));
  CHECK(sb(2) == Approx(0.1 * sa(2)));
  CHECK(sb(4) == Approx(0.5 * sa(4)));
  CHECK(sb(3) == sa(3));  // between the two ranges
  CHECK(sb(5) == sa(5));  // after the last
  // A span's rates at once equal each coordinate's, from any first coordinate.
  for (const auto* s : {&sa, &sb})
    for (Eigen::Index first = 0; first < 6; ++first) {
      std::vector<double> r(static_cast<std::size_t>(6 - first));
      s->rates_of(first, 6 - first, r.data());
      for (Eigen::Index j = first; j < 6; ++j)
        CHECK(r[static_cast<std::size_t>(j - first)] == s->rate_of(j));
      CHECK(s->at_rate(first, s->rate_of(first)) == (*s)(first));
    }
  o.scaled = {{1, 3, 0.5}, {2, 1, 0.1}};
  CHECK_THROWS(Adam<double>(6, o));  // overlapping ranges
  o.scaled = {{4, 3, 0.5}};
  CHECK_THROWS(Adam<double>(6, o));  // past the parameters
}

TEST_CASE("nn learning: an MLP learns XOR (deterministic for a seed)", "[nn]") {
  auto train = [](std::uint64_t seed) {
    df::Rng rng(seed);
    ParameterStore<float> s;
    Mlp<float> mlp(s, "xor", {2, 8, 1}, Activation::tanh, rng);
    AdamOptions o;
    o.lr = 0.05;
    Adam<float> adam(s.size(), o);
    Matrix<float> x(4, 2), y(4, 1);
    x << 0, 0, 0, 1, 1, 0, 1, 1;
    y << 0, 1, 1, 0;
    float loss = 0;
    Tape<float> t;
    for (int it = 0; it < 500; ++it)
      loss = train_step<float>(t, s, adam, [&](Tape<float>& t, const Bound<float>& p) {
        return bce_with_logits(mlp(p, t.constant(x)), y);
      });
    return std::pair{loss, s.values()};
  };
  auto [loss, w1] = train(7);
  CHECK(loss < 0.02f);
  auto [loss2, w2] = train(7);
  CHECK(w1 == w2);  // same seed, same weights
}

TEST_CASE(
    "nn train_step over several stores: the trained ones step as if alone, the read ones and a "
    "frozen part stay",
    "[nn]") {
  df::Rng rng(9);
  ParameterStore<double> gs, ds;
  Linear<double> g1(gs, "gen.lstm", 3, 2, rng), g2(gs, "gen.decoder", 2, 2, rng);
  Linear<double> d(ds, "disc", 2, 1, rng);
  const Matrix<double> x = rnd(5, 3, 2);
  auto loss = [&](Tape<double>& t, const Bound<double>& pg, const Bound<double>& pd) {
    return sum_squares(d(pd, g2(pg, g1(pg, t.constant(x)))));
  };
  // By hand: the generator's store alone, the discriminator's weights constants.
  ParameterStore<double> hand = gs;
  Adam<double> hand_adam(hand.size(), AdamOptions{});
  Tape<double> t;
  hand.zero_grad();
  const Bound<double> ph = hand.bind(t);
  const Var<double> lh = loss(t, ph, ds.bind_constant(t));
  t.backward(lh);
  hand.collect(ph);
  hand_adam.step(hand.values(), hand.grads());
  const Vector<double> disc_before = ds.values(), gen_before = gs.values();
  Adam<double> ga(gs.size(), AdamOptions{}), da(ds.size(), AdamOptions{});
  for (const bool freeze : {false, true}) {
    gs.values() = gen_before;
    Adam<double> fresh(gs.size(), AdamOptions{});
    const StepStore<double> stores[] = {{&gs, &fresh, freeze ? "gen.decoder." : ""}, {&ds}};
    const Var<double> l = train_step<double>(
        t, stores,
        [&](Tape<double>& t, const std::vector<Bound<double>>& p) { return loss(t, p[0], p[1]); });
    CHECK(l.value()(0, 0) == lh.value()(0, 0));
    CHECK(ds.values() == disc_before);  // read, not trained
    const auto& w = gs.views()[static_cast<std::size_t>(g2.w)];
    const auto decoder_now = gs.values().segment(w.offset, w.rows * w.cols);
    CHECK(gs.values().head(w.offset) != gen_before.head(w.offset));  // the LSTM part trains
    if (freeze)
      CHECK(decoder_now == gen_before.segment(w.offset, w.rows * w.cols));
    else
      CHECK(gs.values() == hand.values());  // as the by-hand step, bit for bit
  }
  // Two trained stores: each takes its own step.
  const StepStore<double> both[] = {{&gs, &ga}, {&ds, &da}};
  train_step<double>(t, both, [&](Tape<double>& t, const std::vector<Bound<double>>& p) {
    return loss(t, p[0], p[1]);
  });
  CHECK(ds.values() != disc_before);
}

TEST_CASE("nn parameters: bind_except holds the named part fixed", "[nn]") {
  df::Rng rng(5);
  ParameterStore<double> s;
  Linear<double> kept(s, "gen.lstm", 3, 2, rng), frozen(s, "gen.decoder", 2, 2, rng);
  Tape<double> t;
  const Bound<double> p = s.bind_except(t, "gen.decoder.");
  const Var<double> y = sum_squares(frozen(p, kept(p, t.constant(rnd(4, 3, 1)))));
  t.backward(y);
  s.zero_grad();
  s.collect(p);
  for (int i = 0; i < static_cast<int>(p.vars.size()); ++i) {
    const bool is_frozen = i == frozen.w || i == frozen.b;
    CHECK(p.vars[static_cast<std::size_t>(i)].requires_grad() == !is_frozen);
    if (is_frozen)
      CHECK(s.grad(i).isZero());
    else
      CHECK(s.grad(i).norm() > 0);
  }
}
