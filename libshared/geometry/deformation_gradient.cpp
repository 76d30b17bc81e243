#include "geometry/deformation_gradient.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>

#include "geometry/vertex_normals.h"

namespace df::geometry {

Vertices pseudo_edges(const Vertices& V, const Faces& F, const MeshTopology& topo) {
  Vertices N = vertex_normals(V, F);
  for (int i = 0; i < topo.n_vertices; ++i) {
    double sum = 0;
    for (int k = topo.ring_offsets[i]; k < topo.ring_offsets[i + 1]; ++k)
      sum += (V.row(topo.ring_vertices[k]) - V.row(i)).norm();
    int d = topo.degree(i);
    N.row(i) *= d ? kPseudoEdgeScale * sum / d : 0.0;
  }
  return N;
}

Matrix3 one_ring_moment(const Vertices& reference, const Vertices& pseudo, const MeshTopology& topo,
                        const std::vector<double>& weights, int i) {
  Eigen::Vector3d n = pseudo.row(i);
  Matrix3 A = n * n.transpose();
  for (int k = topo.ring_offsets[i]; k < topo.ring_offsets[i + 1]; ++k) {
    Eigen::Vector3d e = reference.row(topo.ring_vertices[k]) - reference.row(i);
    A += weights[static_cast<std::size_t>(topo.ring_edges[k])] * e * e.transpose();
  }
  return A;
}

DeformationGradientSolver::DeformationGradientSolver(const Vertices& reference, const Faces& faces,
                                                     const MeshTopology& topo,
                                                     std::vector<double> weights)
    : reference_(reference), faces_(faces), topo_(topo), weights_(std::move(weights)) {
  pseudo_ = pseudo_edges(reference_, faces_, topo_);
  a_inv_.resize(static_cast<std::size_t>(topo_.n_vertices));
  tbb::parallel_for(0, topo_.n_vertices, [&](int i) {
    Matrix3 A = one_ring_moment(reference_, pseudo_, topo_, weights_, i);
    // A is symmetric positive semi-definite; invert through its eigen-decomposition so a
    // degenerate one-ring (isolated vertex, collinear neighbours without normal) still gives a
    // least-squares (pseudo-inverse) answer instead of infinities.
    Eigen::SelfAdjointEigenSolver<Matrix3> eig(A);
    Eigen::Vector3d lambda = eig.eigenvalues();
    double cutoff = 1e-12 * std::max(lambda.maxCoeff(), 0.0);
    Eigen::Vector3d inv;
    for (int k = 0; k < 3; ++k)
      inv[k] = lambda[k] > cutoff && lambda[k] > 0 ? 1.0 / lambda[k] : 0.0;
    a_inv_[static_cast<std::size_t>(i)] =
        eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
  });
}

void DeformationGradientSolver::compute(const Vertices& frame, std::vector<Matrix3>& T) const {
  Vertices pseudo = pseudo_edges(frame, faces_, topo_);
  T.resize(static_cast<std::size_t>(topo_.n_vertices));
  for (int i = 0; i < topo_.n_vertices; ++i) {
    Eigen::Vector3d n = pseudo_.row(i), nd = pseudo.row(i);
    Matrix3 B = nd * n.transpose();
    Eigen::Vector3d pi = reference_.row(i), qi = frame.row(i);
    for (int k = topo_.ring_offsets[i]; k < topo_.ring_offsets[i + 1]; ++k) {
      int j = topo_.ring_vertices[k];
      double w = weights_[static_cast<std::size_t>(topo_.ring_edges[k])];
      Eigen::Vector3d e = reference_.row(j).transpose() - pi;
      Eigen::Vector3d ed = frame.row(j).transpose() - qi;
      B.noalias() += (w * ed) * e.transpose();
    }
    T[static_cast<std::size_t>(i)].noalias() = B * a_inv_[static_cast<std::size_t>(i)];
  }
}

}  // namespace df::geometry
