#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "helpers.h"
#include "models/bdlstm/chain.h"
#include "models/bdlstm/network.h"
#include "models/bdlstm/train.h"
#include "nn/gradient_check.h"
#include "nn/train_step.h"

using namespace df;
using namespace df::models;

namespace {

std::vector<std::array<int, 2>> tetra_edges() {
  return {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
}

BdlstmConfig tiny_config(Directions d) {
  BdlstmConfig c;
  c.conv_layers = 2;
  c.latent = 3;
  c.hidden = 4;
  c.lstm_layers = 2;
  c.directions = d;
  return c;
}

// A smooth periodic "feature" sequence on 4 vertices: frame t, window w, batch row b.
template <class T>
std::vector<nn::Matrix<T>> sine_windows(int n, int batch, std::uint64_t seed) {
  Rng rng(seed, 3);
  std::vector<nn::Matrix<T>> w(static_cast<std::size_t>(n), nn::Matrix<T>(batch, 36));
  for (int b = 0; b < batch; ++b) {
    const double start = rng.uniform(0, 6.28);
    for (int t = 0; t < n; ++t)
      for (int k = 0; k < 36; ++k)
        w[static_cast<std::size_t>(t)](b, k) =
            static_cast<T>(0.6 * std::sin(start + 0.35 * t + 0.7 * k));
  }
  return w;
}

// Max error of the loss's analytic gradient against central differences, every parameter set
// to random values first (the last decoder convolution starts at zero, which would hide every
// gradient behind it). The same reparameterisation noise in every evaluation.
std::pair<double, std::string> loss_gradient_error(BdlstmNet<double>& net,
                                                   const std::vector<nn::Matrix<double>>& window,
                                                   int given = 1) {
  Rng w(8, 0);
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(net.store().size()); ++k)
    net.store().values()[k] = w.uniform(-0.5, 0.5);
  std::vector<nn::Matrix<double>> params;
  for (std::size_t i = 0; i < net.store().views().size(); ++i)
    params.push_back(net.store().value(static_cast<int>(i)));
  auto r = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        nn::Bound<double> p{x};
        Rng rng(11, 0);
        return net.loss(t, p, window, rng, nullptr, given);
      },
      params);
  return {r.max_error, r.report};
}

}  // namespace

TEST_CASE("BD-LSTM loss: gradients of every parameter (all variants)", "[models][bdlstm]") {
  struct Variant {
    Directions d;
    bool kl, l2;
    int given;  // ground-truth frames fed before the chains run free
  };
  for (auto v :
       {Variant{Directions::shared, true, true, 1}, Variant{Directions::standard, true, true, 2},
        Variant{Directions::unidirectional, true, true, 1},
        Variant{Directions::shared, false, false, 3}}) {
    auto cfg = tiny_config(v.d);
    cfg.kl = v.kl;
    cfg.l2 = v.l2;
    BdlstmNet<double> net(cfg, 4, tetra_edges(), 7);
    const auto [error, report] = loss_gradient_error(net, sine_windows<double>(4, 2, 1), v.given);
    INFO(name_of(v.d) << " kl=" << v.kl << " l2=" << v.l2 << " given=" << v.given << "\n"
                      << report);
    REQUIRE(error <= 1e-6);
  }
}

