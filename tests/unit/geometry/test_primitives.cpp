#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/cotangent_weights.h"
#include "geometry/mesh_topology.h"
#include "geometry/polar_decomposition.h"
#include "geometry/rotation.h"
#include "geometry/vertex_normals.h"
#include "helpers.h"

using namespace df::geometry;
using df::Faces;
using df::Vertices;

namespace {
Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}
}  // namespace

TEST_CASE("mesh_topology: edges and sorted one-rings of a tetrahedron", "[geometry]") {
  auto m = df::test::tetrahedron();
  auto t = mesh_topology(m.faces, 4);
  CHECK(t.edges.size() == 6);
  for (int i = 0; i < 4; ++i) CHECK(t.degree(i) == 3);
  CHECK(std::vector<int>(t.ring_vertices.begin(), t.ring_vertices.begin() + 3) ==
        std::vector<int>{1, 2, 3});
  for (std::size_t k = 0; k < t.ring_vertices.size(); ++k) {
    auto e = t.edges[static_cast<std::size_t>(t.ring_edges[k])];
    CHECK((e[0] == t.ring_vertices[k] || e[1] == t.ring_vertices[k]));
  }
}

TEST_CASE("cotangent_weights: equilateral, boundary, obtuse and degenerate cases", "[geometry]") {
  // Two equilateral triangles sharing edge (0,1): interior c = ½(cot60 + cot60) = 1/√3.
  Vertices V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0, 0.5, -std::sqrt(3.0) / 2, 0;
  Faces F(2, 3);
  F << 0, 1, 2, 1, 0, 3;
  auto t = mesh_topology(F, 4);
  auto c = cotangent_sums(V, F, t);
  auto w = cotangent_weights(V, F, t);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    bool interior = t.edges[e] == std::array<int, 2>{0, 1};
    double expected = interior ? 1 / std::sqrt(3.0) : 0.5 / std::sqrt(3.0);  // boundary: one term
    CHECK(c[e] == Approx(expected));
    CHECK(w[e] == Approx(std::sqrt(1 + expected)));  // sexp(x) = 1 + x for x > 0
  }
  // Obtuse angle opposite an edge: negative cotangent, still a positive weight e^(c/2).
  CHECK(positive_weight(-2.0) == Approx(std::exp(-1.0)));
  CHECK(positive_weight(0.0) == Approx(1.0));
  CHECK(positive_weight(std::nan("")) == 1.0);
  CHECK(positive_weight(1e11) == 1.0);
  // A zero-area triangle gives infinite/NaN cotangents: weight 1.
  Vertices D(3, 3);
  D << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  Faces G(1, 3);
  G << 0, 1, 2;
  auto td = mesh_topology(G, 3);
  for (double x : cotangent_weights(D, G, td)) CHECK(x == 1.0);
}

TEST_CASE("vertex_normals: unit, outward on a closed mesh", "[geometry]") {
  auto m = df::test::tetrahedron();
  Vertices N = vertex_normals(m.vertices, m.faces);
  Eigen::RowVector3d centre = m.vertices.colwise().mean();
  for (int i = 0; i < 4; ++i) {
    CHECK(N.row(i).norm() == Approx(1.0));
    CHECK(N.row(i).dot(m.vertices.row(i) - centre) > 0);
  }
}

TEST_CASE("polar_decompose: T = RS with R a rotation and S symmetric, also for det T < 0",
          "[geometry]") {
  std::mt19937 rng(0);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3d T;
    for (int k = 0; k < 9; ++k) T(k / 3, k % 3) = u(rng);
    if (trial % 4 == 0) T = random_rotation(rng) * (Eigen::Matrix3d::Identity() + 0.1 * T);
    PolarDecomposition p = polar_decompose(T);
    CHECK((p.R * p.S - T).norm() < 1e-12 * (1 + T.norm()));
    CHECK((p.R.transpose() * p.R - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK(p.R.determinant() == Approx(1.0));
    CHECK((p.S - p.S.transpose()).norm() < 1e-12);
  }
  // A reflection: the smallest singular direction flips, R stays a rotation.
  Eigen::Matrix3d M = Eigen::Vector3d(2, 1.5, -0.5).asDiagonal();
  PolarDecomposition p = polar_decompose(M);
  CHECK(p.R.isApprox(Eigen::Matrix3d::Identity()));
  CHECK(p.S.isApprox(M));
}

TEST_CASE(
    "polar_decompose: a batch gives each matrix's result alone, bit for bit, whatever its lane",
    "[geometry]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Matrix3d> T(21);  // two full batches of eight and a partial one
  for (std::size_t i = 0; i < T.size(); ++i) {
    for (int k = 0; k < 9; ++k) T[i](k / 3, k % 3) = u(rng);
    if (i % 3 == 0) T[i] = random_rotation(rng) * (Eigen::Matrix3d::Identity() + 0.05 * T[i]);
  }
  T[5] = Eigen::Vector3d(2, 1.5, -0.5).asDiagonal();  // det < 0: the SVD fallback inside a batch
  T[9].setZero();                                     // singular: the fallback too
  for (std::size_t offset : {std::size_t{0}, std::size_t{3}}) {  // each matrix in another lane
    std::span<const Eigen::Matrix3d> in(T.data() + offset, T.size() - offset);
    std::vector<PolarDecomposition> out(in.size());
    polar_decompose(in, out);
    for (std::size_t i = 0; i < in.size(); ++i) {
      const PolarDecomposition alone = polar_decompose(in[i]);
      CHECK(out[i].R == alone.R);
      CHECK(out[i].S == alone.S);
      CHECK((out[i].R * out[i].S - in[i]).norm() < 1e-12 * (1 + in[i].norm()));
    }
  }
  std::vector<PolarDecomposition> too_few(2);
  CHECK_THROWS(polar_decompose(std::span<const Eigen::Matrix3d>(T), too_few));
}

TEST_CASE("rotation_log / rotation_exp: round trip, near 0 and near pi", "[geometry]") {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix3d R = random_rotation(rng);
    AxisAngle a = rotation_log(R);
    CHECK(a.angle >= 0);
    CHECK(a.angle <= std::numbers::pi);
    CHECK((rotation_exp(a.axis * a.angle) - R).norm() < 1e-12);
  }
  Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  for (double theta : {0.0, 1e-12, 1e-7, 1e-3, std::numbers::pi / 2, std::numbers::pi - 1e-3,
                       std::numbers::pi - 1e-9, std::numbers::pi}) {
    Eigen::Matrix3d R = Eigen::AngleAxisd(theta, axis).toRotationMatrix();
    AxisAngle a = rotation_log(R);
    CHECK(a.angle == Approx(theta).margin(1e-12));
    if (theta > 1e-6 && theta < std::numbers::pi - 1e-6) CHECK((a.axis - axis).norm() < 1e-9);
    if (theta == std::numbers::pi)
      CHECK(std::abs(std::abs(a.axis.dot(axis)) - 1) < 1e-12);  // ±ω both right
    CHECK((rotation_exp(a.axis * a.angle) - R).norm() < 1e-12);
  }
  CHECK(skew(Eigen::Vector3d(1, 2, 3)) * Eigen::Vector3d(4, 5, 6) ==
        Eigen::Vector3d(1, 2, 3).cross(Eigen::Vector3d(4, 5, 6)));
}
