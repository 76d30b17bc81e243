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

TEST_CASE("mesh_parts, align_parts, erms_share: the one E_rms every tool measures", "[eval]") {
  // Two triangles that share no vertex, and a lone vertex no face touches: three parts.
  Faces faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  const eval::MeshParts parts = eval::mesh_parts(faces, 7);
  REQUIRE(parts.count == 3);
  CHECK(parts.of_vertex[0] == parts.of_vertex[2]);
  CHECK(parts.of_vertex[3] == parts.of_vertex[5]);
  CHECK(parts.of_vertex[0] != parts.of_vertex[3]);
  CHECK(parts.of_vertex[6] != parts.of_vertex[0]);
  CHECK(parts.of_vertex[6] != parts.of_vertex[3]);
  const eval::MeshParts whole = eval::mesh_parts(Faces(0, 3), 7);  // no faces: one part
  CHECK(whole.count == 1);
  CHECK(whole.of_vertex == std::vector<int>(7, 0));

  Vertices truth(7, 3);
  truth << 0, 0, 0, 1, 0, 0, 0, 1, 0, 3, 0, 0, 4, 0, 0, 3, 1, 0, 0, 0, 2;
  // Each part moved by its own translation: aligned away, E_rms 0; as one part it is not.
  Vertices moved = truth;
  moved.topRows(3).rowwise() += Eigen::RowVector3d(1, 2, 3);
  moved.middleRows(3, 3).rowwise() += Eigen::RowVector3d(-4, 0, 1);
  moved.row(6) += Eigen::RowVector3d(0, 5, 0);
  CHECK(eval::erms_share(moved, truth, parts) == Approx(0).margin(1e-20));
  CHECK(eval::erms_share(moved, truth, whole) > 1);
  CHECK((eval::align_parts(moved, truth, parts, eval::Alignment::rigid) - truth).norm() < 1e-12);
  // Vertex 1 off by 0.6 in z: after its part's translation the part's three vertices are off by
  // -0.2, 0.4 and -0.2 in z (squares 0.24 in all), scaled by truth's unit ball (radius
  // max |v - centroid| over the 7 vertices).
  Vertices off = truth;
  off(1, 2) += 0.6;
  const Eigen::RowVector3d c = truth.colwise().mean();
  const double r = (truth.rowwise() - c).rowwise().norm().maxCoeff();
  CHECK(eval::erms_share(off, truth, parts) == Approx((0.04 + 0.16 + 0.04) / (r * r)));
  CHECK(eval::erms_from_sum(eval::erms_share(off, truth, parts), 1, 7) ==
        Approx(1000 * std::sqrt(0.24 / (r * r) / 21)));
}