TEST_CASE("BD-LSTM: an untrained network predicts no change (dX starts at 0)", "[models][bdlstm]") {
  BdlstmNet<double> net(tiny_config(Directions::shared), 4, tetra_edges(), 7);
  nn::Tape<double> tape;
  auto p = net.store().bind(tape);
  auto states = net.constant_states(tape, 2, 0.1);
  const auto x = sine_windows<double>(1, 2, 4)[0];
  auto y = net.step(p, 0, tape.constant(x), states, nullptr, nullptr);
  REQUIRE((y.value() - x).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("BD-LSTM carry: the step adds the motion of the step before, gradients checked",
          "[models][bdlstm]") {
  // An untrained network (dX = 0) with carry c continues the given frames' motion times c:
  // X_t+1 = X_t + c (X_t - X_t-1); at a chain's first step there is no motion to carry.
  auto cfg = tiny_config(Directions::shared);
  cfg.carry = 0.75;
  BdlstmNet<double> net(cfg, 4, tetra_edges(), 7);
  nn::Tape<double> tape;
  auto p = net.store().bind(tape);
  auto states = net.constant_states(tape, 2, 0.1);
  const auto frames = sine_windows<double>(2, 2, 4);
  auto x0 = tape.constant(frames[0]), x1 = tape.constant(frames[1]);
  auto first = net.step(p, 0, x0, states, nullptr, nullptr);
  REQUIRE((first.value() - frames[0]).cwiseAbs().maxCoeff() == 0.0);
  auto second = net.step(p, 0, x1, states, nullptr, nullptr, &x0);
  const Eigen::MatrixXd want = frames[1] + 0.75 * (frames[1] - frames[0]);
  REQUIRE((second.value() - want).cwiseAbs().maxCoeff() <= 1e-12);
  // and trained: every parameter's gradient through the carried motion (given 1: the chain runs
  // free, carrying its own outputs' motion; given 3: the ground truth's)
  for (int given : {1, 3}) {
    auto c = tiny_config(Directions::standard);
    c.carry = 1;
    BdlstmNet<double> trained(c, 4, tetra_edges(), 7);
    const auto [error, report] = loss_gradient_error(trained, sine_windows<double>(5, 2, 1), given);
    INFO("carry 1, given " << given << "\n" << report);
    REQUIRE(error <= 1e-6);
  }
}

TEST_CASE("BD-LSTM carry fade: the carry at step t is carry x fade^(t-1), in training and stepping",
          "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  cfg.carry = 0.8;
  cfg.carry_fade = 0.5;
  REQUIRE(cfg.carry_at(0) == 0.0);
  REQUIRE(cfg.carry_at(1) == Approx(0.8));
  REQUIRE(cfg.carry_at(3) == Approx(0.2));
  // An untrained network (dX = 0) steps X_t+1 = X_t + carry_at(t) (X_t - X_t-1): the chain
  // stepper counts its steps from its reset.
  BdlstmNet<float> net(cfg, 4, tetra_edges(), 7);
  ChainStepper stepper(net, 0);
  Rng rng(1, 0);
  stepper.reset(1, 0.1f, 0, rng);
  const auto frames = sine_windows<float>(1, 1, 4);
  nn::Matrix<float> x = frames[0], y = stepper.step(x);
  REQUIRE((y - x).cwiseAbs().maxCoeff() == 0.0f);
  nn::Matrix<float> x1 = frames[0] + 0.1f * nn::Matrix<float>::Ones(1, frames[0].cols());
  for (int t = 1; t <= 3; ++t) {  // motion 0.1 per step in, carried x 0.8, 0.4, 0.2
    y = stepper.step(x1);
    const float want = 0.1f * static_cast<float>(cfg.carry_at(t));
    REQUIRE(((y - x1).array() - want).abs().maxCoeff() <= 1e-6f);
    x = x1;
    x1 = x1 + 0.1f * nn::Matrix<float>::Ones(1, x1.cols());
  }
  // and trained: gradients through a fading carry
  auto c = tiny_config(Directions::standard);
  c.carry = 1;
  c.carry_fade = 0.7;
  BdlstmNet<double> trained(c, 4, tetra_edges(), 7);
  const auto [error, report] = loss_gradient_error(trained, sine_windows<double>(5, 2, 1), 1);
  INFO(report);
  REQUIRE(error <= 1e-6);
}

TEST_CASE("BD-LSTM motion input: the encoder reads the step's motion, gradients checked",
          "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  cfg.motion_input = true;
  cfg.motion_scale = 3;
  cfg.decoder_init = DecoderInit::small;
  BdlstmNet<double> net(cfg, 4, tetra_edges(), 7);
  // Every weight but the motion's convolution starts as without it.
  auto plain_cfg = cfg;
  plain_cfg.motion_input = false;
  BdlstmNet<double> plain(plain_cfg, 4, tetra_edges(), 7);
  REQUIRE(net.store().views().size() == plain.store().views().size() + 3);
  for (std::size_t k = 0; k < plain.store().views().size(); ++k)
    REQUIRE(net.store().value(static_cast<int>(k)) == plain.store().value(static_cast<int>(k)));
  nn::Tape<double> tape;
  auto p = net.store().bind(tape);
  const auto frames = sine_windows<double>(2, 2, 4);
  auto x0 = tape.constant(frames[0]), x1 = tape.constant(frames[1]);
  // A still step reads as a chain's first (no motion); a moving one does not.
  const Eigen::MatrixXd first = net.encode(p, 0, x1).first.value();
  REQUIRE((net.encode(p, 0, x1, &x1).first.value() - first).cwiseAbs().maxCoeff() <= 1e-12);
  const Eigen::MatrixXd moving = net.encode(p, 0, x1, &x0).first.value();
  REQUIRE((moving - first).cwiseAbs().maxCoeff() > 1e-3);
  // The motion comes in scaled: twice the motion at half the scale reads the same.
  auto half = cfg;
  half.motion_scale = 1.5;
  BdlstmNet<double> halved(half, 4, tetra_edges(), 7);
  auto ph = halved.store().bind(tape);
  auto before = tape.constant(Eigen::MatrixXd(2 * frames[0] - frames[1]));  // x1 - it = 2 (x1 - x0)
  REQUIRE((halved.encode(ph, 0, x1, &before).first.value() - moving).cwiseAbs().maxCoeff() <=
          1e-12);
  // The chain stepper (generation) steps as the training chain does: the same frames from the
  // same given frames (float; z the mean, as gen-bdlstm)
  BdlstmNet<float> fnet(cfg, 4, tetra_edges(), 7);
  ChainStepper stepper(fnet, 0);
  Rng rng(1, 0);
  stepper.reset(2, 0.1f, 0, rng);
  const auto fframes = sine_windows<float>(3, 2, 4);
  nn::Tape<float> ft;
  auto fp = fnet.store().bind(ft);
  auto states = fnet.constant_states(ft, 2, 0.1f);
  nn::Var<float> previous;
  for (int t = 0; t < 3; ++t) {
    auto in = ft.constant(fframes[static_cast<std::size_t>(t)]);
    const nn::Matrix<float> want =
        fnet.step(fp, 0, in, states, nullptr, nullptr, t ? &previous : nullptr, t).value();
    const nn::Matrix<float> got = stepper.step(fframes[static_cast<std::size_t>(t)]);
    REQUIRE((got - want).cwiseAbs().maxCoeff() <= 1e-6f);
    previous = in;
  }
  // and trained: every parameter's gradient through the motion (given 1: the chain's own
  // outputs' motion; given 3: the ground truth's), with and without the carry
  for (int given : {1, 3}) {
    auto c = tiny_config(Directions::standard);
    c.motion_input = true;
    c.motion_scale = 2;
    c.carry = given == 3 ? 0.5 : 0;
    BdlstmNet<double> trained(c, 4, tetra_edges(), 7);
    const auto [error, report] = loss_gradient_error(trained, sine_windows<double>(5, 2, 1), given);
    INFO("motion input, given " << given << "\n" << report);
    REQUIRE(error <= 1e-6);
  }
}

TEST_CASE("BD-LSTM loss: terms are those of eq. 3-5", "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  BdlstmNet<double> net(cfg, 4, tetra_edges(), 3);
  const auto window = sine_windows<double>(5, 3, 2);
  nn::Tape<double> tape;
  auto p = net.store().bind(tape);
  Rng rng(1, 0);
  BdlstmLossTerms terms;
  auto loss = net.loss(tape, p, window, rng, &terms);
  REQUIRE(loss.value()(0, 0) ==
          Approx(terms.recon + 0.5 * terms.bidir + 0.1 * (terms.kl + terms.l2)).epsilon(1e-12));
  double l2 = 0;
  for (std::size_t i = 0; i < net.store().views().size(); ++i)
    l2 += net.store().value(static_cast<int>(i)).squaredNorm();
  REQUIRE(terms.l2 == Approx(l2).epsilon(1e-12));
  REQUIRE(terms.kl > 0);
  // A KL warm-up weight scales only the KL term.
  Rng rw(1, 0);
  BdlstmLossTerms half;
  auto weighted = net.loss(tape, p, window, rw, &half, 1, 0.5);
  REQUIRE(half.kl == Approx(terms.kl).epsilon(1e-12));
  REQUIRE(
      weighted.value()(0, 0) ==
      Approx(terms.recon + 0.5 * terms.bidir + 0.1 * (0.5 * terms.kl + terms.l2)).epsilon(1e-12));
  // No KL: the encoder is deterministic, the KL term is absent.
  cfg.kl = false;
  BdlstmNet<double> det(cfg, 4, tetra_edges(), 3);
  nn::Tape<double> t2;
  auto p2 = det.store().bind(t2);
  Rng r1(1, 0), r2(2, 0);
  BdlstmLossTerms a, b;
  det.loss(t2, p2, window, r1, &a);
  det.loss(t2, p2, window, r2, &b);
  REQUIRE(a.kl == 0);
  REQUIRE(a.total == b.total);
}

TEST_CASE("BD-LSTM training lowers the loss and makes the two chains agree", "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  cfg.latent = 8;
  cfg.hidden = 16;
  BdlstmNet<float> net(cfg, 4, tetra_edges(), 5);
  nn::AdamOptions ao;
  ao.lr = 3e-3;
  nn::Adam<float> adam(net.store().size(), ao);
  nn::Tape<float> tape;
  Rng rng(4, 1);
  auto run = [&](int iterations) {
    BdlstmLossTerms mean;
    for (int it = 0; it < iterations; ++it) {
      const auto window = sine_windows<float>(8, 4, rng.next());
      BdlstmLossTerms t;
      nn::train_step<float>(tape, net.store(), adam,
                            [&](nn::Tape<float>& tp, const nn::Bound<float>& p) {
                              return net.loss(tp, p, window, rng, &t);
                            });
      mean.recon += t.recon / iterations, mean.bidir += t.bidir / iterations;
    }
    return mean;
  };
  const auto first = run(20);
  run(300);
  const auto last = run(20);
  INFO("recon " << first.recon << " -> " << last.recon << ", bidir " << first.bidir << " -> "
                << last.bidir);
  REQUIRE(last.recon < 0.5 * first.recon);
  REQUIRE(last.bidir < 0.3 * first.bidir);
}

TEST_CASE("BD-LSTM split: a contiguous held-out part per sequence", "[models][bdlstm]") {
  BdlstmSplit s;
  split_sequences({0, 100, 150}, 0.2, TestPart::end, 1, s);
  REQUIRE(s.train_begin == std::vector<std::int64_t>{0, 100});
  REQUIRE(s.train_end == std::vector<std::int64_t>{80, 140});
  REQUIRE(s.test_begin == std::vector<std::int64_t>{80, 140});
  REQUIRE(s.test_end == std::vector<std::int64_t>{100, 150});
  BdlstmSplit t;
  split_sequences({0, 10}, 0.2, TestPart::start, 1, t);
  REQUIRE(t.test_begin[0] == 0);
  REQUIRE(t.test_end[0] == 2);
  REQUIRE(t.train_begin[0] == 2);
  REQUIRE_THROWS_AS(split_sequences({0, 10}, 1.0, TestPart::end, 1, t), UsageError);
  // Windows of 3 frames: all starts of the training part, none reaching into the test part.
  REQUIRE(window_starts(s, 3) == [] {
    std::vector<std::int64_t> w;
    for (std::int64_t f = 0; f <= 77; ++f) w.push_back(f);
    for (std::int64_t f = 100; f <= 137; ++f) w.push_back(f);
    return w;
  }());
}

TEST_CASE("BD-LSTM windows played at other speeds (--speeds)", "[models][bdlstm]") {
  // Frame f of the data holds (f, 10 f): a window's frame is where its speed puts it.
  nn::Matrix<float> data(20, 2);
  for (Eigen::Index f = 0; f < 20; ++f) data.row(f) << float(f), 10.0f * float(f);
  std::vector<nn::Matrix<float>> window(5, nn::Matrix<float>::Zero(2, 2));
  auto frames = [&](Eigen::Index row) {
    std::vector<float> v;
    for (const auto& w : window) v.push_back(w(row, 0));
    return v;
  };
  play_window(data, 3, 1, 1.0, window, 0);  // the data's own pace: frames 3..7 as they are
  REQUIRE(frames(0) == std::vector<float>{3, 4, 5, 6, 7});
  play_window(data, 3, 2, 1.0, window, 1);  // stride 2
  REQUIRE(frames(1) == std::vector<float>{3, 5, 7, 9, 11});
  play_window(data, 3, 1, 0.0, window, 0);  // held still at the first frame
  REQUIRE(frames(0) == std::vector<float>{3, 3, 3, 3, 3});
  play_window(data, 2, 1, 0.5, window, 1);  // half the pace: halfway frames interpolated
  REQUIRE(frames(1) == std::vector<float>{2, 2.5f, 3, 3.5f, 4});
  REQUIRE(window[1](1, 1) == 25.0f);        // every feature interpolated alike
  play_window(data, 0, 2, 1.5, window, 0);  // 3 frames a step at stride 2: 0, 3, 6, 9, 12
  REQUIRE(frames(0) == std::vector<float>{0, 3, 6, 9, 12});
  REQUIRE(window[4](1, 0) == 4.0f);  // the other row keeps its own window
}

TEST_CASE("BD-LSTM split: a held-out part inside the sequence", "[models][bdlstm]") {
  BdlstmSplit m;
  split_sequences({0, 100}, 0.2, TestPart::middle, 1, m);
  REQUIRE(m.test_begin[0] == 40);
  REQUIRE(m.test_end[0] == 60);
  REQUIRE(m.train_begin[0] == 0);
  REQUIRE(m.train_end[0] == 100);
  // Windows of 10 frames lie in 0..39 or 60..99.
  const auto w = window_starts(m, 10);
  REQUIRE(w.size() == 31 + 31);
  REQUIRE(w[30] == 30);
  REQUIRE(w[31] == 60);
  REQUIRE(w.back() == 90);
  // random: inside the sequence, placed by the seed (same seed, same place; seeds differ).
  std::vector<std::int64_t> places;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    BdlstmSplit r, again;
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, r);
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, again);
    REQUIRE(r.test_begin == again.test_begin);
    REQUIRE(r.test_end[0] - r.test_begin[0] == 20);
    REQUIRE(r.test_end[1] - r.test_begin[1] == 6);
    REQUIRE(r.test_begin[0] >= 0);
    REQUIRE(r.test_end[0] <= 100);
    REQUIRE(r.test_begin[1] >= 100);
    REQUIRE(r.test_end[1] <= 130);
    places.push_back(r.test_begin[0]);
  }
  std::sort(places.begin(), places.end());
  REQUIRE(std::unique(places.begin(), places.end()) - places.begin() > 3);
}

