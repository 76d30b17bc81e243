#include <catch2/catch.hpp>

#include "core/rng.h"
#include "models/baselines/baselines.h"
#include "models/common/splocs.h"
#include "nn/gradient_check.h"

using namespace df;
using namespace df::models;

TEST_CASE("SPLOCS on 9 numbers per vertex (ACAP features) finds planted local components",
          "[models][baselines]") {
  // Six vertices on a line; two planted components of 9 numbers per vertex, one around each end.
  const int V = 6, G = 9;
  nn::Matrix<double> planted = nn::Matrix<double>::Zero(2, G * V);
  Rng rng(4, 0);
  for (int j = 0; j < G; ++j) {
    planted(0, j) = rng.uniform(0.5, 1.0);                // vertex 0
    planted(0, G + j) = 0.5 * planted(0, j);              // vertex 1
    planted(1, G * 5 + j) = rng.uniform(-1.0, -0.5);      // vertex 5
    planted(1, G * 4 + j) = 0.5 * planted(1, G * 5 + j);  // vertex 4
  }
  auto shapes = [&](int n, std::uint64_t seed) {
    Rng r(seed, 1);
    nn::Matrix<double> x = nn::random_matrix(n, 2, r, 0, 1) * planted;
    x.array() += 0.3;  // a mean that is not zero
    return x;
  };
  auto distance = [&](int i) {
    Eigen::VectorXf d(V);
    for (int j = 0; j < V; ++j) d[j] = static_cast<float>(std::abs(i - j)) / (V - 1);
    return d;
  };
  SplocsOptions o;
  o.components = 2;
  o.iterations = 20;
  o.lambda = 2;
  o.d_min = 0.2;
  o.d_max = 0.5;
  const Splocs s = fit_splocs(shapes(12, 1), o, distance, G);
  REQUIRE(s.components.rows() == 2);
  REQUIRE(s.components.cols() == G * V);
  // The group shrinkage acts on a vertex's 9 numbers together: the middle vertices, fully
  // penalised from either end, carry nothing; a vertex is all zero or has no zero at all.
  for (int k = 0; k < 2; ++k) {
    const auto c = s.components.row(k);
    CHECK(c.segment(G * 2, 2 * G).norm() < 1e-9 * c.norm());
    for (int i = 0; i < V; ++i) {
      const auto g = c.segment(G * i, G);
      const auto zeros = (g.array() == 0).count();
      CHECK((zeros == 0 || zeros == G));
    }
  }
  // Unseen shapes of the same two components: least squares on them explains most of what the
  // mean leaves (weights are non-negative while fitting, as the reference code has them, so two
  // components do not span the centred data exactly).
  const nn::Matrix<double> held = shapes(5, 2);
  const nn::Matrix<double> recon = project_onto(held, s.mean, s.components);
  const double mean_only = (held.rowwise() - s.mean.row(0)).norm();
  CHECK((recon - held).norm() < 0.25 * mean_only);
  CHECK_THROWS(fit_splocs(shapes(4, 3).leftCols(G * V - 1), o, distance, G));
}
