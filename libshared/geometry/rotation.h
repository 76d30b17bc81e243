// Rotation logarithm and exponential (SPEC §4.4), stable near θ = 0 and θ = π.
// log: θ = atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2) (well conditioned everywhere, unlike acos);
// the axis comes from the skew part for θ ≤ π/2 and from the symmetric part
// (R + Rᵀ)/2 − cos θ·I = (1 − cos θ) ω ωᵀ above, its sign matched to the skew part.
#pragma once

#include <Eigen/Core>

namespace df::geometry {

struct AxisAngle {
  Eigen::Vector3d axis;  ///< unit axis ω (zero when θ = 0)
  double angle = 0;      ///< θ in [0, π]
};

AxisAngle rotation_log(const Eigen::Matrix3d& R);

/// exp of the rotation vector r = θω (Rodrigues, with series for small θ).
Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& r);

/// The skew matrix [r]× (so that [r]× v = r × v).
Eigen::Matrix3d skew(const Eigen::Vector3d& r);

}  // namespace df::geometry
