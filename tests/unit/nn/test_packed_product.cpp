#include <tbb/global_control.h>

#include <catch2/catch.hpp>

#include "core/rng.h"
#include "nn/gradient_check.h"
#include "nn/packed_product.h"

using namespace df::nn;
using detail::pack_rhs;
using detail::packed_product;
using Eigen::Index;

namespace {
// C0 + A · op(W) summed in long double, one element at a time.
template <class T>
Matrix<long double> reference(const Matrix<T>& c0, const Matrix<T>& a, const Matrix<T>& w,
                              bool transpose) {
  Matrix<long double> c = c0.template cast<long double>();
  for (Index i = 0; i < c.rows(); ++i)
    for (Index j = 0; j < c.cols(); ++j)
      for (Index k = 0; k < a.cols(); ++k)
        c(i, j) += static_cast<long double>(a(i, k)) * (transpose ? w(j, k) : w(k, j));
  return c;
}

// Every shape, op(W) and A layout against the reference: rows around the register tile's
// height, columns around the panel's width, K from 1.
template <class T>
void check_against_reference(double tolerance) {
  std::uint64_t seed = 1;
  for (Index m : {1, 5, 12, 13, 25, 32})
    for (Index k : {1, 7, 64})
      for (Index n : {1, 17, 33, 69})
        for (bool transpose : {false, true})
          for (bool a_transposed : {false, true})
            for (bool accumulate : {false, true}) {
              INFO("m " << m << " k " << k << " n " << n << " Wᵀ " << transpose << " Aᵀ "
                        << a_transposed << " accumulate " << accumulate);
              const Matrix<T> w =
                  transpose ? seeded_matrix<T>(n, k, ++seed) : seeded_matrix<T>(k, n, ++seed);
              const Matrix<T> a = seeded_matrix<T>(m, k, ++seed), at = a.transpose();
              const Matrix<T> c0 = seeded_matrix<T>(m, n, ++seed);
              const auto packed = pack_rhs(w, transpose);
              REQUIRE(packed.k == k);
              REQUIRE(packed.n == n);
              Matrix<T> c = c0;
              if (a_transposed)
                packed_product<T>(c, at.transpose(), packed, accumulate);
              else
                packed_product<T>(c, a, packed, accumulate);
              const Matrix<long double> expected =
                  reference<T>(accumulate ? c0 : Matrix<T>::Zero(m, n), a, w, transpose);
              const long double error =
                  (c.template cast<long double>() - expected).cwiseAbs().maxCoeff();
              CHECK(static_cast<double>(error) <= tolerance * std::sqrt(static_cast<double>(k)));
            }
}

// Long K: the panel is walked in chunks (2,048 of its rows at a time), the running sums carried
// between them; and K = 0.
template <class T>
void check_long_and_empty_k(double tolerance) {
  std::uint64_t seed = 500;
  for (Index m : {1, 13, 16})
    for (Index k : {0, 2048, 2049, 5000})
      for (bool transpose : {false, true})
        for (bool accumulate : {false, true}) {
          INFO("m " << m << " k " << k << " Wᵀ " << transpose << " accumulate " << accumulate);
          const Index n = 33;
          const Matrix<T> w =
              transpose ? seeded_matrix<T>(n, k, ++seed) : seeded_matrix<T>(k, n, ++seed);
          const Matrix<T> a = seeded_matrix<T>(m, k, ++seed), c0 = seeded_matrix<T>(m, n, ++seed);
          Matrix<T> c = c0;
          packed_product<T>(c, a, pack_rhs(w, transpose), accumulate);
          const Matrix<long double> expected =
              reference<T>(accumulate ? c0 : Matrix<T>::Zero(m, n), a, w, transpose);
          const long double error =
              (c.template cast<long double>() - expected).cwiseAbs().maxCoeff();
          CHECK(static_cast<double>(error) <=
                tolerance * std::sqrt(static_cast<double>(std::max<Index>(k, 1))));
        }
}
}  // namespace

TEST_CASE("nn packed product: a long K walked in chunks, and K = 0", "[nn]") {
  check_long_and_empty_k<double>(1e-14);
  check_long_and_empty_k<float>(1e-5);
}

TEST_CASE("nn packed product: A · W and A · Wᵀ against a long-double reference, every remainder",
          "[nn]") {
  check_against_reference<double>(1e-13);
  check_against_reference<float>(1e-5);
}

TEST_CASE("nn packed product: writes only its block of a larger matrix (middle rows, strided A)",
          "[nn]") {
  const Matrix<double> w = seeded_matrix<double>(20, 40, 1),
                       big_a = seeded_matrix<double>(30, 20, 2);
  Matrix<double> big_c = seeded_matrix<double>(30, 40, 3);
  const Matrix<double> before = big_c;
  packed_product<double>(big_c.middleRows(7, 13), big_a.middleRows(3, 13), pack_rhs(w, false),
                         true);
  CHECK(big_c.topRows(7) == before.topRows(7));
  CHECK(big_c.bottomRows(10) == before.bottomRows(10));
  const Matrix<double> expected = before.middleRows(7, 13) + big_a.middleRows(3, 13) * w;
  CHECK((big_c.middleRows(7, 13) - expected).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("nn packed product: results do not depend on the thread count", "[nn]") {
  const Matrix<float> a = seeded_matrix<float>(300, 257, 4), w = seeded_matrix<float>(257, 130, 5);
  const auto packed = pack_rhs(w, false);
  auto run = [&](int threads) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism,
                          static_cast<std::size_t>(threads));
    Matrix<float> out(300, 130);
    packed_product<float>(out, a, packed, false);
    return out;
  };
  CHECK(run(1) == run(2));
}
