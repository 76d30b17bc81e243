#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/acap_consistency.h"
#include "geometry/acap_features.h"
#include "geometry/reconstruction.h"
#include "synth/meshseq.h"

using namespace df::geometry;
using df::Vertices;

namespace {
df::Mesh finger_rest(int resolution = 12) {
  df::synth::MeshSeqParams p;
  p.resolution = resolution;
  p.frames = 1;
  return df::synth::MeshSequenceGenerator(p).rest();
}

std::vector<double> features_of(const AcapFeatureExtractor& ex, const Vertices& frame) {
  FrameDecomposition d;
  ex.decompose(frame, d);
  std::vector<Eigen::Vector3d> r;
  ex.make_consistent(d, nullptr, r);
  std::vector<double> f(r.size() * kFeatureDims);
  pack_features(r, d.stretch, f.data());
  return f;
}
}  // namespace

TEST_CASE("ACAP features: identity frame gives r = 0 and s = identity", "[geometry]") {
  auto m = finger_rest();
  AcapFeatureExtractor ex(m.vertices, m.faces);
  auto f = features_of(ex, m.vertices);
  const double id[9] = {0, 0, 0, 1, 0, 0, 1, 0, 1};
  for (std::size_t k = 0; k < f.size(); ++k) REQUIRE(f[k] == Approx(id[k % 9]).margin(1e-12));
}

TEST_CASE("ACAP features: rigid rotation gives s = identity and r = the rotation", "[geometry]") {
  auto m = finger_rest();
  AcapFeatureExtractor ex(m.vertices, m.faces);
  Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const double theta = 2.0;
  Eigen::Matrix3d R = Eigen::AngleAxisd(theta, axis).toRotationMatrix();
  Vertices rotated = (m.vertices * R.transpose()).rowwise() + Eigen::RowVector3d(5, -2, 1);
  auto f = features_of(ex, rotated);
  // L = θ[ω]x: L01 = −θω_z, L02 = θω_y, L12 = −θω_x.
  const double expected[9] = {
      -theta * axis.z(), theta * axis.y(), -theta * axis.x(), 1, 0, 0, 1, 0, 1};
  for (std::size_t k = 0; k < f.size(); ++k) REQUIRE(f[k] == Approx(expected[k % 9]).margin(1e-9));
}

TEST_CASE("ACAP features: uniform scaling gives s = scale * identity", "[geometry]") {
  auto m = finger_rest();
  AcapFeatureExtractor ex(m.vertices, m.faces);
  auto f = features_of(ex, 1.7 * m.vertices);
  const double expected[9] = {0, 0, 0, 1.7, 0, 0, 1.7, 0, 1.7};
  for (std::size_t k = 0; k < f.size(); ++k) REQUIRE(f[k] == Approx(expected[k % 9]).margin(1e-9));
}

TEST_CASE("ACAP features: a known bend reproduces its rotation angles", "[geometry]") {
  // The finger bent by 90 deg with constant curvature: the cross-section at arc length s is
  // rotated about +y by (π/2)(s/L). Check the middle rings, away from the caps.
  df::synth::MeshSeqParams p;
  p.resolution = 24;
  p.frames = 20;
  p.periods = 1;
  p.twist_degrees = 0;
  df::synth::MeshSequenceGenerator g(p);
  AcapFeatureExtractor ex(g.rest().vertices, g.rest().faces);
  auto f = features_of(ex, g.frame(10));
  const int seg = 24, rings = 96;
  for (int ring = 24; ring <= 72; ring += 8) {
    double expected = std::numbers::pi / 2 * ring / rings;
    for (int k = 0; k < seg; k += 5) {
      const double* v = f.data() + 9 * (ring * seg + k);
      Eigen::Vector3d r(-v[2], v[1], -v[0]);
      CHECK(r.y() == Approx(expected).epsilon(0.02));
      CHECK(std::hypot(r.x(), r.z()) < 0.02);
    }
  }
}

