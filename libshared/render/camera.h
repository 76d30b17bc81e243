// An orthographic camera for pictures of meshes and skeletons: a view direction (azimuth and
// elevation around the world's up axis) and a fit of the 2-D extent of everything a picture
// shows, so that every panel of a sheet uses the same scale and centre and rows are comparable.
#pragma once

#include <Eigen/Core>
#include <string>

namespace df::render {

/// Where the camera looks from. View space: x right, y up, z towards the viewer.
struct View {
  double azimuth =
      0;  ///< degrees around the up axis; 0 = front (+z for y-up, −y for z-up), 90 = from +x
  double elevation = 0;  ///< degrees above the horizontal plane; 90 = from above
  char up = 'y';         ///< the world's up axis: 'y' or 'z'
};

/// "front", "side", "top", "back" or "AZ,EL" in degrees; `up` is "y" or "z". UsageError otherwise.
View parse_view(const std::string& text, const std::string& up);

class Camera {
 public:
  explicit Camera(const View& view);

  /// World to view space (rotation only), a point or direction.
  Eigen::Vector3d to_view(const Eigen::Vector3d& p) const { return rotation_ * p; }
  const Eigen::Matrix3d& rotation() const { return rotation_; }

  /// Grows the fitted 2-D extent by the view-space projection of each row of P (#P by 3).
  template <class Derived>
  void include(const Eigen::MatrixBase<Derived>& P) {
    for (Eigen::Index i = 0; i < P.rows(); ++i) include_point(P.row(i).transpose());
  }
  void include_point(const Eigen::Vector3d& p);
  bool empty() const { return !(lo_.x() <= hi_.x()); }

  /// Panel coordinates of world point p in a w by h panel, with `margin` (fraction of the
  /// smaller side) left on each side of the fitted extent: x right, y down (pixels), z = view
  /// depth (larger is nearer). The extent is centred and scaled uniformly to fit.
  Eigen::Vector3d to_panel(const Eigen::Vector3d& p, double w, double h,
                           double margin = 0.05) const;
  /// Pixels per world unit in a w by h panel.
  double scale(double w, double h, double margin = 0.05) const;

 private:
  Eigen::Matrix3d rotation_;
  Eigen::Vector2d lo_{1e300, 1e300}, hi_{-1e300, -1e300};
};

}  // namespace df::render
