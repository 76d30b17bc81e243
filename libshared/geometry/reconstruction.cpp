#include "geometry/reconstruction.h"

#include <chrono>

#include "core/error.h"
#include "geometry/acap_features.h"
#include "geometry/cotangent_weights.h"
#include "geometry/deformation_gradient.h"
#include "geometry/rotation.h"

namespace df::geometry {

Reconstructor::Reconstructor(const io::Vertices& reference, const io::Faces& faces, int anchor)
    : Reconstructor(reference, faces, anchor,
                    anchor >= 0 && anchor < reference.rows() ? Eigen::Vector3d(reference.row(anchor))
                                                             : Eigen::Vector3d::Zero()) {}

Reconstructor::Reconstructor(const io::Vertices& reference, const io::Faces& faces, int anchor,
                             const Eigen::Vector3d& anchor_position)
    : reference_(reference),
      topo_(mesh_topology(faces, static_cast<int>(reference.rows()))),
      weights_(cotangent_weights(reference, faces, topo_)),
      anchor_(anchor),
      anchor_position_(anchor_position),
      faces_(faces) {
  if (anchor < 0 || anchor >= reference.rows())
    throw InvalidInput("anchor vertex " + std::to_string(anchor) + " does not exist (the template has " +
                       std::to_string(reference.rows()) + " vertices)");
  factor();
}

Reconstructor::~Reconstructor() = default;

void Reconstructor::factor() {
  auto t0 = std::chrono::steady_clock::now();
  const int n = topo_.n_vertices;
  // One pinned vertex per connected component: the anchor, then each other component's first.
  std::vector<int>& component = component_;
  component.assign(static_cast<std::size_t>(n), -1);
  auto flood = [&](int seed) {
    std::vector<int> stack{seed};
    component[seed] = static_cast<int>(pinned_.size());
    pinned_.push_back(seed);
    while (!stack.empty()) {
      int i = stack.back();
      stack.pop_back();
      for (int k = topo_.ring_offsets[i]; k < topo_.ring_offsets[i + 1]; ++k) {
        int j = topo_.ring_vertices[k];
        if (component[j] < 0) {
          component[j] = component[seed];
          stack.push_back(j);
        }
      }
    }
  };
  flood(anchor_);
  for (int i = 0; i < n; ++i)
    if (component[i] < 0) flood(i);
  pinned_position_ = reference_;
  pinned_position_.row(anchor_) = anchor_position_.transpose();
  reduced_.assign(static_cast<std::size_t>(n), 0);
  for (int p : pinned_) reduced_[p] = -1;
  int rows = 0;
  for (int i = 0; i < n; ++i)
    if (reduced_[i] == 0) reduced_[i] = rows++;
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
  Eigen::SparseMatrix<double> L(rows, rows);
  L.setFromTriplets(trip.begin(), trip.end());
  ldlt_.compute(L);
  if (ldlt_.info() != Eigen::Success) throw InvalidInput("the reconstruction system cannot be factored");
  factor_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

io::Vertices Reconstructor::solve(const double* features, const io::Vertices* pinned_positions) const {
  const io::Vertices& pinned = pinned_positions ? *pinned_positions : pinned_position_;
  const int n = topo_.n_vertices;
  // T_i = exp(L_i) S_i
  std::vector<Eigen::Matrix3d> T(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d r;
    Eigen::Matrix3d S;
    unpack_features(features + kFeatureDims * i, r, S);
    T[i].noalias() = rotation_exp(r) * S;
  }
  io::Vertices P(n, 3);
  for (int i = 0; i < n; ++i)
    if (reduced_[i] < 0) P.row(i) = pinned.row(i);
  if (exact_) {
    // Σ_j w_ij (p'_j − p'_i) (P_i e_ij)ᵀ = T_i A_i P_i
    Eigen::MatrixXd g(3 * n, 3);  // row 3i+k, column = coordinate c: (T_i A_i P_i)(c, k)
    for (int i = 0; i < n; ++i) g.middleRows(3 * i, 3) = (T[i] * moment_[i]).transpose();
    for (const auto& t : pinned_terms_) g.row(t.row) -= t.coefficient * pinned.row(t.vertex);
    Eigen::MatrixXd y = exact_ldlt_.solve(Eigen::MatrixXd(m_free_.transpose() * g));
    for (int i = 0; i < n; ++i)
      if (reduced_[i] >= 0) P.row(i) = y.row(reduced_[i]);
    return P;
  }
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(reduced_.size() - pinned_.size()), 3);
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
  Eigen::MatrixXd x = ldlt_.solve(b);
  for (int i = 0; i < n; ++i)
    if (reduced_[i] >= 0) P.row(i) = x.row(reduced_[i]);

  return P;
}

void Reconstructor::enable_exact() {
  if (exact_) return;
  const int n = topo_.n_vertices;
  io::Vertices pseudo = pseudo_edges(reference_, faces_, topo_);
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
  Eigen::SparseMatrix<double> normal = m_free_.transpose() * m_free_;
  exact_ldlt_.compute(normal);
  if (exact_ldlt_.info() != Eigen::Success) throw InvalidInput("the exact reconstruction system cannot be factored");
  exact_ = true;
}

io::Vertices reconstruct(const io::Vertices& reference, const io::Faces& faces, const double* features, int anchor) {
  return Reconstructor(reference, faces, anchor).solve(features);
}

}  // namespace df::geometry