TEST_CASE(
    "ACAP consistency: a bending finger twisting past 180 deg stays continuous in space and time",
    "[geometry]") {
  // (Past 360 deg, a twisted tube's per-vertex rotations R_z(τ)·R_radial(shear) approach the
  // shear rotation alone, about radial axes that differ around the ring: every rotation-vector
  // lift must then jump by ~2π·(angle between neighbouring radial axes). See the README.)
  df::synth::MeshSeqParams p;
  p.resolution = 12;
  p.frames = 41;
  p.periods = 0.5;  // the twist grows monotonically to 300 deg at the last frame
  p.twist_degrees = 300;
  p.amplitude = 0.3;
  df::synth::MeshSequenceGenerator g(p);
  AcapFeatureExtractor ex(g.rest().vertices, g.rest().faces);
  const auto& topo = ex.topology();
  std::vector<Eigen::Vector3d> prev, r, prev_naive;
  double max_space = 0, max_time = 0, naive_space = 0, naive_time = 0;
  for (int t = 0; t < p.frames; ++t) {
    FrameDecomposition d;
    ex.decompose(g.frame(t), d);
    auto rep = ex.make_consistent(d, t ? &prev : nullptr, r);
    CHECK(rep.axis_after >= rep.axis_before);
    CHECK(rep.angle_after <= rep.angle_before + 1e-9);
    auto naive = principal_rotation_vectors(d);
    for (const auto& [i, j] : topo.edges) {
      max_space = std::max(max_space, (r[i] - r[j]).norm());
      naive_space = std::max(naive_space, (naive[i] - naive[j]).norm());
    }
    if (t)
      for (std::size_t i = 0; i < r.size(); ++i) {
        max_time = std::max(max_time, (r[i] - prev[i]).norm());
        naive_time = std::max(naive_time, (naive[i] - prev_naive[i]).norm());
      }
    prev = r;
    prev_naive = naive;
  }
  // The tip ring is twisted by 300 deg = 5.24 rad at the last frame: |r| keeps growing past π.
  const int tip = 12 * 48 + 3;
  CHECK(prev[tip].norm() == Approx(300 * std::numbers::pi / 180).epsilon(0.03));
  CHECK(max_space < 1.6);    // neighbours (measured 1.36: shear-tilted axes times |r| ≈ 5)
  CHECK(max_time < 0.3);     // frames: ≤ 7.5 deg twist steps (measured 0.22)
  CHECK(naive_space > 4.0);  // a per-vertex log jumps by ~2π where the twist passes 180 deg
  CHECK(naive_time > 4.0);
}

TEST_CASE("ACAP consistency: never worse than its initialisation, deterministic", "[geometry]") {
  // A noisy rotation field on a grid: random axes near a common one, angles near π.
  df::synth::MeshSeqParams p;
  p.kind = df::synth::MeshSeqKind::bumps;
  p.resolution = 20;
  p.frames = 1;
  df::synth::MeshSequenceGenerator g(p);
  auto topo = mesh_topology(g.rest().faces, static_cast<int>(g.rest().vertices.rows()));
  AcapConsistency solver(topo);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0, 0.6);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<AxisAngle> rot(static_cast<std::size_t>(topo.n_vertices));
    for (auto& a : rot) {
      Eigen::Vector3d w = Eigen::Vector3d(0, 0, 1) + Eigen::Vector3d(n(rng), n(rng), n(rng));
      double theta = std::clamp(2.8 + n(rng), 0.0, std::numbers::pi);
      Eigen::Matrix3d R = rotation_exp(w.normalized() * theta);
      a = rotation_log(R);
    }
    std::vector<Eigen::Vector3d> r1, r2;
    auto rep = solver.solve(rot, nullptr, r1);
    CHECK(rep.axis_after >= rep.axis_before);
    CHECK(rep.angle_after <= rep.angle_before);
    solver.solve(rot, nullptr, r2);
    CHECK(r1 == r2);
    // Every r_i is a valid representation of its rotation.
    for (std::size_t i = 0; i < rot.size(); ++i)
      REQUIRE((rotation_exp(r1[i]) - rotation_exp(rot[i].axis * rot[i].angle)).norm() < 1e-9);
  }
}

