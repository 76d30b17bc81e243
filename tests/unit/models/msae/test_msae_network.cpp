#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "helpers.h"
#include "models/msae/model.h"
#include "models/msae/network.h"
#include "nn/adam.h"
#include "nn/gradient_check.h"

using namespace df;
using namespace df::models;

namespace {

std::vector<std::array<int, 2>> grid_edges() {
  return test::grid3x3_edges();
}

nn::Matrix<double> random_shapes(int rows, std::uint64_t seed) {
  Rng rng(seed, 5);
  return nn::random_matrix(rows, 81, rng, -0.9, 0.9);
}

// Random 0/1 masks for Ω (the geodesic step function, with fixed centres).
std::vector<nn::Matrix<double>> random_lambda(const MsaeNet<double>& net, std::uint64_t seed) {
  Rng rng(seed, 6);
  std::vector<nn::Matrix<double>> out;
  for (const auto& b : net.blocks()) {
    nn::Matrix<double> m(b.kz, net.n_vertices());
    for (Eigen::Index k = 0; k < m.size(); ++k) m.data()[k] = rng.uniform(0, 1) < 0.5 ? 0 : 1;
    out.push_back(m);
  }
  return out;
}

// The loss's gradient against finite differences, for every parameter of `net`, on shapes x.
nn::GradientCheck check_loss_gradient(MsaeNet<double>& net, const nn::Matrix<double>& x,
                                      const std::vector<nn::Matrix<double>>& lambda) {
  std::vector<nn::Matrix<double>> params;
  for (std::size_t i = 0; i < net.store().views().size(); ++i)
    params.push_back(net.store().value(static_cast<int>(i)));
  return nn::gradient_check(
      [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& v) {
        return net.loss(t, nn::Bound<double>{v}, x, lambda);
      },
      params);
}

MsaeConfig tiny(std::vector<int> kz, bool attention) {
  MsaeConfig c;
  c.kz = kz;
  c.d.assign(kz.size(), 0.3);
  c.attention = attention;
  c.theta = 0.3;  // tanh codes never pass the paper's θ = 5: a small θ makes V(Z) act
  return c;
}

}  // namespace

TEST_CASE("MSAE: the tree of blocks", "[models][msae]") {
  MsaeNet<float> net(tiny({3, 2}, true), 9, grid_edges(), 1);
  REQUIRE(net.blocks().size() == 4);  // AE0 and one second-level AE per component of AE0
  CHECK(net.level_begin() == std::vector<int>{0, 1, 4});
  CHECK(net.blocks()[2].parent == 0);
  CHECK(net.blocks()[2].slot == 1);
  MsaeNet<float> plain(tiny({3, 2, 2}, false), 9, grid_edges(), 1);
  REQUIRE(plain.blocks().size() == 3);  // one block per level, as many components as the tree
  CHECK(plain.blocks()[1].kz == 6);
  CHECK(plain.blocks()[2].kz == 12);  // 6 blocks × 2 in the attention tree
  CHECK_THROWS(MsaeNet<float>(MsaeConfig{{10, 5}, {0.4}}, 9, grid_edges(), 1));
}

TEST_CASE("MSAE loss: gradients of every parameter (attention, none, three levels)",
          "[models][msae]") {
  for (auto [kz, attention] :
       {std::pair{std::vector<int>{3, 2}, true}, std::pair{std::vector<int>{2, 2}, false},
        std::pair{std::vector<int>{2, 2, 2}, true}}) {
    MsaeNet<double> net(tiny(kz, attention), 9, grid_edges(), 3);
    const auto x = random_shapes(4, 1);
    const auto lambda = random_lambda(net, 2);
    MsaeLossTerms terms;
    {
      nn::Tape<double> t;
      net.loss(t, net.store().bind(t), x, lambda, &terms);
    }
    const auto r = check_loss_gradient(net, x, lambda);
    INFO("levels " << kz.size() << " attention " << attention << "\n" << r.report);
    CHECK(terms.latent > 0);  // every term is exercised
    CHECK(terms.sparsity > 0);
    REQUIRE(r.max_error <= 1e-6);
  }
}

