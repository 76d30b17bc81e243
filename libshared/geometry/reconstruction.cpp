#include "geometry/reconstruction.h"

#include <chrono>

#include "core/error.h"
#include "geometry/acap_features.h"
#include "geometry/cotangent_weights.h"
#include "geometry/deformation_gradient.h"
#include "geometry/rotation.h"

namespace df::geometry {

Reconstructor::Reconstructor(const Vertices& reference, const Faces& faces, int anchor,
                             ReconstructionSolver solver)
    : reference_(reference),
      faces_(faces),
      topo_(mesh_topology(faces, static_cast<int>(reference.rows()))),
      weights_(cotangent_weights(reference, faces, topo_)),
      solver_(solver) {
  if (anchor < 0 || anchor >= reference.rows())
    throw InvalidInput("anchor vertex " + std::to_string(anchor) +
                       " does not exist (the template has " + std::to_string(reference.rows()) +
                       " vertices)");
  pin_components(anchor);
  factor();
}

Reconstructor::Reconstructor(const Vertices& reference, const Faces& faces,
                             const std::vector<int>& pinned)
    : reference_(reference),
      faces_(faces),
      topo_(mesh_topology(faces, static_cast<int>(reference.rows()))),
      weights_(cotangent_weights(reference, faces, topo_)),
      solver_(ReconstructionSolver::edges) {
  for (int v : pinned)
    if (v < 0 || v >= reference.rows())
      throw InvalidInput("vertex " + std::to_string(v) + " does not exist (the template has " +
                         std::to_string(reference.rows()) + " vertices)");
  pin_vertices(pinned);
  factor();
}

void Reconstructor::factor() {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const Eigen::SparseMatrix<double> system =
      solver_ == ReconstructionSolver::edges ? edge_system() : gradient_system();
  assemble_seconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
  cholesky_.factor(system);
  factor_seconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
}

Reconstructor::~Reconstructor() = default;

void Reconstructor::pin_components(int anchor) {
  const int n = topo_.n_vertices;
  // One pinned vertex per connected component: the anchor, then each other component's first.
  int count = 0;
  component_ = connected_components(topo_, anchor, &count);
  n_components_ = count;
  pinned_.assign(static_cast<std::size_t>(count), -1);
  pinned_[0] = anchor;
  for (int i = 0; i < n; ++i)
    if (pinned_[static_cast<std::size_t>(component_[static_cast<std::size_t>(i)])] < 0)
      pinned_[static_cast<std::size_t>(component_[static_cast<std::size_t>(i)])] = i;
  number_free();
}

void Reconstructor::number_free() {
  reduced_.assign(static_cast<std::size_t>(topo_.n_vertices), 0);
  for (int p : pinned_) reduced_[p] = -1;
  int rows = 0;
  for (auto& r : reduced_)
    if (r == 0) r = rows++;
}

void Reconstructor::pin_vertices(const std::vector<int>& pinned) {
  const int n = topo_.n_vertices;
  int count = 0;
  component_ = connected_components(topo_, 0, &count);
  n_components_ = count;
  std::vector<char> held(static_cast<std::size_t>(count), 0),
      is_pinned(static_cast<std::size_t>(n), 0);
  for (int v : pinned) {
    if (!is_pinned[v]) pinned_.push_back(v);
    is_pinned[v] = 1;
    held[static_cast<std::size_t>(component_[v])] = 1;
  }
  for (int i = 0; i < n; ++i)
    if (!held[static_cast<std::size_t>(component_[i])]) {
      held[static_cast<std::size_t>(component_[i])] = 1;
      pinned_.push_back(i);
    }
  number_free();
}

// The weighted graph Laplacian over the free vertices.
Eigen::SparseMatrix<double> Reconstructor::edge_system() const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(topo_.edges.size() * 4);
  for (std::size_t e = 0; e < topo_.edges.size(); ++e) {
    auto [i, j] = topo_.edges[e];
    double w = weights_[e];
    int ri = reduced_[i], rj = reduced_[j];
    if (ri >= 0) trip.emplace_back(ri, ri, w);
    if (rj >= 0) trip.emplace_back(rj, rj, w);
    if (ri >= 0 && rj >= 0) {
      trip.emplace_back(ri, rj, -w);
      trip.emplace_back(rj, ri, -w);
    }
  }
  const int free = topo_.n_vertices - static_cast<int>(pinned_.size());
  Eigen::SparseMatrix<double> L(free, free);
  L.setFromTriplets(trip.begin(), trip.end());
  return L;
}