TEST_CASE("Normalization: group and per-dim ranges, widened, invertible", "[geometry]") {
  std::vector<double> f = {-1,  0.5, 0.2, 1, 0,   0,    1,   0, 1,     // vertex 0
                           0.3, -2,  0.1, 2, 0.1, -0.3, 0.9, 0, 1.2};  // vertex 1
  NormalizationBuilder gb(df::NormalizationMode::group), pb(df::NormalizationMode::per_dim);
  gb.add(f.data(), 2);
  pb.add(f.data(), 2);
  Normalization g = gb.finish(), d = pb.finish();
  for (int k = 0; k < 3; ++k) {
    CHECK(g.min[k] == Approx(-2 - 1e-6));
    CHECK(g.max[k] == Approx(0.5 + 1e-6));
  }
  for (int k = 3; k < 9; ++k) {
    CHECK(g.min[k] == Approx(-0.3 - 1e-6));
    CHECK(g.max[k] == Approx(2 + 1e-6));
  }
  CHECK(d.min[0] == Approx(-1 - 1e-6));
  CHECK(d.max[0] == Approx(0.3 + 1e-6));
  for (std::size_t k = 0; k < f.size(); ++k) {
    int dim = static_cast<int>(k % 9);
    for (const auto* n : {&g, &d}) {
      double y = n->normalize(dim, f[k]);
      CHECK(std::abs(y) < 0.95);
      CHECK(n->denormalize(dim, y) == Approx(f[k]).margin(1e-12));
    }
  }
}

TEST_CASE("Reconstructor: identity and rigid motions are reproduced exactly", "[geometry]") {
  auto m = finger_rest(10);
  AcapFeatureExtractor ex(m.vertices, m.faces);
  Reconstructor rec(m.vertices, m.faces);
  auto P = rec.solve(features_of(ex, m.vertices).data());
  CHECK((P - m.vertices).cwiseAbs().maxCoeff() < 1e-10);
  Eigen::Matrix3d R =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  Vertices moved = (m.vertices * R.transpose() * 1.3).rowwise() + Eigen::RowVector3d(1, 2, 3);
  auto Q = rec.solve(features_of(ex, moved).data());
  Eigen::RowVector3d shift = moved.row(0) - Q.row(0);
  CHECK(((Q.rowwise() + shift) - moved).cwiseAbs().maxCoeff() < 1e-9);
  // Pinned to the frame's own positions, no shift is needed.
  auto S = rec.solve(features_of(ex, moved).data(), &moved);
  CHECK((S - moved).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("Reconstructor: one pinned vertex per connected component", "[geometry]") {
  auto a = finger_rest(6);
  const auto na = a.vertices.rows();
  df::Mesh two;  // two fingers side by side: two components
  two.vertices.resize(2 * na, 3);
  two.vertices << a.vertices, a.vertices.rowwise() + Eigen::RowVector3d(3, 0, 0);
  two.faces.resize(2 * a.faces.rows(), 3);
  two.faces << a.faces, a.faces.array() + static_cast<int>(na);
  Reconstructor rec(two.vertices, two.faces, 5);
  CHECK(rec.components() == 2);
  AcapFeatureExtractor ex(two.vertices, two.faces);
  auto P = rec.solve(features_of(ex, 0.5 * two.vertices).data());
  CHECK(P.allFinite());
  CHECK((P.row(5) - two.vertices.row(5)).norm() == 0.0);  // the anchor stays put
  CHECK((P.row(0) - P.row(1)).norm() ==
        Approx(0.5 * (two.vertices.row(0) - two.vertices.row(1)).norm()));
  CHECK_THROWS_WITH(Reconstructor(two.vertices, two.faces, 100000),
                    Catch::Contains("does not exist"));
}

TEST_CASE("Reconstructor: the gradient system reproduces a non-affine deformation exactly",
          "[geometry]") {
  // The bumps surface: localized, strongly non-affine deformations of a grid.
  df::synth::MeshSeqParams p;
  p.kind = df::synth::MeshSeqKind::bumps;
  p.resolution = 24;
  p.frames = 4;
  p.amplitude = 3;
  df::synth::MeshSequenceGenerator g(p);
  const auto& m = g.rest();
  AcapFeatureExtractor ex(m.vertices, m.faces);
  Reconstructor edges(m.vertices, m.faces),
      grads(m.vertices, m.faces, 0, ReconstructionSolver::gradients);
  CHECK(grads.solver() == ReconstructionSolver::gradients);
  const double diag = (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm();
  for (int t = 1; t < 4; ++t) {
    Vertices frame = g.frame(t);
    frame =
        (frame * Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()).toRotationMatrix().transpose())
            .eval();
    auto f = features_of(ex, frame);
    auto align = [&](const Vertices& P) {
      Eigen::RowVector3d shift = frame.row(0) - P.row(0);
      return ((P.rowwise() + shift) - frame).rowwise().norm().maxCoeff() / diag;
    };
    double e_grad = align(grads.solve(f.data())), e_edge = align(edges.solve(f.data()));
    CHECK(e_grad < 1e-10);
    CHECK(e_edge > 1e-4);  // the SPEC/paper edge system is only approximate here
  }
}
