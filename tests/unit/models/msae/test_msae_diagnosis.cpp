#include <catch2/catch.hpp>

#include "core/error.h"
#include "helpers.h"
#include "models/msae/diagnosis.h"
#include "models/msae/network.h"
#include "nn/gradient_check.h"

using namespace df;
using namespace df::models;

namespace {

// n shapes of V vertices whose residual is a[s]·u + b[s]·w: u lives on the first half of the
// vertices, w on the second, so two regions each vary along one direction.
nn::Matrix<double> two_regions(int n, int V) {
  nn::Matrix<double> r = nn::Matrix<double>::Zero(n, 9 * V);
  for (int s = 0; s < n; ++s)
    for (int i = 0; i < V; ++i)
      for (int f = 0; f < 9; ++f) {
        const double a = (s % 3) - 1.0, b = s % 2 ? 0.7 : -0.4 * s;
        r(s, 9 * i + f) =
            i < V / 2 ? a * (1 + 0.1 * f + 0.01 * i) : b * (0.5 - 0.05 * f + 0.02 * i);
      }
  return r;
}

double left(const nn::Matrix<double>& r, const nn::Matrix<double>& approx) {
  return (r - approx).squaredNorm() / r.squaredNorm();
}

}  // namespace

TEST_CASE("MSAE diagnosis: children on disjoint masks each take their own region",
          "[models][msae]") {
  const int n = 6, V = 8;
  const auto r = two_regions(n, V);
  nn::Matrix<double> one_hot = nn::Matrix<double>::Zero(2, V);
  for (int i = 0; i < V; ++i) one_hot(i < V / 2 ? 0 : 1, i) = 1;
  // One component per child suffices: each region varies along one direction.
  CHECK(left(r, best_linear_children(r, one_hot, {1, 1})) < 1e-20);
  // One autoencoder of two components on the whole residual spans both as well.
  CHECK(left(r, best_linear_children(r, nn::Matrix<double>(), {2})) < 1e-20);
  // ... and one of one component cannot.
  CHECK(left(r, best_linear_children(r, nn::Matrix<double>(), {1})) > 0.05);
}

TEST_CASE("MSAE diagnosis: children on spread masks span little more than one of them",
          "[models][msae]") {
  const int n = 6, V = 8;
  const auto r = two_regions(n, V);
  // Uniform masks: both children are fed r/2 and their best rank-1 maps both take its top
  // direction, so their sum is the rank-1 projection of r, not a rank-2 one.
  const nn::Matrix<double> uniform = nn::Matrix<double>::Constant(2, V, 0.5);
  const double spread = left(r, best_linear_children(r, uniform, {1, 1}));
  CHECK(spread ==
        Approx(left(r, best_linear_children(r, nn::Matrix<double>(), {1}))).epsilon(1e-9));
  CHECK(spread > 0.05);
  // Partly spread masks lie between the two.
  nn::Matrix<double> soft = nn::Matrix<double>::Zero(2, V);
  for (int i = 0; i < V; ++i) soft(0, i) = i < V / 2 ? 0.8 : 0.2, soft(1, i) = 1 - soft(0, i);
  const double partly = left(r, best_linear_children(r, soft, {1, 1}));
  CHECK(partly > 1e-6);
  CHECK(partly < spread);
  // Enough components per child take everything back, however spread the masks.
  CHECK(left(r, best_linear_children(r, uniform, {2, 2})) < 1e-20);
  CHECK_THROWS_AS(best_linear_children(r, uniform, {1}), Error);
}

TEST_CASE(
    "MSAE eq. 7: a local component leaking a little everywhere is counted over the whole mesh",
    "[models][msae]") {
  // 20 of 1,000 vertices moved by 0.5: exactly local, eq. 7 is 0.5.
  std::vector<double> d(1000, 0.0);
  for (int i = 0; i < 20; ++i) d[static_cast<std::size_t>(i)] = 0.5;
  auto p = strength_parts(d, 1e-6);
  CHECK(p.counted == 20);
  CHECK(p.support == 20);
  CHECK(p.strength == Approx(0.5));
  CHECK(p.support_strength == Approx(0.5));
  // The same component with 1e-4 elsewhere (above eps1): eq. 7 averages over all 1,000 vertices
  // and falls below the pruning threshold 0.01, while the mean over its support stays 0.5.
  for (std::size_t i = 20; i < d.size(); ++i) d[i] = 1e-4;
  p = strength_parts(d, 1e-6);
  CHECK(p.counted == 1000);
  CHECK(p.support == 20);
  CHECK(p.strength == Approx((20 * 0.5 + 980 * 1e-4) / 1000));
  CHECK(p.strength < 0.011);
  CHECK(p.support_strength == Approx(0.5));
  // A noise floor above the leak counts the support again.
  CHECK(strength_parts(d, 1e-3).strength == Approx(0.5));
  CHECK(strength_parts(std::vector<double>(5, 0.0), 1e-6).strength == 0.0);
}

TEST_CASE(
    "MSAE diagnosis: the children's own errors are their losses; their sum is what the shapes are "
    "left with",
    "[models][msae]") {
  const auto edges = test::grid3x3_edges();
  Rng rng(3, 5);
  const nn::Matrix<float> x = nn::random_matrix(6, 81, rng, -0.9, 0.9).cast<float>();
  for (bool attention : {true, false}) {
    MsaeConfig c;
    c.kz = {3, 2};
    c.d = {0.3, 0.3};
    c.attention = attention;
    const MsaeNet<float> net(c, 9, edges, 4);
    const ChildrenErrors e = children_errors(net, x);
    INFO("attention " << attention);
    CHECK(e.residual ==
          Approx((x - net.reconstruct(x, 1)).cast<double>().squaredNorm()).epsilon(1e-5));
    CHECK(e.whole ==
          Approx((x - net.reconstruct(x, 2)).cast<double>().squaredNorm()).epsilon(1e-5));
    // Σ_k ‖e_k‖² / n is level 1's reconstruction term of the loss (levels {1}: its blocks only)
    std::vector<nn::Matrix<float>> lambda;
    for (const auto& b : net.blocks()) lambda.push_back(nn::Matrix<float>::Zero(b.kz, 9));
    MsaeLossTerms terms;
    nn::Tape<float> t;
    net.loss(t, net.store().bind(t), x, lambda, &terms, {1});
    CHECK(e.own / 6 == Approx(terms.recon).epsilon(1e-5));
    if (attention)
      CHECK(e.own != Approx(e.whole).epsilon(1e-3));  // three children: cross terms
    else
      CHECK(e.own == Approx(e.whole).epsilon(1e-12));  // one child on R whole: none
  }
}