TEST_CASE("BD-LSTM split: a validation part carved out of the training frames",
          "[models][bdlstm]") {
  std::vector<std::int64_t> places;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    BdlstmSplit plain, v, again;
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, plain);
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, v, 0.1);
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, again, 0.1);
    // The test part does not move; the validation part is deterministic per seed.
    REQUIRE(v.test_begin == plain.test_begin);
    REQUIRE(v.validation_begin == again.validation_begin);
    for (std::size_t s = 0; s < 2; ++s) {
      const std::int64_t b = v.validation_begin[s], e = v.validation_end[s];
      REQUIRE(e - b == (s == 0 ? 10 : 3));
      REQUIRE(b >= v.train_begin[s]);
      REQUIRE(e <= v.train_end[s]);
      REQUIRE((e <= v.test_begin[s] || b >= v.test_end[s]));  // clear of the test part
    }
    // No training window touches either part.
    for (std::int64_t f : window_starts(v, 5)) {
      const std::size_t s = f < 100 ? 0 : 1;
      REQUIRE((f + 5 <= v.validation_begin[s] || f >= v.validation_end[s]));
      REQUIRE((f + 5 <= v.test_begin[s] || f >= v.test_end[s]));
    }
    REQUIRE(window_starts(v, 5).size() < window_starts(plain, 5).size());
    places.push_back(v.validation_begin[0]);
  }
  std::sort(places.begin(), places.end());
  REQUIRE(std::unique(places.begin(), places.end()) - places.begin() > 3);
  // No validation: empty ranges, the same windows as before.
  BdlstmSplit none;
  split_sequences({0, 50}, 0.2, TestPart::end, 1, none);
  REQUIRE(none.validation_begin == none.validation_end);
  // Too large for the training runs beside a test part in the middle (40 + 40 frames).
  BdlstmSplit big;
  REQUIRE_THROWS_AS(split_sequences({0, 100}, 0.2, TestPart::middle, 1, big, 0.5),
                    df::InvalidInput);
  REQUIRE_THROWS_AS(split_sequences({0, 100}, 0.2, TestPart::end, 1, big, 0.8), UsageError);
}