TEST_CASE("MSAE: the block-by-block gradient equals the one-tape gradient", "[models][msae]") {
  for (bool attention : {true, false})
    for (std::vector<int> levels : {std::vector<int>{}, std::vector<int>{1}, std::vector<int>{0}}) {
      MsaeNet<double> net(tiny({3, 2, 2}, attention), 9, grid_edges(), 4);
      const auto x = random_shapes(5, 7);
      const auto lambda = random_lambda(net, 8);
      nn::Tape<double> t;
      auto p = net.store().bind(t);
      MsaeLossTerms one;
      auto l = net.loss(t, p, x, lambda, &one, levels);
      t.backward(l);
      net.store().zero_grad();
      net.store().collect(p);
      const Eigen::VectorXd expected = net.store().grads();
      net.store().zero_grad();
      const MsaeLossTerms staged = net.loss_and_gradient(x, lambda, levels);
      INFO("attention " << attention << ", levels " << levels.size());
      CHECK(staged.total == Approx(one.total).epsilon(1e-12));
      CHECK(staged.recon == Approx(one.recon).epsilon(1e-12));
      CHECK(staged.sparsity == Approx(one.sparsity).epsilon(1e-12));
      CHECK(staged.latent == Approx(one.latent).margin(1e-12));
      REQUIRE((net.store().grads() - expected).cwiseAbs().maxCoeff() <=
              1e-10 * (1 + expected.cwiseAbs().maxCoeff()));
    }
}

