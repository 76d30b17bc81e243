#include "geometry/rotation.h"

#include <cmath>

namespace df::geometry {

Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d K;
  K << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return K;
}

AxisAngle rotation_log(const Eigen::Matrix3d& R) {
  Eigen::Vector3d v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sinθ ω
  double s = 0.5 * v.norm();
  double c = 0.5 * (R.trace() - 1.0);
  double theta = std::atan2(s, c);
  AxisAngle out;
  out.angle = theta;
  if (s == 0.0 && c > 0) {  // identity
    out.axis.setZero();
    out.angle = 0.0;
    return out;
  }
  if (c >= 0) {
    out.axis = v / (2 * s);
    return out;
  }
  // θ > π/2: axis from the symmetric part, column of largest norm.
  Eigen::Matrix3d B = 0.5 * (R + R.transpose()) - c * Eigen::Matrix3d::Identity();
  int k = 0;
  B.diagonal().maxCoeff(&k);
  Eigen::Vector3d w = B.col(k);
  w.normalize();
  if (w.dot(v) < 0) w = -w;
  out.axis = w;
  return out;
}

Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& r) {
  double theta2 = r.squaredNorm();
  Eigen::Matrix3d K = skew(r);
  double a, b;  // R = I + a K + b K², a = sinθ/θ, b = (1 − cosθ)/θ²
  if (theta2 < 1e-8) {
    a = 1.0 - theta2 / 6.0 + theta2 * theta2 / 120.0;
    b = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0;
  } else {
    double theta = std::sqrt(theta2);
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * K + b * K * K;
}

}  // namespace df::geometry