TEST_CASE("BD-LSTM split: a stopping part that keeps the longest training stretch whole",
          "[models][bdlstm]") {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    BdlstmSplit v, vs;
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, v, 0.1);
    split_sequences({0, 100, 130}, 0.2, TestPart::random, seed, vs, 0.1, 0.1);
    // The test and validation parts do not move.
    REQUIRE(vs.test_begin == v.test_begin);
    REQUIRE(vs.validation_begin == v.validation_begin);
    for (std::size_t s = 0; s < 2; ++s) {
      const std::int64_t b = vs.stopping_begin[s], e = vs.stopping_end[s];
      REQUIRE(e - b == (s == 0 ? 10 : 3));
      REQUIRE(b >= vs.train_begin[s]);
      REQUIRE(e <= vs.train_end[s]);
      REQUIRE((e <= vs.test_begin[s] || b >= vs.test_end[s]));
      REQUIRE((e <= vs.validation_begin[s] || b >= vs.validation_end[s]));
    }
    // No training window touches it; its own windows lie inside it.
    for (std::int64_t f : window_starts(vs, 5)) {
      const std::size_t s = f < 100 ? 0 : 1;
      REQUIRE((f + 5 <= vs.stopping_begin[s] || f >= vs.stopping_end[s]));
    }
    REQUIRE(window_starts(vs, 5).size() < window_starts(v, 5).size());
    const auto inside = range_starts(vs.stopping_begin, vs.stopping_end, 5);
    REQUIRE(inside.size() == 6);  // 10 frames hold 6 windows of 5, 3 frames none
    REQUIRE(inside.front() == vs.stopping_begin[0]);
  }
  // It keeps the longest stretch of training frames whole: no clear place leaves a longer one,
  // and it cuts no stretch in two.
  const auto longest_run = [](const BdlstmSplit& sp, std::size_t s, std::int64_t lo,
                              std::int64_t hi) {
    std::int64_t best = 0, run = 0;
    for (std::int64_t f = sp.train_begin[s]; f < sp.train_end[s]; ++f) {
      const auto in = [&](const std::vector<std::int64_t>& b, const std::vector<std::int64_t>& e) {
        return f >= b[s] && f < e[s];
      };
      const bool held = (f >= lo && f < hi) || in(sp.test_begin, sp.test_end) ||
                        in(sp.validation_begin, sp.validation_end);
      run = held ? 0 : run + 1;
      best = std::max(best, run);
    }
    return best;
  };
  for (std::uint64_t seed = 1; seed <= 8; ++seed)
    for (const TestPart part : {TestPart::end, TestPart::middle, TestPart::random}) {
      BdlstmSplit sp;
      split_sequences({0, 100, 160}, 0.2, part, seed, sp, 0.1, 0.15);
      for (std::size_t s = 0; s < 2; ++s) {
        const std::int64_t n = sp.stopping_end[s] - sp.stopping_begin[s];
        const std::int64_t kept = longest_run(sp, s, sp.stopping_begin[s], sp.stopping_end[s]);
        // It cuts no stretch in two: a frame before it and one after are not both free.
        BdlstmSplit without = sp;
        without.stopping_begin[s] = without.stopping_end[s] = 0;
        const auto free = window_starts(without, 1);
        const auto is_free = [&](std::int64_t f) {  // a free training frame of this sequence
          return f >= sp.train_begin[s] && f < sp.train_end[s] &&
                 std::find(free.begin(), free.end(), f) != free.end();
        };
        REQUIRE(!(is_free(sp.stopping_begin[s] - 1) && is_free(sp.stopping_end[s])));
        for (std::int64_t v = sp.train_begin[s]; v + n <= sp.train_end[s]; ++v) {
          BdlstmSplit clear = sp;  // v is a place when the part fits there clear of the others
          clear.stopping_begin[s] = clear.stopping_end[s] = 0;
          const auto fits = window_starts(clear, n);
          if (std::find(fits.begin(), fits.end(), v) != fits.end())
            REQUIRE(longest_run(sp, s, v, v + n) <= kept);
        }
      }
    }
  // No stopping part: empty ranges and the same windows.
  BdlstmSplit none, plain;
  split_sequences({0, 50}, 0.2, TestPart::end, 1, none, 0.1, 0);
  split_sequences({0, 50}, 0.2, TestPart::end, 1, plain, 0.1);
  REQUIRE(none.stopping_begin == none.stopping_end);
  REQUIRE(window_starts(none, 5) == window_starts(plain, 5));
  BdlstmSplit big;
  REQUIRE_THROWS_AS(split_sequences({0, 100}, 0.2, TestPart::end, 1, big, 0.4, 0.4), UsageError);
}

