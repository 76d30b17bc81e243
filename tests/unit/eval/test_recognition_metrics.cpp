#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "eval/recognition_metrics.h"

using namespace df;

TEST_CASE("FID: hand-computed Gaussians", "[eval][recognition]") {
  // 1-D: A = {0, 2} (mean 1, variance 2 over n - 1), B = {1, 5} (mean 3, variance 8):
  // (1 - 3)^2 + 2 + 8 - 2 sqrt(2 * 8) = 6
  Eigen::MatrixXd A(2, 1), B(2, 1);
  A << 0, 2;
  B << 1, 5;
  CHECK(eval::frechet_distance(A, B) == Approx(6.0));
  CHECK(eval::frechet_distance(A, A) == Approx(0.0).margin(1e-12));
  // 2-D, the second set the first rotated by 90 degrees and moved by (3, 4): the covariances
  // diag(a, b) and diag(b, a) commute, so tr (S_A S_B)^(1/2) = 2 sqrt(ab) and
  // FID = 25 + 2 (a + b) - 4 sqrt(ab) = 25 + 2 (sqrt(a) - sqrt(b))^2.
  Eigen::MatrixXd P(4, 2), Q(4, 2);
  P << 1, 0, -1, 0, 0, 2, 0, -2;  // variances a = 2/3, b = 8/3 about mean 0
  for (int i = 0; i < 4; ++i) Q.row(i) << -P(i, 1) + 3, P(i, 0) + 4;
  const double a = 2.0 / 3, b = 8.0 / 3;
  CHECK(eval::frechet_distance(P, Q) == Approx(25 + 2 * std::pow(std::sqrt(a) - std::sqrt(b), 2)));
  // Covariances that do not commute: S_P = diag(2/3, 8/3) (P above, mean 0) and R's
  // S_R = [[10/3, 2/3], [2/3, 4/3]] (mean 0). For 2 x 2, tr M^(1/2) = sqrt(tr M + 2 sqrt(det M)):
  // M = S_P S_R has trace 52/9 and determinant 64/9, so tr M^(1/2) = sqrt(52/9 + 16/3) = 10/3
  // and FID = 10/3 + 14/3 - 20/3 = 4/3.
  Eigen::MatrixXd R(4, 2);
  R << 2, 1, -2, -1, 1, -1, -1, 1;
  CHECK(eval::frechet_distance(P, R) == Approx(4.0 / 3));
  CHECK(eval::frechet_distance(R, P) == Approx(4.0 / 3));
  Eigen::MatrixXd one(1, 2);
  CHECK_THROWS_AS(eval::frechet_distance(one, R), InvalidInput);
}

TEST_CASE("Diversity and multimodality: the expected distance of random pairs",
          "[eval][recognition]") {
  // Three points at distances 3, 4, 5: a uniform ordered pair (i, j), i = j allowed, has the mean
  // distance 2 (3 + 4 + 5) / 9 = 8/3.
  Eigen::MatrixXd F(3, 2);
  F << 0, 0, 3, 0, 0, 4;
  CHECK(eval::mean_pair_distance(F, {0, 1, 2}, {1, 2, 0}) == Approx(4.0));  // (3 + 5 + 4) / 3
  CHECK(eval::diversity(F, 5, 200, 200) == Approx(8.0 / 3).epsilon(0.02));
  CHECK(eval::diversity(F, 5) == eval::diversity(F, 5));  // the same draws for the same seed
  // Multimodality: within class 0 (points 0 and 1, distance 3: mean over ordered pairs 1.5),
  // class 1 (points 2 and 3, distance 10: 5); class 2 has one clip and is left out.
  Eigen::MatrixXd G(5, 2);
  G << 0, 0, 3, 0, 0, 10, 0, 20, 7, 7;
  const std::vector<int> labels{0, 0, 1, 1, 2};
  CHECK(eval::multimodality(G, labels, 3, 20, 400) == Approx((1.5 + 5) / 2).epsilon(0.03));
  CHECK(std::isnan(eval::multimodality(G, {0, 1, 2, 3, 4}, 3)));
}

TEST_CASE("Recognition metrics: accuracy, and the real clips' own row", "[eval][recognition]") {
  eval::RecognisedClips real, gen;
  real.features.resize(6, 1);
  real.features << 0, 1, 2, 3, 4, 5;
  real.labels = {0, 0, 0, 1, 1, 1};
  real.predicted = {0, 0, 1, 1, 1, 1};
  gen.features = real.features.array() + 10;
  gen.labels = {0, 0, 0, 1, 1, 1};
  gen.predicted = {1, 1, 1, 1, 1, 0};
  CHECK(eval::accuracy(real) == Approx(5.0 / 6));
  CHECK(eval::accuracy(gen) == Approx(2.0 / 6));
  const eval::RecognitionMetrics m = eval::recognition_metrics(gen, real);
  CHECK(m.features == 1);
  CHECK(m.generated.fid == Approx(100.0));  // moved by 10, same spread
  CHECK(m.generated.accuracy == Approx(2.0 / 6));
  CHECK(m.real.accuracy == Approx(5.0 / 6));
  // real halves {0, 2, 4} and {1, 3, 5}: means 2 and 3, the same variance: FID 1
  CHECK(m.real.fid == Approx(1.0));
  CHECK(m.generated.diversity == Approx(m.real.diversity));  // a shift changes no distance
  gen.predicted.pop_back();
  CHECK_THROWS(eval::recognition_metrics(gen, real));
}
