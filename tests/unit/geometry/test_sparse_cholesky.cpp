#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <vector>

#include "core/error.h"
#include "core/rng.h"
#include "geometry/sparse_cholesky.h"

using df::geometry::SparseCholesky;

namespace {
// A weighted path-and-chord graph Laplacian plus a diagonal shift: sparse, symmetric positive
// definite, with fill (the chords) — large enough for CHOLMOD to consider supernodes.
Eigen::SparseMatrix<double> test_system(int n, double shift, df::Rng& rng) {
  std::vector<Eigen::Triplet<double>> t;
  auto edge = [&](int i, int j, double w) {
    t.emplace_back(i, i, w);
    t.emplace_back(j, j, w);
    t.emplace_back(i, j, -w);
    t.emplace_back(j, i, -w);
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1, 1 + rng.uniform());
  for (int i = 0; i + 37 < n; i += 3) edge(i, i + 37, 0.5 + rng.uniform());
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, shift);
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}
}  // namespace

TEST_CASE("SparseCholesky solves an SPD system like a dense solver, from many threads alike",
          "[geometry]") {
  df::Rng rng(11);
  const int n = 600;
  const Eigen::SparseMatrix<double> a = test_system(n, 0.01, rng);
  SparseCholesky chol;
  chol.factor(a);
  REQUIRE(chol.rows() == n);
  // What the factorisation reports (acap2obj -v): the factor holds at least A's lower triangle,
  // and a dense factor's n³/3 operations bound CHOLMOD's count.
  const auto& st = chol.stats();
  CHECK(st.factor_nonzeros >=
        double(Eigen::SparseMatrix<double>(a.triangularView<Eigen::Lower>()).nonZeros()));
  CHECK(st.flops > 0);
  CHECK(st.flops <= double(n) * n * n / 3 + 10.0 * n * n);
  CHECK(st.analyse_seconds > 0);  // measured, not left at zero
  CHECK(st.factor_seconds > 0);
  CHECK(st.simplicial_seconds >= 0);  // zero work when CHOLMOD chose a simplicial factor
  Eigen::MatrixXd b(n, 3);
  for (Eigen::Index k = 0; k < b.size(); ++k) b.data()[k] = rng.normal();
  const Eigen::MatrixXd x = chol.solve(b);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(a).ldlt().solve(b);
  CHECK((x - dense).norm() <= 1e-9 * dense.norm());
  CHECK((a * x - b).norm() <= 1e-9 * b.norm());
  // Concurrent solves (acap2obj's frames in parallel) give the same bits as one.
  std::vector<Eigen::MatrixXd> many(16);
  tbb::parallel_for(0, 16, [&](int k) { many[static_cast<std::size_t>(k)] = chol.solve(b); });
  for (const auto& m : many) CHECK(m == x);
}

TEST_CASE("SparseCholesky refuses a singular system", "[geometry]") {
  df::Rng rng(12);
  SparseCholesky chol;
  // One unknown that nothing constrains (an empty row and column): a zero pivot.
  Eigen::SparseMatrix<double> a = test_system(200, 0.01, rng);
  a.conservativeResize(201, 201);
  CHECK_THROWS_AS(chol.factor(a), df::InvalidInput);
  CHECK_THROWS_AS(chol.solve(Eigen::MatrixXd::Zero(201, 1)), df::Error);
}