TEST_CASE("MSAE: attention masks sum to 1 per vertex; reconstruction sums the levels",
          "[models][msae]") {
  MsaeNet<double> net(tiny({3, 2}, true), 9, grid_edges(), 5);
  const auto am = net.attention_masks(0);
  REQUIRE(am.rows() == 3);
  CHECK((am.colwise().sum().array() - 1).abs().maxCoeff() < 1e-12);
  CHECK(am.minCoeff() >= 0);
  // The first level's reconstruction is AE0's output: its loss term is ‖x − x̂₀‖² / B.
  const auto x = random_shapes(3, 9);
  const auto lambda = random_lambda(net, 1);
  MsaeLossTerms level0;
  {
    nn::Tape<double> t;
    net.loss(t, net.store().bind(t), x, lambda, &level0, {0});
  }
  std::vector<nn::Matrix<double>> codes;
  const auto one = net.reconstruct(x, 1, &codes);
  CHECK((x - one).squaredNorm() / 3 == Approx(level0.recon).epsilon(1e-12));
  CHECK(codes[0].rows() == 3);
  CHECK(codes[0].cols() == 3);
  CHECK(codes[1].size() == 0);  // level 1 not run
  // Two levels add the second-level outputs: the decoders of the blocks on their codes.
  const auto two = net.reconstruct(x, 2, &codes);
  nn::Matrix<double> sum = one;
  for (int b = 1; b < 4; ++b) sum += net.decode(b, codes[static_cast<std::size_t>(b)]);
  CHECK((two - sum).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((one - net.decode(0, codes[0])).cwiseAbs().maxCoeff() < 1e-12);
  CHECK_THROWS(net.reconstruct(x, 3));
}

TEST_CASE("MSAE: centres are the strongest vertex of each component", "[models][msae]") {
  MsaeNet<float> net(tiny({2, 2}, true), 9, grid_edges(), 6);
  net.store().value(net.blocks()[0].c).row(1).segment(9 * 7, 9).setConstant(3.0f);
  const auto c = net.centres();
  CHECK(c[0][1] == 7);
  // Ω's step masks: 1 where the distance from the centre is at least d (0.3 here).
  const auto lam = net.sparsity_masks(c, [](int centre) {
    Eigen::VectorXf d = Eigen::VectorXf::Constant(9, 0.5f);
    d[centre] = 0;
    return d;
  });
  CHECK(lam[0](1, 7) == 0);
  CHECK(lam[0](1, 0) == 1);
}

TEST_CASE("MSAE: a batch with repeated shapes equals its distinct shapes weighted by count",
          "[models][msae]") {
  MsaeNet<double> net(tiny({3, 2}, true), 9, grid_edges(), 8);
  const auto shapes = random_shapes(3, 4);
  const auto lambda = random_lambda(net, 5);
  // rows 0, 1, 0, 2, 0, 1 → distinct 0, 1, 2 with counts 3, 2, 1
  nn::Matrix<double> full(6, 81);
  const int pick[] = {0, 1, 0, 2, 0, 1};
  for (int r = 0; r < 6; ++r) full.row(r) = shapes.row(pick[r]);
  nn::Matrix<double> w(3, 1);
  w << 3, 2, 1;
  net.store().zero_grad();
  const auto a = net.loss_and_gradient(full, lambda);
  const Eigen::VectorXd ga = net.store().grads();
  net.store().zero_grad();
  const auto b = net.loss_and_gradient(shapes, lambda, {}, &w);
  CHECK(b.total == Approx(a.total).epsilon(1e-12));
  CHECK(b.latent == Approx(a.latent).margin(1e-12));
  REQUIRE((net.store().grads() - ga).cwiseAbs().maxCoeff() <=
          1e-10 * (1 + ga.cwiseAbs().maxCoeff()));
}

TEST_CASE(
    "MSAE: the convMesh variants (linear decoder FC, shared decoder convolution, N(0, 0.02) "
    "initialisation) are gradient-checked and change what they say",
    "[models][msae]") {
  MsaeConfig c = tiny({3, 2}, true);
  c.decoder_fc = MsaeActivation::linear;
  c.decoder_conv = DecoderConv::shared;
  c.init = MsaeInit::normal;
  MsaeNet<double> net(c, 9, grid_edges(), 3);
  // N(0, 0.02²): every weight of C and of the convolutions is small; Glorot's are not all.
  const auto& C = net.store().value(net.blocks()[0].c);
  CHECK(C.cwiseAbs().maxCoeff() < 0.02 * 6);
  CHECK(std::sqrt(C.squaredNorm() / static_cast<double>(C.size())) == Approx(0.02).epsilon(0.35));
  MsaeNet<double> glorot(tiny({3, 2}, true), 9, grid_edges(), 3);
  CHECK(glorot.store().value(glorot.blocks()[0].conv.w_point).cwiseAbs().maxCoeff() > 0.2);
  // The decoder: y = z C (no tanh) and the encoder's convolution weights as they are.
  const auto& b = net.blocks()[0];
  nn::Matrix<double> z(1, 3);
  z << 30, -20, 10;  // large codes: a tanh after z C would saturate at ±1
  nn::Matrix<double> y = z * net.store().value(b.c);
  nn::Tape<double> t;
  const auto a = nn::neighbour_mean_operator<double>(9, grid_edges());
  const nn::Matrix<double> expect =
      nn::tanh(nn::mesh_conv(t.constant(y), t.constant(net.store().value(b.conv.w_point)),
                             t.constant(net.store().value(b.conv.w_nb)),
                             t.constant(net.store().value(b.b_dec)), a))
          .value();
  CHECK((net.decode(0, z) - expect).cwiseAbs().maxCoeff() < 1e-12);
  // Gradients of every parameter through the variant (Glorot weights: N(0, 0.02²) ones make
  // gradients so small that finite differences, not the formula, limit the check).
  MsaeConfig g = c;
  g.init = MsaeInit::glorot;
  MsaeNet<double> checked(g, 9, grid_edges(), 3);
  const auto x = random_shapes(4, 1);
  const auto r = check_loss_gradient(checked, x, random_lambda(checked, 2));
  INFO(r.report);
  REQUIRE(r.max_error <= 1e-6);
  // "small": C at Glorot × 0.01, the convolutions as Glorot's.
  MsaeConfig sm = tiny({3, 2}, true);
  sm.init = MsaeInit::small;
  MsaeNet<double> small(sm, 9, grid_edges(), 3);
  CHECK(
      (small.store().value(small.blocks()[0].c) - 0.01 * glorot.store().value(glorot.blocks()[0].c))
          .cwiseAbs()
          .maxCoeff() < 1e-15);
  CHECK(small.store().value(small.blocks()[0].conv.w_point) ==
        glorot.store().value(glorot.blocks()[0].conv.w_point));
}

TEST_CASE(
    "MSAE: fitted codes reconstruct at least as well as the encoder's and recover a decoded shape",
    "[models][msae]") {
  MsaeConfig c = tiny({3, 2}, true);
  c.decoder_fc = MsaeActivation::linear;
  MsaeNet<double> net(c, 9, grid_edges(), 11);
  const auto x = random_shapes(3, 12);
  std::vector<nn::Matrix<double>> codes;
  const auto encoded = net.reconstruct(x, 2, &codes);
  auto fitted_codes = codes;
  const auto fitted = net.fit_codes(x, 2, fitted_codes, 400, 0.05);
  CHECK((x - fitted).squaredNorm() < (x - encoded).squaredNorm());
  // A shape the decoders make from known codes is found again from the encoder's codes.
  std::vector<nn::Matrix<double>> truth = codes;
  nn::Matrix<double> target = nn::Matrix<double>::Zero(3, 81);
  for (std::size_t b = 0; b < truth.size(); ++b) {
    truth[b] = truth[b] * 0.7 + nn::Matrix<double>::Constant(truth[b].rows(), truth[b].cols(), 0.2);
    target += net.decode(static_cast<int>(b), truth[b]);
  }
  auto start = codes;
  const auto found = net.fit_codes(target, 2, start, 3000, 0.05);
  CHECK((found - target).cwiseAbs().maxCoeff() < 1e-3);
  CHECK_THROWS(net.fit_codes(x, 3, start, 10, 0.05));
}

TEST_CASE("MSAE: recombined shapes are the decoders' sums on codes taken from the shapes given",
          "[models][msae]") {
  MsaeNet<double> net(tiny({3, 2}, true), 9, grid_edges(), 13);
  // One shape: every recombined shape is its reconstruction.
  const auto one = random_shapes(1, 14);
  Rng rng(1, 2);
  const auto same = net.recombined_shapes(one, 4, rng);
  REQUIRE(same.rows() == 4);
  for (Eigen::Index r = 0; r < 4; ++r)
    CHECK((same.row(r) - net.reconstruct(one, 2).row(0)).cwiseAbs().maxCoeff() < 1e-12);
  // Two shapes: each shape is Σ_b decode(b, z_b) with every code z_b,j one of the two shapes'
  // codes z_b,j; over many shapes both choices occur for every code, and the draws follow the Rng.
  const auto two = random_shapes(2, 15);
  std::vector<nn::Matrix<double>> codes;
  net.reconstruct(two, 2, &codes);
  Rng a(3, 4), b(3, 4);
  const int n = 40;
  const auto mixed = net.recombined_shapes(two, n, a);
  CHECK((mixed - net.recombined_shapes(two, n, b)).cwiseAbs().maxCoeff() == 0);
  Rng replay(3, 4);
  nn::Matrix<double> expect = nn::Matrix<double>::Zero(n, 81);
  for (std::size_t k = 0; k < codes.size(); ++k) {
    nn::Matrix<double> z(n, codes[k].cols());
    nn::Matrix<int> from(n, codes[k].cols());
    for (Eigen::Index j = 0; j < z.cols(); ++j)
      for (Eigen::Index r = 0; r < n; ++r) {
        from(r, j) = static_cast<int>(replay.below(2));
        z(r, j) = codes[k](from(r, j), j);
      }
    for (Eigen::Index j = 0; j < z.cols(); ++j) {
      CHECK(from.col(j).sum() > 0);
      CHECK(from.col(j).sum() < n);
    }
    expect += net.decode(static_cast<int>(k), z);
  }
  CHECK((mixed - expect).cwiseAbs().maxCoeff() < 1e-12);
  // Some recombined shapes are neither of the two shapes' reconstructions.
  const auto rec = net.reconstruct(two, 2);
  int new_ones = 0;
  for (Eigen::Index r = 0; r < n; ++r)
    new_ones +=
        (mixed.row(r) - rec.row(0)).norm() > 1e-6 && (mixed.row(r) - rec.row(1)).norm() > 1e-6;
  CHECK(new_ones > n / 2);
}

TEST_CASE("MSAE: place_centres makes the given vertices the centres", "[models][msae]") {
  MsaeNet<float> net(tiny({3, 2}, true), 9, grid_edges(), 7);
  std::vector<std::vector<int>> want = {{8, 0, 4}, {1, 2}, {3, 5}, {6, 7}};
  net.place_centres(want);
  CHECK(net.centres() == want);
}

TEST_CASE("MSAE: separate training's levels restart the rate or continue the schedule",
          "[models][msae]") {
  MsaeModel m;
  Faces f(8, 3);
  f << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7;
  m.tmpl.faces = f;
  m.tmpl.vertices = Vertices::Zero(9, 3);
  m.config = tiny({3, 2}, true);
  m.training.lr = 1e-3;
  m.training.lr_decay = 0.5;
  m.training.lr_decay_steps = 1000;
  m.initialize();
  CHECK(m.make_adam(2000)->learning_rate() == Approx(1e-3));  // restart (the default)
  m.training.separate_rate = SeparateRate::continue_;
  CHECK(m.make_adam(2000)->learning_rate() == Approx(2.5e-4));
  CHECK(m.make_adam(0)->learning_rate() == Approx(1e-3));
}

TEST_CASE("MSAE: --centre-separation gives a block's components centres apart", "[models][msae]") {
  MsaeConfig config = tiny({3}, true);
  config.d = {0.4};
  // Distances on the 3 × 3 grid: Chebyshev steps / 2 (so neighbours are 0.5 apart).
  auto distance = [](int c) {
    Eigen::VectorXf d(9);
    for (int i = 0; i < 9; ++i)
      d[i] = 0.5f * static_cast<float>(std::max(std::abs(i % 3 - c % 3), std::abs(i / 3 - c / 3)));
    return d;
  };
  std::vector<Eigen::VectorXf> rows;
  for (int c = 0; c < 9; ++c) rows.push_back(distance(c));
  auto row = [&](int c) -> const Eigen::VectorXf& { return rows[static_cast<std::size_t>(c)]; };
  auto peaked = [&](MsaeNet<float>& net) {
    auto C = net.store().value(net.blocks()[0].c);
    C.setConstant(0.01f);
    // All three components peak at vertex 4 (the centre); the strongest is component 2, and
    // component 0's second-best vertex is 0, component 1's is 8.
    for (int k = 0; k < 3; ++k)
      C.row(k).segment(9 * 4, 9).setConstant(1.0f + 0.5f * static_cast<float>(k));
    C.row(0).segment(9 * 0, 9).setConstant(0.5f);
    C.row(1).segment(9 * 8, 9).setConstant(0.5f);
  };
  MsaeNet<float> plain(config, 9, grid_edges(), 1);
  peaked(plain);
  CHECK(plain.centres()[0] == std::vector<int>{4, 4, 4});  // the paper's argmax: one centre
  config.centre_separation = 1;  // at least d = 0.4 apart: a neighbour is far enough
  MsaeNet<float> apart(config, 9, grid_edges(), 1);
  peaked(apart);
  const auto c = apart.separated_centres(row)[0];
  CHECK(c[2] == 4);  // the strongest keeps its peak
  CHECK(c[1] == 8);  // the next takes its best vertex outside d of vertex 4
  CHECK(c[0] == 0);
  config.centre_separation = 4;  // 1.6 apart: nothing is left after the first; plain argmax
  MsaeNet<float> crowded(config, 9, grid_edges(), 1);
  peaked(crowded);
  CHECK(crowded.separated_centres(row)[0] == std::vector<int>{4, 4, 4});
  config.centre_separation = -1;
  CHECK_THROWS_AS(MsaeNet<float>(config, 9, grid_edges(), 1), UsageError);
}

TEST_CASE("MSAE: --support hard zeroes C outside each component's radius", "[models][msae]") {
  MsaeConfig config = tiny({2, 2}, true);
  config.support = Support::hard;
  MsaeNet<double> net(config, 9, grid_edges(), 3);
  std::vector<nn::Matrix<double>> before;
  for (const auto& b : net.blocks()) before.push_back(net.store().value(b.c));
  const auto lambda = random_lambda(net, 8);
  net.project_onto_support(lambda);
  for (std::size_t b = 0; b < net.blocks().size(); ++b) {
    const auto C = net.store().value(net.blocks()[b].c);
    for (int k = 0; k < net.blocks()[b].kz; ++k)
      for (int i = 0; i < 9; ++i) {
        const auto group = C.row(k).segment(9 * i, 9);
        if (lambda[b](k, i) != 0)
          CHECK(group.norm() == 0);
        else
          CHECK(group == before[b].row(k).segment(9 * i, 9));
      }
  }
}

TEST_CASE(
    "MSAE: --support proximal shrinks C's groups outside the radius by Omega's step and zeroes the "
    "small ones exactly",
    "[models][msae]") {
  MsaeConfig config = tiny({2, 2}, true);
  config.support = Support::proximal;
  config.lambda_sparse = 3;
  MsaeNet<double> net(config, 9, grid_edges(), 3);
  const auto lambda = random_lambda(net, 8);
  // One Adam step from a known gradient: |g| = 0.5 everywhere gives v̂ = 0.25, so every
  // coordinate's step size is rate / (0.5 + ε).
  nn::AdamOptions o;
  o.lr = 0.02;
  nn::Adam<double> adam(net.store().size(), o);
  nn::Vector<double> zero = nn::Vector<double>::Zero(static_cast<Eigen::Index>(net.store().size()));
  nn::Vector<double> grad = nn::Vector<double>::Constant(zero.size(), 0.5);
  adam.step(zero, grad);  // moves a copy; the net's weights stay as they are
  const double eta = 0.02 / (0.5 + 1e-8);
  // Level 0's groups set to norms around the threshold λ·η/K_z = 3 · 0.04 / 2 = 0.06.
  auto C0 = net.store().value(net.blocks()[0].c);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 9; ++i)
      C0.row(k).segment(9 * i, 9).setConstant((i % 3 == 0 ? 0.05 : 0.3) / 3.0);  // norms 0.05, 0.3
  std::vector<nn::Matrix<double>> before;
  for (const auto& b : net.blocks()) before.push_back(net.store().value(b.c));
  net.proximal_sparsity(lambda, adam.last_step_sizes(), {0});
  const double tau = 3 * eta / 2;
  int zeroed = 0, shrunk = 0;
  for (std::size_t b = 0; b < net.blocks().size(); ++b) {
    const auto C = net.store().value(net.blocks()[b].c);
    for (int k = 0; k < net.blocks()[b].kz; ++k)
      for (int i = 0; i < 9; ++i) {
        const auto group = C.row(k).segment(9 * i, 9);
        const auto old = before[b].row(k).segment(9 * i, 9);
        if (b > 0 || lambda[b](k, i) == 0) {  // level 1 not asked for; inside the radius
          CHECK(group == old);
        } else if (old.norm() <= tau) {
          CHECK(group.norm() == 0);
          ++zeroed;
        } else {
          CHECK(group.norm() == Approx(old.norm() - tau).epsilon(1e-12));
          CHECK((group / group.norm() - old / old.norm()).norm() < 1e-12);  // same direction
          ++shrunk;
        }
      }
  }
  CHECK(zeroed > 0);
  CHECK(shrunk > 0);
  // Where the reconstruction's gradient is small (|g| = 1e-6: η = rate / 1e-6) the threshold is
  // 3 · 2e4 / 2 and every group goes at once; --proximal-cap 0.5 shrinks each by 0.5 · rate alone.
  {
    nn::Adam<double> weak(net.store().size(), o);
    nn::Vector<double> moved = zero;
    nn::Vector<double> small = nn::Vector<double>::Constant(zero.size(), 1e-6);
    weak.step(moved, small);
    for (double cap : {0.0, 0.5}) {
      MsaeConfig capped_config = config;
      capped_config.proximal_cap = cap;
      MsaeNet<double> capped(capped_config, 9, grid_edges(), 3);
      capped.store().value(capped.blocks()[0].c) = before[0];
      capped.proximal_sparsity(lambda, weak.last_step_sizes(), {0});
      const auto C = capped.store().value(capped.blocks()[0].c);
      for (int k = 0; k < 2; ++k)
        for (int i = 0; i < 9; ++i) {
          const double was = before[0].row(k).segment(9 * i, 9).norm(),
                       now = C.row(k).segment(9 * i, 9).norm();
          INFO("cap " << cap << ", group " << k << "," << i);
          if (lambda[0](k, i) == 0)
            CHECK(now == was);
          else
            CHECK(now == Approx(cap == 0 ? 0 : was - 0.5 * 0.02).margin(1e-12));
        }
    }
  }
  // Omega is out of the gradient with proximal support (its step replaces it), and in the
  // reported total either way.
  const auto x = random_shapes(4, 9);
  MsaeConfig soft_config = config;
  soft_config.support = Support::soft;
  MsaeNet<double> soft(soft_config, 9, grid_edges(), 3);
  soft.store().values() = net.store().values();
  net.store().zero_grad();
  soft.store().zero_grad();
  const MsaeLossTerms pt = net.loss_and_gradient(x, lambda, {}, nullptr);
  const MsaeLossTerms st = soft.loss_and_gradient(x, lambda, {}, nullptr);
  CHECK(pt.total == Approx(st.total).epsilon(1e-12));
  CHECK(pt.sparsity == Approx(st.sparsity).epsilon(1e-12));
  const auto gp = net.store().grad(net.blocks()[0].c), gs = soft.store().grad(soft.blocks()[0].c);
  CHECK((gp - gs).norm() > 1e-3);
  for (const auto& b : net.blocks())  // the other parameters' gradients do not involve Omega
    CHECK((net.store().grad(b.conv.w_point) - soft.store().grad(b.conv.w_point)).norm() < 1e-12);
}