// MᵀM of the projected deformation-gradient equations; keeps M, A_i P_i and the pinned terms.
Eigen::SparseMatrix<double> Reconstructor::gradient_system() {
  const int n = topo_.n_vertices;
  Vertices pseudo = pseudo_edges(reference_, faces_, topo_);
  moment_.resize(static_cast<std::size_t>(n));
  std::vector<Eigen::Triplet<double>> trip;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d nhat = pseudo.row(i);
    if (nhat.norm() > 0) nhat.normalize();
    const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - nhat * nhat.transpose();
    moment_[i] = one_ring_moment(reference_, pseudo, topo_, weights_, i) * proj;
    for (int k = topo_.ring_offsets[i]; k < topo_.ring_offsets[i + 1]; ++k) {
      int j = topo_.ring_vertices[k];
      double w = weights_[static_cast<std::size_t>(topo_.ring_edges[k])];
      Eigen::Vector3d e = proj * (reference_.row(j) - reference_.row(i)).transpose();
      for (int c = 0; c < 3; ++c) {
        int row = 3 * i + c;
        for (auto [v, coef] : {std::pair{j, w * e[c]}, std::pair{i, -w * e[c]}}) {
          if (reduced_[v] >= 0)
            trip.emplace_back(row, reduced_[v], coef);
          else
            pinned_terms_.push_back({row, v, coef});
        }
      }
    }
  }
  m_free_.resize(3 * n, n - static_cast<int>(pinned_.size()));
  m_free_.setFromTriplets(trip.begin(), trip.end());
  return m_free_.transpose() * m_free_;
}

Vertices Reconstructor::solve(const double* features, const Vertices* pinned_positions) const {
  const Vertices& pinned = pinned_positions ? *pinned_positions : reference_;
  const int n = topo_.n_vertices;
  // T_i = exp(L_i) S_i
  std::vector<Eigen::Matrix3d> T(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d r;
    Eigen::Matrix3d S;
    unpack_features(features + kFeatureDims * i, r, S);
    T[i].noalias() = rotation_exp(r) * S;
  }
  Eigen::MatrixXd x;
  if (solver_ == ReconstructionSolver::gradients) {
    // Σ_j w_ij (p'_j − p'_i) (P_i e_ij)ᵀ = T_i A_i P_i
    Eigen::MatrixXd g(3 * n, 3);  // row 3i+k, column = coordinate c: (T_i A_i P_i)(c, k)
    for (int i = 0; i < n; ++i) g.middleRows(3 * i, 3) = (T[i] * moment_[i]).transpose();
    for (const auto& t : pinned_terms_) g.row(t.row) -= t.coefficient * pinned.row(t.vertex);
    x = cholesky_.solve(Eigen::MatrixXd(m_free_.transpose() * g));
  } else {
    Eigen::MatrixXd b =
        Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(reduced_.size() - pinned_.size()), 3);
    for (std::size_t e = 0; e < topo_.edges.size(); ++e) {
      auto [i, j] = topo_.edges[e];
      Eigen::Vector3d pij = reference_.row(i) - reference_.row(j);
      Eigen::Vector3d d = weights_[e] * 0.5 * ((T[i] + T[j]) * pij);  // w_ij d_ij
      int ri = reduced_[i], rj = reduced_[j];
      if (ri >= 0) b.row(ri) += d.transpose();
      if (rj >= 0) b.row(rj) -= d.transpose();
      // A pinned vertex's known position moves to the right-hand side: L_ip p_p = −w p_p.
      if (ri < 0 && rj >= 0) b.row(rj) += weights_[e] * pinned.row(i);
      if (rj < 0 && ri >= 0) b.row(ri) += weights_[e] * pinned.row(j);
    }
    x = cholesky_.solve(b);
  }
  Vertices P(n, 3);
  for (int i = 0; i < n; ++i)
    P.row(i) = reduced_[i] >= 0 ? Eigen::RowVector3d(x.row(reduced_[i]))
                                : Eigen::RowVector3d(pinned.row(i));
  return P;
}

}  // namespace df::geometry
