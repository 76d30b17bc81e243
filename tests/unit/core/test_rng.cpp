#include <catch2/catch.hpp>
#include <cmath>

#include "core/rng.h"

TEST_CASE("Rng: streams are keyed by (seed, index) and reproducible", "[core]") {
  df::Rng a(42, 7), b(42, 7), c(42, 8), d(43, 7);
  for (int i = 0; i < 100; ++i) {
    auto x = a.next();
    CHECK(x == b.next());
    CHECK(x != c.next());
    CHECK(x != d.next());
  }
}

TEST_CASE("Rng: uniform, below and normal have the right ranges and moments", "[core]") {
  df::Rng r(1, 0);
  double sum = 0, sum2 = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    double u = r.uniform();
    REQUIRE(u >= 0.0);
    REQUIRE(u < 1.0);
    auto k = r.below(7);
    REQUIRE(k < 7);
    double z = r.normal();
    sum += z;
    sum2 += z * z;
  }
  CHECK(std::abs(sum / n) < 0.01);
  CHECK(std::abs(sum2 / n - 1.0) < 0.02);
}

TEST_CASE("Rng: state save and restore continues the same sequence", "[core]") {
  df::Rng r(5, 3);
  for (int i = 0; i < 11; ++i) r.normal();  // leaves a spare normal pending
  auto s = r.state();
  bool has = r.has_spare_normal();
  double spare = r.spare_normal();
  std::vector<double> expected;
  for (int i = 0; i < 20; ++i) expected.push_back(r.normal());
  df::Rng q;
  q.restore(s, has, spare);
  for (int i = 0; i < 20; ++i) CHECK(q.normal() == expected[static_cast<std::size_t>(i)]);
}