TEST_CASE("BD-LSTM remedies: L2 without biases, L2 weight, a small last decoder layer",
          "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  const auto window = sine_windows<double>(5, 3, 2);
  auto terms_of = [&](const BdlstmConfig& c) {
    BdlstmNet<double> net(c, 4, tetra_edges(), 3);
    nn::Tape<double> tape;
    auto p = net.store().bind(tape);
    Rng rng(1, 0);
    BdlstmLossTerms t;
    net.loss(tape, p, window, rng, &t);
    double biases = 0;
    for (std::size_t i = 0; i < net.store().views().size(); ++i)
      if (net.store().views()[i].name.ends_with(".bias"))
        biases += net.store().value(static_cast<int>(i)).squaredNorm();
    return std::pair{t, biases};
  };
  const auto [paper, biases] = terms_of(cfg);
  REQUIRE(biases > 0);  // the LSTM forget-gate biases start at 1
  cfg.l2_scope = L2Scope::weights;
  const auto [weights_only, unused] = terms_of(cfg);
  REQUIRE(weights_only.l2 == Approx(paper.l2 - biases).epsilon(1e-12));
  REQUIRE(weights_only.recon == paper.recon);
  // tf: the forget-gate biases (1 at the start) are measured from 1, so they add nothing at first
  // (hidden 4 × 2 layers of them); every other value counts as in "all".
  cfg.l2_scope = L2Scope::tf;
  const auto [tf, unused_tf] = terms_of(cfg);
  REQUIRE(tf.l2 == Approx(paper.l2 - 4 * 2).epsilon(1e-12));
  {
    BdlstmNet<double> net(cfg, 4, tetra_edges(), 7);
    const auto [error, report] = loss_gradient_error(net, window);
    INFO(report);
    REQUIRE(error <= 1e-6);
  }
  cfg.l2_scope = L2Scope::all;
  cfg.l2_weight = 0.25;
  const auto [quarter, unused2] = terms_of(cfg);
  REQUIRE(quarter.l2 == Approx(paper.l2).epsilon(1e-12));  // reported unweighted
  REQUIRE(quarter.total == Approx(paper.total - 0.1 * 0.75 * paper.l2).epsilon(1e-12));
  cfg.l2_weight = 1;

  // decoder_init small: the untrained network predicts a small change, and the encoder gets a
  // gradient at once (it gets none while the last layer is zero).
  cfg = tiny_config(Directions::shared);
  auto encoder_grad = [&](const BdlstmConfig& c, double* change) {
    BdlstmNet<double> net(c, 4, tetra_edges(), 3);
    nn::Tape<double> tape;
    auto p = net.store().bind(tape);
    auto states = net.constant_states(tape, 3, 0.1);
    const auto x = window[0];
    *change = (net.step(p, 0, tape.constant(x), states, nullptr, nullptr).value() - x)
                  .cwiseAbs()
                  .maxCoeff();
    Rng rng(1, 0);
    net.store().zero_grad();
    nn::Tape<double> t2;
    auto p2 = net.store().bind(t2);
    BdlstmNet<double>::Var loss = net.loss(t2, p2, window, rng);
    t2.backward(loss);
    net.store().collect(p2);
    return net.store().grad(net.store().find("conv0.point")).cwiseAbs().maxCoeff();
  };
  double change = 0;
  // (with KL the encoder's mean still gets the KL gradient; switch it off to see recon's alone)
  cfg.kl = false;
  cfg.l2 = false;
  REQUIRE(encoder_grad(cfg, &change) == 0);
  REQUIRE(change == 0);
  cfg.decoder_init = DecoderInit::small;
  REQUIRE(encoder_grad(cfg, &change) > 0);
  REQUIRE(change > 0);
  REQUIRE(change < 0.05);
}