TEST_CASE("MSAE: --centre-features models deviations from a fixed offset, which gets no gradient",
          "[models][msae]") {
  MsaeConfig config = tiny({3, 2}, true);
  MsaeNet<double> plain(config, 9, grid_edges(), 6);
  config.centre_features = true;
  MsaeNet<double> centred(config, 9, grid_edges(), 6);
  const auto x = random_shapes(4, 9);
  const nn::Matrix<double> mean = random_shapes(1, 10) * 0.5;
  CHECK_THROWS(plain.set_offset(mean));
  CHECK_THROWS(centred.set_offset(random_shapes(2, 10)));
  centred.set_offset(mean);
  // The same blocks' weights (the offset is drawn last): centred(x) = mean + plain(x − mean).
  for (const auto& b : plain.blocks())
    REQUIRE(plain.store().value(b.c) == centred.store().value(b.c));
  const nn::Matrix<double> shifted = x.rowwise() - mean.row(0);
  for (int levels : {1, 2}) {
    const nn::Matrix<double> expected = plain.reconstruct(shifted, levels).rowwise() + mean.row(0);
    CHECK((centred.reconstruct(x, levels) - expected).cwiseAbs().maxCoeff() < 1e-12);
  }
  CHECK((centred.decode(0, nn::Matrix<double>::Zero(1, 3)) -
         plain.decode(0, nn::Matrix<double>::Zero(1, 3)) - mean)
            .cwiseAbs()
            .maxCoeff() < 1e-12);
  // The loss is the plain network's on the shifted shapes; the offset's gradient stays zero, so
  // an Adam step (which moves every other weight) leaves it where train-msae put it.
  const auto lambda = random_lambda(centred, 11);
  centred.store().zero_grad();
  const MsaeLossTerms c = centred.loss_and_gradient(x, lambda);
  const MsaeLossTerms p = plain.loss_and_gradient(shifted, lambda);
  CHECK(c.total == Approx(p.total).epsilon(1e-12));
  const int offset = centred.store().find("offset");
  REQUIRE(offset >= 0);
  CHECK(centred.store().grad(offset).cwiseAbs().maxCoeff() == 0);
  const nn::Matrix<double> c0_before = centred.store().value(centred.blocks()[0].c);
  nn::Adam<double> adam(centred.store().size(), nn::AdamOptions{});
  adam.step(centred.store().values(), centred.store().grads());
  CHECK(centred.store().value(centred.blocks()[0].c) != c0_before);
  CHECK(centred.store().value(offset) == mean);
}

