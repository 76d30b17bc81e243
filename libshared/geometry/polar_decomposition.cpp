#include "geometry/polar_decomposition.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"

namespace df::geometry {
namespace {

PolarDecomposition via_svd(const Eigen::Matrix3d& T) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(T, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Vector3d sigma = svd.singularValues();  // descending
  if ((U * V.transpose()).determinant() < 0) {
    U.col(2) *= -1;  // flip the singular vector of the smallest singular value
    sigma[2] *= -1;  // ... and its sign in S, so that T = R S still holds
  }
  return {U * V.transpose(), V * sigma.asDiagonal() * V.transpose()};
}

}  // namespace

namespace {

// Eight matrices at a time, one per SIMD lane (AVX-512 holds eight doubles): the scaled Newton
// iteration X <- ½(γX + X⁻ᵀ/γ), γ = (‖X⁻¹‖_F / ‖X‖_F)^½ (Higham 1986), with X⁻ᵀ = cof(X) / det X
// (the cofactor matrix: cross products of X's columns). Convergence is quadratic: the error after
// a step is about the square of that step's change, so once a step changes X by less than 1e-9
// (relative; ‖X‖_F = √3 for a rotation) X is at machine precision and its lane stops. Every
// matrix goes through these same lane-wise operations, whichever batch and lane it lands in, so
// a result does not depend on how the matrices were grouped (nor on the thread count).
constexpr int kLanes = 8;
using Lane = Eigen::Array<double, kLanes, 1>;
using LaneMask = Eigen::Array<bool, kLanes, 1>;

// GCC 12 warns inside its own AVX-512 header (_mm512_sqrt_pd's undefined pass-through operand)
// when Eigen's Array sqrt is inlined here: a false positive of the intrinsic, not of this code.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
void newton_lanes(const Eigen::Matrix3d* T, int n, PolarDecomposition* out) {
  std::array<Lane, 9> x;  // x[3 r + c] = X(r, c), lane l = matrix l
  for (int l = 0; l < kLanes; ++l)
    for (int e = 0; e < 9; ++e) x[e][l] = l < n ? T[l](e / 3, e % 3) : (e % 4 == 0 ? 1.0 : 0.0);
  auto col = [&](const std::array<Lane, 9>& m, int c) {
    return std::array<Lane, 3>{m[c], m[3 + c], m[6 + c]};
  };
  auto cross = [](const std::array<Lane, 3>& a, const std::array<Lane, 3>& b) {
    return std::array<Lane, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                               a[0] * b[1] - a[1] * b[0]};
  };
  LaneMask done = LaneMask::Constant(false), fallback = LaneMask::Constant(false);
  for (int it = 0; it < 40 && !done.all(); ++it) {
    const auto c0 = col(x, 0), c1 = col(x, 1), c2 = col(x, 2);
    const auto k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);
    std::array<Lane, 9> cof;
    for (int r = 0; r < 3; ++r) {
      cof[3 * r] = k0[r];
      cof[3 * r + 1] = k1[r];
      cof[3 * r + 2] = k2[r];
    }
    const Lane det = c0[0] * k0[0] + c0[1] * k0[1] + c0[2] * k0[2];
    Lane xx = Lane::Zero(), cc = Lane::Zero();
    for (int e = 0; e < 9; ++e) {
      xx += x[e] * x[e];
      cc += cof[e] * cof[e];
    }
    const Lane gamma = (cc.sqrt() / (det * xx.sqrt())).sqrt();
    const LaneMask bad =
        !done && (!(det > 1e-300) || !det.isFinite() || !gamma.isFinite() || gamma == 0.0);
    fallback = fallback || bad;
    done = done || bad;
    const Lane a = 0.5 * gamma, b = 0.5 / (gamma * det);
    Lane change = Lane::Zero();
    for (int e = 0; e < 9; ++e) {
      const Lane next = a * x[e] + b * cof[e];
      const Lane d = next - x[e];
      change += d * d;
      x[e] = done.select(x[e], next);
    }
    done = done || change.sqrt() < 1e-9 * 1.7320508075688772;
  }
  for (int l = 0; l < n; ++l) {
    if (fallback[l]) {
      out[l] = via_svd(T[l]);
      continue;
    }
    Eigen::Matrix3d X;
    for (int e = 0; e < 9; ++e) X(e / 3, e % 3) = x[e][l];
    Eigen::Matrix3d S = X.transpose() * T[l];
    out[l] = {X, 0.5 * (S + S.transpose())};
  }
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace

void polar_decompose(std::span<const Eigen::Matrix3d> T, std::span<PolarDecomposition> out) {
  if (out.size() != T.size()) throw Error("internal: polar_decompose needs one output per matrix");
  for (std::size_t i = 0; i < T.size(); i += kLanes)
    newton_lanes(T.data() + i, static_cast<int>(std::min<std::size_t>(kLanes, T.size() - i)),
                 out.data() + i);
}

PolarDecomposition polar_decompose(const Eigen::Matrix3d& T) {
  PolarDecomposition p;
  newton_lanes(&T, 1, &p);
  return p;
}

}  // namespace df::geometry