TEST_CASE("BD-LSTM free bits: a dimension's KL below the floor costs nothing", "[models][bdlstm]") {
  auto cfg = tiny_config(Directions::shared);
  const auto window = sine_windows<double>(4, 2, 5);
  auto kl_of = [&](double free_bits, double scale_mean) {
    auto c = cfg;
    c.free_bits = free_bits;
    BdlstmNet<double> net(c, 4, tetra_edges(), 3);
    Rng w(9, 0);
    for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(net.store().size()); ++k)
      net.store().values()[k] = scale_mean * w.uniform(-0.5, 0.5);
    nn::Tape<double> tape;
    auto p = net.store().bind(tape);
    Rng rng(1, 0);
    BdlstmLossTerms t;
    net.loss(tape, p, window, rng, &t);
    return t;
  };
  // Weights near 0: q(z|x) ≈ N(0, 1), every dimension below the floor → the floor exactly:
  // latent 3 × 3 steps × 2 chains (the shared batch) per window.
  const auto floor = kl_of(0.5, 1e-4);
  REQUIRE(floor.kl == Approx(0.5 * 3 * 3 * 2).epsilon(1e-9));
  // Large weights: an informative latent above the floor pays its full KL.
  const auto paper = kl_of(0, 1), free = kl_of(1e-6, 1);
  REQUIRE(paper.kl > 1);
  REQUIRE(free.kl == Approx(paper.kl).epsilon(1e-6));
  REQUIRE(free.recon == paper.recon);
  cfg.free_bits = -1;
  REQUIRE_THROWS_AS(BdlstmNet<double>(cfg, 4, tetra_edges(), 3), UsageError);

  // Gradients through the floor (dimensions above it) match central differences.
  cfg.free_bits = 0.05;
  BdlstmNet<double> net(cfg, 4, tetra_edges(), 7);
  const auto [error, report] = loss_gradient_error(net, window);
  INFO(report);
  REQUIRE(error <= 1e-6);
}
