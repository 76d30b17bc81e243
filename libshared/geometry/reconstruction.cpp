#include "geometry/reconstruction.h"

#include <chrono>

#include "core/error.h"
#include "geometry/acap_features.h"
#include "geometry/cotangent_weights.h"
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
      anchor_position_(anchor_position) {
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
  io::Vertices P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) = reduced_[i] >= 0 ? Eigen::RowVector3d(x.row(reduced_[i])) : Eigen::RowVector3d(pinned.row(i));
  return P;
}

io::Vertices reconstruct(const io::Vertices& reference, const io::Faces& faces, const double* features, int anchor) {
  return Reconstructor(reference, faces, anchor).solve(features);
}

}  // namespace df::geometry
