// Gradient checks (double) of ActGAN's networks on tiny sizes: the generator (frames and
// smoothness), the discriminator and classifier, the generator's whole adversarial + cycle loss
// through both or through a critic of whole clips, and the critic's gradient penalty (a gradient
// of a gradient).
#include <catch2/catch.hpp>

#include "core/error.h"
#include "models/actgan/network.h"
#include "nn/gradient_check.h"
#include "nn/ops.h"

using namespace df;
using namespace df::models;

namespace {

ActganConfig tiny() {
  ActganConfig c;
  c.pose = 6;
  c.classes = 2;
  c.noise = 3;
  c.latent = 2;
  c.hidden = 3;
  c.fc = 4;
  c.sigma1 = 0.3;  // large enough to matter in the check
  c.sigma2 = 0.2;
  return c;
}

std::vector<nn::Matrix<double>> values(const nn::ParameterStore<double>& s) {
  std::vector<nn::Matrix<double>> v;
  for (std::size_t i = 0; i < s.views().size(); ++i) v.push_back(s.value(static_cast<int>(i)));
  return v;
}

nn::Matrix<double> random(Eigen::Index r, Eigen::Index c, std::uint64_t seed) {
  Rng rng(seed);
  nn::Matrix<double> m(r, c);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = rng.normal();
  return m;
}

// Inputs of a generated batch of 2 sequences of 4 frames (labels 0 and 1).
struct GenInputs {
  nn::Matrix<double> y = one_hot<double>({0, 1}, 2), h1 = random(2, 2, 3);
  std::vector<nn::Matrix<double>> noise{random(2, 3, 4), random(2, 3, 5), random(2, 3, 6)};
  GeneratedSequences<double> run(const ActganGenerator<double>& g, nn::Tape<double>& t,
                                 const nn::Bound<double>& p) const {
    std::vector<nn::Var<double>> xi;
    for (const auto& n : noise) xi.push_back(t.constant(n));
    return g.generate(p, t.constant(y), t.constant(h1), xi);
  }
};

}  // namespace

TEST_CASE("ActGAN: generator frames and smoothness, residual and direct latent",
          "[models][actgan]") {
  for (bool residual : {true, false}) {
    for (Smoothness smooth : {Smoothness::both, Smoothness::latent, Smoothness::action}) {
      ActganConfig c = tiny();
      c.residual = residual;
      c.smoothness = smooth;
      Rng rng(1);
      ActganGenerator<double> g(c, rng);
      GenInputs in;
      auto r = nn::gradient_check(
          [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
            const auto s = in.run(g, t, nn::Bound<double>{x});
            return nn::add(nn::sum_squares(nn::concat_rows<double>(s.frames)), smoothness(c, s));
          },
          values(g.store()));
      INFO("residual " << residual << " smoothness " << name_of(smooth) << "\n" << r.report);
      CHECK(r.max_error <= 1e-6);
    }
  }
  // the direct-pose baseline: T noise steps, the LSTM's output through one FC is the pose
  ActganConfig pc = tiny();
  pc.generator = Generator::pose;
  Rng prng(1);
  ActganGenerator<double> pg(pc, prng);
  GenInputs pin;
  pin.noise.push_back(random(2, 3, 11));
  auto pr = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        const auto s = pin.run(pg, t, nn::Bound<double>{x});
        return nn::add(nn::sum_squares(nn::concat_rows<double>(s.frames)), smoothness(pc, s));
      },
      values(pg.store()));
  INFO("pose baseline\n" << pr.report);
  CHECK(pr.max_error <= 1e-6);
  CHECK(pg.store().find("gen.decoder.0.weight") < 0);
  // residual: h_{t+1} - h_t is the LSTM's output; h_1 is the given start
  ActganConfig c = tiny();
  Rng rng(1);
  ActganGenerator<double> g(c, rng);
  nn::Tape<double> t;
  GenInputs in;
  const auto s = in.run(g, t, g.store().bind(t));
  REQUIRE(s.frames.size() == 4);
  CHECK(s.latents[0].value() == in.h1);
  CHECK(s.frames[2].cols() == 6);
}

