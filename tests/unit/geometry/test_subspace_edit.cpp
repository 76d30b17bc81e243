// Editing in a subspace of ACAP deformations (geometry/subspace_edit): its derivatives against
// finite differences, a shape inside the span recovered from a few handles, handles held.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <random>

#include "geometry/acap_features.h"
#include "geometry/subspace_edit.h"
#include "synth/meshseq.h"

using namespace df::geometry;
using df::Vertices;

namespace {
df::Mesh finger(int resolution) {
  df::synth::MeshSeqParams p;
  p.resolution = resolution;
  p.frames = 1;
  return df::synth::MeshSequenceGenerator(p).rest();
}

// Features [9V] with the same rotation vector r and stretch S at every vertex.
std::vector<double> uniform(int V, const Eigen::Vector3d& r, const Eigen::Matrix3d& S) {
  std::vector<double> f(static_cast<std::size_t>(V) * kFeatureDims);
  pack_features(std::vector<Eigen::Vector3d>(static_cast<std::size_t>(V), r),
                std::vector<Eigen::Matrix3d>(static_cast<std::size_t>(V), S), f.data());
  return f;
}

Eigen::MatrixXd rows_of(const std::vector<std::vector<double>>& d) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(d.size()), static_cast<Eigen::Index>(d[0].size()));
  for (std::size_t k = 0; k < d.size(); ++k)
    m.row(static_cast<Eigen::Index>(k)) =
        Eigen::Map<const Eigen::RowVectorXd>(d[k].data(), m.cols());
  return m;
}

// Random per-vertex rotation vectors and symmetric stretch changes: local, non-affine directions.
Eigen::MatrixXd random_directions(int K, int V, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<std::vector<double>> d;
  for (int k = 0; k < K; ++k) {
    std::vector<Eigen::Vector3d> r(static_cast<std::size_t>(V));
    std::vector<Eigen::Matrix3d> S(static_cast<std::size_t>(V));
    for (int i = 0; i < V; ++i) {
      r[i] = {u(rng), u(rng), u(rng)};
      Eigen::Matrix3d a;
      for (int x = 0; x < 9; ++x) a(x / 3, x % 3) = u(rng);
      S[i] = 0.5 * (a + a.transpose());
    }
    d.emplace_back(static_cast<std::size_t>(V) * kFeatureDims);
    pack_features(r, S, d.back().data());
  }
  return rows_of(d);
}
}  // namespace

TEST_CASE("subspace edit: dT/dw and the energy's gradient match finite differences", "[geometry]") {
  const auto m = finger(6);
  const int V = static_cast<int>(m.vertices.rows());
  std::mt19937 rng(5);
  const Eigen::MatrixXd D = random_directions(4, V, rng);
  const std::vector<int> handles{0, V / 2, V - 1};
  SubspaceEditor ed(m.vertices, m.faces, handles, D,
                    uniform(V, {0.2, -0.1, 0.4}, Eigen::Matrix3d::Identity()));
  Vertices pinned = m.vertices;
  pinned.row(V - 1) += Eigen::RowVector3d(0.3, 0.1, -0.2);
  const Eigen::Vector4d w(0.7, -0.4, 0.3, 1.1);
  const double h = 1e-6;
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd a = w, b = w;
    a[k] += h, b[k] -= h;
    for (int i : {1, V / 3, V - 2}) {
      const Eigen::Matrix3d fd = (ed.transform(a, i) - ed.transform(b, i)) / (2 * h);
      CHECK((ed.transform_derivative(w, i, k) - fd).cwiseAbs().maxCoeff() < 1e-7);
    }
  }
  SubspaceEditOptions reg;
  reg.l2 = 0.01;
  reg.l1 = 0.02;  // the sparsity term's gradient checked too
  const auto e = ed.energy(w, pinned, reg, SubspaceEditor::EnergyParts::gauss_newton);
  CHECK(e.fit > 0.01);  // far from the handles' shape: the fit term dominates the gradient
  const Eigen::VectorXd sparse = 0.02 * (w.array() / (w.array().square() + 1e-6).sqrt()).matrix();
  CHECK((e.gradient - 2 * 0.01 * w - sparse).cwiseAbs().minCoeff() > 0.005);
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd a = w, b = w;
    a[k] += h, b[k] -= h;
    const double fd = (ed.energy(a, pinned, reg, SubspaceEditor::EnergyParts::value).value -
                       ed.energy(b, pinned, reg, SubspaceEditor::EnergyParts::value).value) /
                      (2 * h);
    CHECK(e.gradient[k] == Approx(fd).epsilon(1e-6).margin(1e-9));
  }
  // The Gauss-Newton matrix is symmetric and positive semi-definite, λ added on its diagonal.
  CHECK((e.gauss_newton - e.gauss_newton.transpose()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(e.gauss_newton).eigenvalues().minCoeff() >=
        2 * 0.01 - 1e-9);
  // μ: the sparsity term's share of the energy
  SubspaceEditOptions none;
  none.l2 = 0.01;
  const double l1 = e.value - ed.energy(w, pinned, none, SubspaceEditor::EnergyParts::value).value;
  CHECK(l1 == Approx(0.02 * ((w.array().square() + 1e-6).sqrt() - 1e-3).sum()));
}