TEST_CASE("MSAE: --attention-sharpness raises the masks' am to the power p, gradient-checked",
          "[models][msae]") {
  MsaeConfig config = tiny({3, 2}, true);
  MsaeNet<double> plain(config, 9, grid_edges(), 7);
  for (int p : {2, 4}) {
    config.attention_sharpness = p;
    MsaeNet<double> sharp(config, 9, grid_edges(), 7);
    // AM_k,i = am_k,i^p / Σ_k am_k,i^p, with am the plain masks' numerators (same weights)
    const auto am = plain.attention_masks(0);
    nn::Matrix<double> expected = am.array().square().matrix();  // am^2, then am^4 for p = 4
    if (p == 4) expected = expected.array().square().matrix();
    expected.array().rowwise() /= expected.colwise().sum().array();
    const auto got = sharp.attention_masks(0);
    CHECK((got - expected).cwiseAbs().maxCoeff() < 1e-10);
    CHECK((got.colwise().sum().array() - 1).abs().maxCoeff() < 1e-12);
    // sharper: each vertex's largest mask grows
    CHECK(got.colwise().maxCoeff().sum() > am.colwise().maxCoeff().sum());
    const auto x = random_shapes(4, 1);
    const auto r = check_loss_gradient(sharp, x, random_lambda(sharp, 2));
    INFO("p " << p << "\n" << r.report);
    REQUIRE(r.max_error <= 1e-6);
  }
  config.attention_sharpness = 3;
  CHECK_THROWS_AS(MsaeNet<double>(config, 9, grid_edges(), 7), UsageError);
}