TEST_CASE("ActGAN: discriminator and classifier gradients", "[models][actgan]") {
  ActganConfig c = tiny();
  Rng rng(2);
  SequenceNet<double> d(c, c.pose + c.classes, 1, "disc", rng),
      cls(c, c.pose, c.classes, "cls", rng);
  std::vector<nn::Matrix<double>> frames{random(2, 6, 7), random(2, 6, 8), random(2, 6, 9)};
  const auto y = one_hot<double>({1, 0}, 2);
  auto rd = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        std::vector<nn::Var<double>> seq;
        for (const auto& f : frames) seq.push_back(t.constant(f));
        return nn::bce_with_logits(d(nn::Bound<double>{x}, with_label(seq, t.constant(y))),
                                   nn::Matrix<double>(nn::Matrix<double>::Ones(2, 1)));
      },
      values(d.store()));
  INFO(rd.report);
  CHECK(rd.max_error <= 1e-6);
  auto rc = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        std::vector<nn::Var<double>> seq;
        for (const auto& f : frames) seq.push_back(t.constant(f));
        return nn::softmax_cross_entropy(cls(nn::Bound<double>{x}, seq), {1, 0});
      },
      values(cls.store()));
  INFO(rc.report);
  CHECK(rc.max_error <= 1e-6);
}

TEST_CASE("ActGAN: the generator's loss through discriminator and classifier", "[models][actgan]") {
  ActganConfig c = tiny();
  Rng rng(3);
  ActganGenerator<double> g(c, rng);
  SequenceNet<double> d(c, c.pose + c.classes, 1, "disc", rng),
      cls(c, c.pose, c.classes, "cls", rng);
  GenInputs in;
  const std::size_t ng = g.store().views().size();
  auto params = values(g.store());
  for (auto& m : values(cls.store())) params.push_back(m);
  const auto pd = values(d.store());
  auto r = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        nn::Bound<double> pg{{x.begin(), x.begin() + static_cast<std::ptrdiff_t>(ng)}};
        nn::Bound<double> pc{{x.begin() + static_cast<std::ptrdiff_t>(ng), x.end()}};
        nn::Bound<double> bd;
        for (const auto& m : pd) bd.vars.push_back(t.constant(m));
        const auto s = in.run(g, t, pg);
        const auto y = t.constant(in.y);
        const auto adv = nn::bce_with_logits(d(bd, with_label(s.frames, y)),
                                             nn::Matrix<double>(nn::Matrix<double>::Ones(2, 1)));
        const auto cyc = nn::softmax_cross_entropy(cls(pc, s.frames), {0, 1});
        return nn::add(nn::add(adv, smoothness(c, s)), nn::scale(cyc, 0.5));
      },
      params);
  INFO(r.report);
  CHECK(r.max_error <= 1e-6);
}

TEST_CASE("ActGAN: the critic's input gradient and its gradient penalty", "[models][actgan]") {
  ActganConfig c = tiny();
  Rng rng(4);
  Critic<double> critic(c, c.pose, "critic", rng);
  const auto x = random(3, 6, 10), y = one_hot<double>({0, 1, 1}, 2);
  // the penalty's gradient w.r.t. the critic's weights (through the input gradient)
  auto r = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& w) {
        return critic.gradient_penalty(nn::Bound<double>{w}, t.constant(x), t.constant(y));
      },
      values(critic.store()));
  INFO(r.report);
  CHECK(r.max_error <= 1e-6);
  // the penalty is (|grad_x D| - 1)^2 with grad_x D from central differences of the score
  nn::Tape<double> t;
  const auto p = critic.store().bind(t);
  const double penalty = critic.gradient_penalty(p, t.constant(x), t.constant(y)).value()(0, 0);
  double expected = 0;
  for (Eigen::Index row = 0; row < 3; ++row) {
    double sq = 0;
    for (Eigen::Index k = 0; k < 6; ++k) {
      nn::Matrix<double> up = x, down = x;
      up(row, k) += 1e-6;
      down(row, k) -= 1e-6;
      nn::Tape<double> u;
      const auto pu = critic.store().bind(u);
      const double d = (critic(pu, u.constant(up), u.constant(y)).value()(row, 0) -
                        critic(pu, u.constant(down), u.constant(y)).value()(row, 0)) /
                       2e-6;
      sq += d * d;
    }
    expected += (std::sqrt(sq) - 1) * (std::sqrt(sq) - 1) / 3;
  }
  CHECK(penalty == Approx(expected).epsilon(1e-6));
}