TEST_CASE("subspace edit: a shape inside the span is recovered from a few handles", "[geometry]") {
  const auto m = finger(8);
  const int V = static_cast<int>(m.vertices.rows());
  const Eigen::Matrix3d Z = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d sx = Z, sy = Z;
  sx(0, 0) = 1, sy(1, 1) = 1;
  // Global rotations about x and z, stretches along x and y: every shape in the span is an
  // affine image of the reference, which the edge system represents exactly.
  const Eigen::MatrixXd D = rows_of({uniform(V, {1, 0, 0}, Z), uniform(V, {0, 0, 1}, Z),
                                     uniform(V, {0, 0, 0}, sx), uniform(V, {0, 0, 0}, sy)});
  const Eigen::Vector4d truth(0.6, -0.9, 0.25, -0.15);
  const Eigen::Matrix3d A = rotation_exp(Eigen::Vector3d(0.6, 0, -0.9)) *
                            Eigen::DiagonalMatrix<double, 3>(1.25, 0.85, 1).toDenseMatrix();
  const Vertices shape = (m.vertices * A.transpose()).rowwise() + Eigen::RowVector3d(0.5, -1, 2);
  const std::vector<int> handles{0, V / 5, V / 2, (3 * V) / 4, V - 1};
  Vertices pinned = m.vertices;
  for (int v : handles) pinned.row(v) = shape.row(v);
  SubspaceEditor ed(m.vertices, m.faces, handles, D,
                    uniform(V, {0, 0, 0}, Eigen::Matrix3d::Identity()));
  SubspaceEditOptions opt;
  opt.l2 = 0;
  const auto r = ed.edit(Eigen::VectorXd::Zero(4), pinned, opt);
  CHECK(r.converged);
  CHECK(r.iterations < 30);
  const double diagonal =
      (m.vertices.colwise().maxCoeff() - m.vertices.colwise().minCoeff()).norm();
  CHECK((r.positions - shape).rowwise().norm().maxCoeff() < 1e-6 * diagonal);
  CHECK((r.weights - truth).cwiseAbs().maxCoeff() < 1e-6);
  for (int v : handles) CHECK((r.positions.row(v) - shape.row(v)).norm() == 0.0);  // held exactly
  CHECK(r.energy.back() < 1e-20);
  // At the solution the residual is zero, so the Gauss-Newton matrix is the Hessian: the
  // gradient's finite differences give it.
  const auto at = ed.energy(truth, pinned, opt, SubspaceEditor::EnergyParts::gauss_newton);
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd a = truth, b = truth;
    a[k] += 1e-6, b[k] -= 1e-6;
    const Eigen::VectorXd fd =
        (ed.energy(a, pinned, opt, SubspaceEditor::EnergyParts::gradient).gradient -
         ed.energy(b, pinned, opt, SubspaceEditor::EnergyParts::gradient).gradient) /
        2e-6;
    CHECK((fd - at.gauss_newton.col(k)).cwiseAbs().maxCoeff() <
          1e-6 * (1 + at.gauss_newton.cwiseAbs().maxCoeff()));
  }
  for (std::size_t i = 1; i < r.energy.size(); ++i) CHECK(r.energy[i] < r.energy[i - 1]);
  for (std::size_t i = 1; i < r.energy.size(); ++i)
    CHECK(r.energy[i] <= r.energy[i - 1] * (1 - opt.tolerance));

  // A shape outside the span (its handles moved off the affine image): the minimum is above zero,
  // and the steps near it gain less than the tolerance; none of them is taken, so the step count
  // does not depend on rounding.
  Vertices off = pinned;
  for (std::size_t h = 0; h < handles.size(); ++h)
    off(handles[h], 2) += 0.05 * (h % 2 ? 1.0 : -1.0);
  const auto o = ed.edit(Eigen::VectorXd::Zero(4), off, opt);
  CHECK(o.converged);
  CHECK(o.energy.back() > 1e-8);
  for (std::size_t i = 1; i < o.energy.size(); ++i)
    CHECK(o.energy[i] <= o.energy[i - 1] * (1 - opt.tolerance));
}

TEST_CASE("subspace edit: handles out of range or a span of another size are refused",
          "[geometry]") {
  const auto m = finger(4);
  const int V = static_cast<int>(m.vertices.rows());
  const auto base = uniform(V, {0, 0, 0}, Eigen::Matrix3d::Identity());
  const Eigen::MatrixXd D = Eigen::MatrixXd::Zero(2, 9 * V);
  CHECK_THROWS_WITH(SubspaceEditor(m.vertices, m.faces, {V}, D, base),
                    Catch::Contains("does not exist"));
  CHECK_THROWS_WITH(
      SubspaceEditor(m.vertices, m.faces, {0}, Eigen::MatrixXd::Zero(2, 9 * V - 1), base),
      Catch::Contains("9 numbers per template vertex"));
}
