#include "render/camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace df::render {

View parse_view(const std::string& text, const std::string& up) {
  View v;
  if (up != "y" && up != "z") throw UsageError("--up must be y or z, not '" + up + "'");
  v.up = up[0];
  if (text == "front") return v;
  if (text == "side") return v.azimuth = 90, v;
  if (text == "back") return v.azimuth = 180, v;
  if (text == "top") return v.elevation = 90, v;
  const auto comma = text.find(',');
  try {
    if (comma != std::string::npos) {
      std::size_t n1 = 0, n2 = 0;
      v.azimuth = std::stod(text.substr(0, comma), &n1);
      v.elevation = std::stod(text.substr(comma + 1), &n2);
      if (n1 == comma && n2 == text.size() - comma - 1 && std::abs(v.elevation) <= 90 &&
          std::isfinite(v.azimuth))
        return v;
    }
  } catch (const std::exception&) {
  }
  throw UsageError(
      "bad --view '" + text +
      "' (front, side, top, back, or AZIMUTH,ELEVATION in degrees with |elevation| <= 90)");
}

Camera::Camera(const View& view) {
  const double a = view.azimuth * std::numbers::pi / 180,
               e = view.elevation * std::numbers::pi / 180;
  // In y-up coordinates: the direction towards the camera d, screen right x, screen up y = d × x.
  const Eigen::Vector3d d(std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e));
  const Eigen::Vector3d x(std::cos(a), 0, -std::sin(a));
  const Eigen::Vector3d y = d.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = d.transpose();
  Eigen::Matrix3d to_y_up = Eigen::Matrix3d::Identity();
  if (view.up == 'z')
    to_y_up << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // (x, y, z) -> (x, z, −y): front looks from −y
  rotation_ = R * to_y_up;
}

void Camera::include_point(const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = rotation_ * p;
  lo_ = lo_.cwiseMin(v.head<2>());
  hi_ = hi_.cwiseMax(v.head<2>());
}

double Camera::scale(double w, double h, double margin) const {
  if (empty()) return 1;
  const double m = margin * std::min(w, h);
  const Eigen::Vector2d extent = hi_ - lo_;
  double s = 1e300;
  if (extent.x() > 0) s = std::min(s, (w - 2 * m) / extent.x());
  if (extent.y() > 0) s = std::min(s, (h - 2 * m) / extent.y());
  return s < 1e300 ? s : 1;  // a single point: any scale
}

Eigen::Vector3d Camera::to_panel(const Eigen::Vector3d& p, double w, double h,
                                 double margin) const {
  const Eigen::Vector3d v = rotation_ * p;
  const double s = scale(w, h, margin);
  const Eigen::Vector2d c = empty() ? Eigen::Vector2d::Zero() : Eigen::Vector2d((lo_ + hi_) / 2);
  return {w / 2 + s * (v.x() - c.x()), h / 2 - s * (v.y() - c.y()), v.z()};
}

}  // namespace df::render