TEST_CASE("ActGAN: the generator's loss through a critic of whole clips", "[models][actgan]") {
  // --discriminator critic: the critic reads the 4 generated frames side by side [B, 4 P]; the
  // generator's term -mean critic(x_1..x_4, y) and the penalty at a clip, checked as above.
  ActganConfig c = tiny();
  Rng rng(5);
  ActganGenerator<double> g(c, rng);
  Critic<double> critic(c, 4 * c.pose, "disc", rng);
  CHECK(critic.store().views().front().rows == 4 * c.pose + c.classes);
  GenInputs in;
  const auto pd = values(critic.store());
  auto r = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& w) {
        nn::Bound<double> bd;
        for (const auto& m : pd) bd.vars.push_back(t.constant(m));
        const auto s = in.run(g, t, nn::Bound<double>{w});
        return nn::add(
            nn::scale(nn::mean(critic(bd, nn::concat_cols<double>(s.frames), t.constant(in.y))),
                      -1.0),
            smoothness(c, s));
      },
      values(g.store()));
  INFO(r.report);
  CHECK(r.max_error <= 1e-6);
  auto rp = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& w) {
        return critic.gradient_penalty(nn::Bound<double>{w}, t.constant(random(2, 4 * c.pose, 11)),
                                       t.constant(in.y));
      },
      pd);
  INFO(rp.report);
  CHECK(rp.max_error <= 1e-6);
}

TEST_CASE("ActGAN: --step-init small starts the generator near its h_1", "[models][actgan]") {
  // The same draw, the output layer x 0.01: every step v_t and so every drift from h_1 is 100x
  // smaller (the bias starts at 0), the rest of the network unchanged.
  auto drift = [](StepInit init) {
    ActganConfig c = tiny();
    c.step_init = init;
    Rng rng(1);
    ActganGenerator<double> g(c, rng);
    nn::Tape<double> t;
    GenInputs in;
    const auto s = in.run(g, t, g.store().bind(t));
    return (s.latents.back().value() - s.latents.front().value()).norm();
  };
  const double glorot = drift(StepInit::glorot), small = drift(StepInit::small);
  CHECK(glorot > 1e-3);
  CHECK(small == Approx(0.01 * glorot).epsilon(1e-9));
}

TEST_CASE("ActGAN: the discriminator on frames and differences over every step",
          "[models][actgan]") {
  // --disc-input motion --disc-pool all (the authors' discriminator): gradients w.r.t. its
  // weights and through its input to the generator's; the input holds x_t, x_t - x_{t-1}
  // (0 at the first frame) and y; the head reads all T steps and refuses another length.
  ActganConfig c = tiny();
  c.disc_input = DiscInput::motion;
  c.disc_pool = DiscPool::all;
  Rng rng(5);
  ActganGenerator<double> g(c, rng);
  const auto d = make_discriminator<double>(c, 4, rng);
  CHECK(discriminator_width(c) == 2 * c.pose + c.classes);
  CHECK(d->store().value(d->store().find("disc.head.0.weight")).rows() == 4 * 2 * c.hidden);
  GenInputs in;
  const auto ones = nn::Matrix<double>(nn::Matrix<double>::Ones(2, 1));
  auto rd = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        const auto s = in.run(g, t, g.store().bind_constant(t));
        return nn::bce_with_logits(
            (*d)(nn::Bound<double>{x}, discriminator_input(c, s.frames, t.constant(in.y))), ones);
      },
      values(d->store()));
  INFO(rd.report);
  CHECK(rd.max_error <= 1e-6);
  auto rg = nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& x) {
        const auto s = in.run(g, t, nn::Bound<double>{x});
        return nn::bce_with_logits(
            (*d)(d->store().bind_constant(t), discriminator_input(c, s.frames, t.constant(in.y))),
            ones);
      },
      values(g.store()));
  INFO(rg.report);
  CHECK(rg.max_error <= 1e-6);
  nn::Tape<double> t;
  const auto s = in.run(g, t, g.store().bind(t));
  const auto x = discriminator_input(c, s.frames, t.constant(in.y));
  REQUIRE(x.size() == 4);
  CHECK(x[0].value().middleCols(6, 6).norm() == 0);
  CHECK(x[2].value().leftCols(6) == s.frames[2].value());
  CHECK(x[2].value().middleCols(6, 6).isApprox(s.frames[2].value() - s.frames[1].value()));
  CHECK(x[2].value().rightCols(2) == in.y);
  const std::vector<nn::Var<double>> three(x.begin(), x.begin() + 3);
  CHECK_THROWS_AS((*d)(d->store().bind(t), three), Error);
}
