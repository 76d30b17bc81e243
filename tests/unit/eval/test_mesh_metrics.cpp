#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "core/rng.h"
#include "eval/mesh_metrics.h"

using namespace df;

TEST_CASE(
    "align_rigid: undoes a rotation and translation per connected part; translation-only does not",
    "[eval]") {
  Rng rng(3, 0);
  Vertices truth(40, 3);
  for (Eigen::Index v = 0; v < truth.rows(); ++v)
    for (int k = 0; k < 3; ++k) truth(v, k) = rng.uniform(-1, 1);
  std::vector<int> part(40);
  for (int v = 0; v < 40; ++v) part[static_cast<std::size_t>(v)] = v < 25 ? 0 : 1;
  // Part 0 turned by 30° about one axis, part 1 by 70° about another, both moved.
  const Eigen::Matrix3d r0 =
      Eigen::AngleAxisd(0.52, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d r1 =
      Eigen::AngleAxisd(1.22, Eigen::Vector3d(-1, 0, 1).normalized()).toRotationMatrix();
  Vertices pred(40, 3);
  for (Eigen::Index v = 0; v < 40; ++v)
    pred.row(v) =
        v < 25 ? Eigen::RowVector3d(truth.row(v) * r0.transpose() + Eigen::RowVector3d(0.3, -2, 1))
               : Eigen::RowVector3d(truth.row(v) * r1.transpose() + Eigen::RowVector3d(5, 0, 0));
  CHECK((eval::align_rigid(pred, truth, part, 2) - truth).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(eval::unit_ball_squared_error(eval::align_translation(pred, truth, part, 2), truth) > 1);
  // A reflection is not a rotation: a mirrored copy is not aligned onto the original.
  Vertices mirrored = truth;
  mirrored.col(0) *= -1;
  std::vector<int> one(40, 0);
  CHECK((eval::align_rigid(mirrored, truth, one, 1) - truth).norm() > 0.1);
  // Already aligned: unchanged.
  CHECK((eval::align_rigid(truth, truth, one, 1) - truth).cwiseAbs().maxCoeff() < 1e-12);
}
