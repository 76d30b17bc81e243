// Polar decomposition T = R S of a 3x3 deformation gradient (SPEC §4.3): R a rotation
// (det +1), S symmetric. Equivalent to R = UVᵀ, S = VΣVᵀ from the SVD T = UΣVᵀ; when
// det T < 0 the singular vector of the smallest singular value is flipped (and its sign in S),
// so R stays a rotation. Computed by Higham's scaled Newton iteration (machine precision in a
// few steps, much cheaper than a 3x3 SVD), eight matrices at a time in SIMD lanes, with an SVD
// fallback for det T <= 0. A matrix's result is the same alone or in any batch.
#pragma once

#include <Eigen/Core>
#include <span>

namespace df::geometry {

struct PolarDecomposition {
  Eigen::Matrix3d R;  ///< rotation
  Eigen::Matrix3d S;  ///< symmetric stretch
};

PolarDecomposition polar_decompose(const Eigen::Matrix3d& T);
/// out[i] = polar_decompose(T[i]) for every i (out.size() == T.size()), bit for bit.
void polar_decompose(std::span<const Eigen::Matrix3d> T, std::span<PolarDecomposition> out);

}  // namespace df::geometry
