#include "geometry/vertex_normals.h"

#include <Eigen/Geometry>

namespace df::geometry {

Vertices vertex_normals(const Vertices& V, const Faces& F) {
  Vertices N = Vertices::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    Eigen::Vector3d n = (b - a).cross(c - a);
    double len = n.norm();
    if (len == 0.0) continue;
    n /= len;
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n.transpose();
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    double len = N.row(i).norm();
    if (len != 0.0) N.row(i) /= len;
  }
  return N;
}

}  // namespace df::geometry