TEST_CASE(
    "MSAE: --lambda-whole adds the whole reconstruction's MSE, gradient-checked, block by block as "
    "on one tape",
    "[models][msae]") {
  for (bool attention : {true, false}) {
    MsaeConfig config = tiny({3, 2, 2}, attention);
    MsaeNet<double> plain(config, 9, grid_edges(), 4);
    config.lambda_whole = 2.5;
    MsaeNet<double> net(config, 9, grid_edges(), 4);
    const auto x = random_shapes(5, 7);
    const auto lambda = random_lambda(net, 8);
    INFO("attention " << attention);
    // the term's value: λ_w · mean over the shapes of ‖x − Σ_b x̂_b‖² through the levels trained
    for (std::vector<int> levels : {std::vector<int>{}, std::vector<int>{1}}) {
      const int through = levels.empty() ? 3 : 2;
      const double whole = (x - net.reconstruct(x, through)).rowwise().squaredNorm().mean();
      MsaeLossTerms with, without;
      nn::Tape<double> t;
      net.loss(t, net.store().bind(t), x, lambda, &with, levels);
      plain.loss(t, plain.store().bind(t), x, lambda, &without, levels);
      CHECK(with.whole == Approx(whole).epsilon(1e-12));
      CHECK(with.total == Approx(without.total + 2.5 * whole).epsilon(1e-12));
      CHECK(with.recon == Approx(without.recon).epsilon(1e-12));
    }
    const auto r = check_loss_gradient(net, x, lambda);
    INFO(r.report);
    REQUIRE(r.max_error <= 1e-6);
    // the block-by-block gradient equals the one-tape gradient, with repeated rows weighted
    const nn::Matrix<double> w = (nn::Matrix<double>(5, 1) << 1, 3, 2, 1, 4).finished();
    for (std::vector<int> levels : {std::vector<int>{}, std::vector<int>{1}, std::vector<int>{0}}) {
      nn::Tape<double> t;
      auto p = net.store().bind(t);
      MsaeLossTerms one;
      auto l = net.loss(t, p, x, lambda, &one, levels, &w);
      t.backward(l);
      net.store().zero_grad();
      net.store().collect(p);
      const Eigen::VectorXd expected = net.store().grads();
      net.store().zero_grad();
      const MsaeLossTerms staged = net.loss_and_gradient(x, lambda, levels, &w);
      INFO("levels " << levels.size());
      CHECK(staged.total == Approx(one.total).epsilon(1e-12));
      CHECK(staged.whole == Approx(one.whole).epsilon(1e-12));
      REQUIRE((net.store().grads() - expected).cwiseAbs().maxCoeff() <=
              1e-10 * (1 + expected.cwiseAbs().maxCoeff()));
    }
  }
  MsaeConfig bad = tiny({3, 2}, true);
  bad.lambda_whole = -1;
  CHECK_THROWS_AS(MsaeNet<double>(bad, 9, grid_edges(), 7), UsageError);
}

