// The mesh convolution's narrow kernels against long-double references: every width and depth
// up to 16 (so every template instance), row counts around the 4-row tile, strided operands,
// = and +=, and outputs that must not write outside their rows' first n values.
#include <catch2/catch.hpp>

#include "core/rng.h"
#include "nn/gradient_check.h"
#include "nn/narrow_product.h"

using namespace df::nn;
using detail::narrow_product;
using detail::narrow_weight_gradients;
using detail::pack_narrow;
using Eigen::Index;

namespace {
template <class T>
long double max_error(const Matrix<T>& got, const Matrix<long double>& expected) {
  return (got.template cast<long double>() - expected).cwiseAbs().maxCoeff();
}

// A, B (the second term) and C are the left blocks of wider matrices (row strides k + 3,
// k + 5, n + 2), so rows are not contiguous and a kernel that writes past n is caught.
template <class T>
void check_product(double tolerance) {
  std::uint64_t seed = 1;
  for (Index k = 1; k <= detail::kNarrowMax; ++k)
    for (Index n = 1; n <= detail::kNarrowMax; ++n)
      for (Index m : {1, 4, 7})
        for (int variant = 0; variant < 16; ++variant) {  // every combination of the four options
          const bool two_terms = variant & 1, with_bias = variant & 2;
          const bool accumulate = variant & 4, transpose = variant & 8;
          INFO("k " << k << " n " << n << " m " << m << " two terms " << two_terms << " bias "
                    << with_bias << " accumulate " << accumulate << " Wᵀ " << transpose);
          const Matrix<T> a = seeded_matrix<T>(m, k + 3, ++seed),
                          b = seeded_matrix<T>(m, k + 5, ++seed);
          const Matrix<T> w =
              transpose ? seeded_matrix<T>(n, k, ++seed) : seeded_matrix<T>(k, n, ++seed);
          const Matrix<T> u = seeded_matrix<T>(k, n, ++seed), bias = seeded_matrix<T>(1, n, ++seed);
          const Matrix<T> c0 = seeded_matrix<T>(m, n + 2, ++seed);
          const auto pw = pack_narrow(w, transpose), pu = pack_narrow(u, false);
          Matrix<T> c = c0;
          narrow_product<T>(c.data(), c.cols(), m, a.data(), a.cols(), pw,
                            two_terms ? b.data() : nullptr, b.cols(), two_terms ? &pu : nullptr,
                            with_bias ? bias.data() : nullptr, accumulate);
          Matrix<long double> expected = c0.template cast<long double>();
          for (Index r = 0; r < m; ++r)
            for (Index j = 0; j < n; ++j) {
              long double sum = with_bias ? bias(0, j) : 0;
              for (Index i = 0; i < k; ++i) {
                sum += static_cast<long double>(a(r, i)) * (transpose ? w(j, i) : w(i, j));
                if (two_terms) sum += static_cast<long double>(b(r, i)) * u(i, j);
              }
              expected(r, j) = accumulate ? expected(r, j) + sum : sum;
            }
          REQUIRE(max_error(c, expected) <= tolerance * std::sqrt(static_cast<double>(2 * k + 1)));
        }
}

// G is the left block of a matrix with n + 1 columns: its rows' whole vectors reach into the
// next row (lanes that must not count) and, in the last rows, past G's end (copied instead).
template <class T>
void check_weight_gradients(double tolerance) {
  std::uint64_t seed = 100;
  for (Index k = 1; k <= detail::kNarrowMax; ++k)
    for (Index n = 1; n <= detail::kNarrowMax; ++n)
      for (Index m : {1, 3, 40})
        for (int variant = 0; variant < 8; ++variant) {  // every combination of the three options
          const bool accumulate = variant & 1, with_u = variant & 2, with_b = variant & 4;
          INFO("k " << k << " n " << n << " m " << m << " accumulate " << accumulate << " dU "
                    << with_u << " db " << with_b);
          const Matrix<T> a = seeded_matrix<T>(m, k + 2, ++seed),
                          b = seeded_matrix<T>(m, k + 1, ++seed);
          const Matrix<T> g = seeded_matrix<T>(m, n + 1, ++seed);
          const Matrix<T> dw0 = seeded_matrix<T>(k, n, ++seed),
                          du0 = seeded_matrix<T>(k, n, ++seed),
                          db0 = seeded_matrix<T>(1, n, ++seed);
          Matrix<T> dw = dw0, du = du0, db = db0;
          narrow_weight_gradients<T>(dw.data(), with_u ? du.data() : nullptr,
                                     with_b ? db.data() : nullptr, m, k, n, a.data(), a.cols(),
                                     b.data(), b.cols(), g.data(), g.cols(), accumulate);
          Matrix<long double> ew(k, n), eu(k, n), eb(1, n);
          for (Index j = 0; j < n; ++j) {
            for (Index i = 0; i < k; ++i) {
              long double sw = 0, su = 0;
              for (Index r = 0; r < m; ++r) {
                sw += static_cast<long double>(a(r, i)) * g(r, j);
                su += static_cast<long double>(b(r, i)) * g(r, j);
              }
              ew(i, j) = accumulate ? dw0(i, j) + sw : sw;
              eu(i, j) = accumulate ? du0(i, j) + su : su;
            }
            long double sb = 0;
            for (Index r = 0; r < m; ++r) sb += g(r, j);
            eb(0, j) = accumulate ? db0(0, j) + sb : sb;
          }
          const double bound = tolerance * std::sqrt(static_cast<double>(m));
          REQUIRE(max_error(dw, ew) <= bound);
          if (with_b)
            REQUIRE(max_error(db, eb) <= bound);
          else
            REQUIRE(db == db0);
          if (with_u)
            REQUIRE(max_error(du, eu) <= bound);
          else
            REQUIRE(du == du0);
        }
}
}  // namespace

TEST_CASE("nn narrow product: every width and depth against a long-double reference", "[nn]") {
  check_product<double>(1e-14);
  check_product<float>(1e-5);
}

TEST_CASE("nn narrow product: weight gradients against a long-double reference", "[nn]") {
  check_weight_gradients<double>(1e-14);
  check_weight_gradients<float>(1e-5);
}
