#include <catch2/catch.hpp>
#include <cmath>

#include "geometry/mesh_topology.h"
#include "models/msae/network.h"
#include "nn/gradient_check.h"

using namespace df;
using namespace df::models;

namespace {

// A 3 × 3 vertex grid (8 triangles): small enough for finite differences of every weight.
std::vector<std::array<int, 2>> grid_edges() {
  io::Faces f(8, 3);
  f << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7;
  return geometry::mesh_topology(f, 9).edges;
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
    std::vector<nn::Matrix<double>> params;
    for (std::size_t i = 0; i < net.store().views().size(); ++i)
      params.push_back(net.store().value(static_cast<int>(i)));
    MsaeLossTerms terms;
    {
      nn::Tape<double> t;
      net.loss(t, net.store().bind(t), x, lambda, &terms);
    }
    auto r = nn::gradient_check(
        [&](nn::Tape<double>& t, const std::vector<nn::Var<double>>& v) {
          return net.loss(t, nn::Bound<double>{v}, x, lambda);
        },
        params);
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