TEST_CASE("MSAE: start_block makes a block the tied projection onto the components given",
          "[models][msae]") {
  MsaeConfig config = tiny({2, 2}, true);
  config.init = MsaeInit::local;
  MsaeNet<double> net(config, 9, grid_edges(), 5);
  // Two orthonormal components on disjoint vertices (0-2 and 6-8), as --init local gives AE0.
  Rng rng(4, 1);
  nn::Matrix<double> C = nn::Matrix<double>::Zero(2, 81);
  C.row(0).segment(0, 27) = nn::random_matrix(1, 27, rng, -1, 1);
  C.row(1).segment(54, 27) = nn::random_matrix(1, 27, rng, -1, 1);
  C.row(0).normalize();
  C.row(1).normalize();
  net.start_block(0, C);
  // Small shapes in their span come back through level 0 up to tanh's cubic term (|u|³/3 of
  // |u| ≤ 0.01, twice), and a shape outside it (vertices 3-5 only) comes back as nothing.
  const nn::Matrix<double> codes = nn::random_matrix(3, 2, rng, -0.01, 0.01);
  const nn::Matrix<double> inside = codes * C;
  CHECK((net.reconstruct(inside, 1) - inside).cwiseAbs().maxCoeff() <
        1e-4 * inside.cwiseAbs().maxCoeff());
  nn::Matrix<double> outside = nn::Matrix<double>::Zero(1, 81);
  outside.row(0).segment(27, 27) = nn::random_matrix(1, 27, rng, -0.01, 0.01);
  CHECK(net.reconstruct(outside, 1).cwiseAbs().maxCoeff() < 1e-12);
  // Level 1 keeps its initial weights, and a matrix of the wrong size is refused.
  CHECK(net.store().value(net.blocks()[1].c).cwiseAbs().maxCoeff() > 0);
  CHECK_THROWS(net.start_block(0, C.topRows(1)));
  CHECK_THROWS(net.start_block(9, C));
  CHECK_THROWS(net.start_block(0, C, 0));

  // Shapes as large as normalized features: with a linear decoder_fc, scale 1 bends them by two
  // tanh (encoder and output), scale 0.05 by the output's alone — x̂ = tanh(x) to within the
  // encoder's cubic term, (s·|u|)²/3 relative: 400 times smaller at s = 0.05 than at 1.
  config.decoder_fc = MsaeActivation::linear;
  const nn::Matrix<double> large = nn::random_matrix(3, 2, rng, -3, 3) * C;
  REQUIRE(large.cwiseAbs().maxCoeff() > 0.5);
  const nn::Matrix<double> bent = large.array().tanh().matrix();
  double off[2];
  for (double scale : {1.0, 0.05}) {
    MsaeNet<double> lin(config, 9, grid_edges(), 5);
    lin.start_block(0, C, scale);
    CHECK(lin.store()
              .value(lin.blocks()[0].conv.w_point)
              .isApprox(scale * nn::Matrix<double>::Identity(9, 9)));
    off[scale == 1.0 ? 0 : 1] = (lin.reconstruct(large, 1) - bent).cwiseAbs().maxCoeff();
  }
  INFO("off tanh(x) by " << off[0] << " at scale 1, " << off[1] << " at 0.05");
  CHECK(off[0] > 1e-2);
  CHECK(off[1] < off[0] / 200);
}
