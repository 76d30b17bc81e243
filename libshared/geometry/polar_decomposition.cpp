#include "geometry/polar_decomposition.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

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

PolarDecomposition polar_decompose(const Eigen::Matrix3d& T) {
  double det = T.determinant();
  if (!(det > 1e-300) || !std::isfinite(det)) return via_svd(T);
  // Scaled Newton iteration X <- ½(γX + X⁻ᵀ/γ), γ = (‖X⁻¹‖_F / ‖X‖_F)^½ (Higham 1986).
  // Convergence is quadratic: once a step changes X by less than 1e-8 (relative), one more
  // unscaled step reaches machine precision.
  Eigen::Matrix3d X = T;
  bool last = false;
  for (int it = 0; it < 40; ++it) {
    Eigen::Matrix3d Xinv = X.inverse();
    double gamma = last ? 1.0 : std::sqrt(Xinv.norm() / X.norm());
    if (!std::isfinite(gamma) || gamma == 0) return via_svd(T);
    Eigen::Matrix3d next = 0.5 * (gamma * X + Xinv.transpose() / gamma);
    double change = (next - X).norm();
    X = next;
    if (last) break;
    last = change < 1e-8 * 1.7320508075688772;  // ‖X‖_F = √3 for a rotation
  }
  Eigen::Matrix3d S = X.transpose() * T;
  S = 0.5 * (S + S.transpose()).eval();
  return {X, S};
}

}  // namespace df::geometry
