// Per-vertex deformation gradients (SPEC §4.2):
//   T_i = argmin_T Σ_j w_ij ‖T(p_j − p_i) − (p'_j − p'_i)‖² + ‖T ñ_i − ñ'_i‖²
// with the pseudo-edge ñ_i = n_i · 0.3 · (mean one-ring edge length) on each mesh, so flat
// one-rings are well posed. Closed form: T_i = B_i A_i⁻¹ with
//   A_i = Σ_j w_ij e_ij e_ijᵀ + ñ_i ñ_iᵀ (reference only: inverted once here),
//   B_i = Σ_j w_ij e'_ij e_ijᵀ + ñ'_i ñ_iᵀ.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/mesh_topology.h"

namespace df::geometry {

using Matrix3 = Eigen::Matrix3d;

/// The normal pseudo-edge scale (factor of the mean one-ring edge length).
inline constexpr double kPseudoEdgeScale = 0.3;

/// Pseudo-edges ñ_i of a mesh: #V by 3.
Vertices pseudo_edges(const Vertices& V, const Faces& F, const MeshTopology& topo);

/// The reference one-ring moment A_i = Σ_j w_ij e_ij e_ijᵀ + ñ_i ñ_iᵀ of vertex i.
/// @param pseudo  the reference's pseudo-edges (#V by 3)
Matrix3 one_ring_moment(const Vertices& reference, const Vertices& pseudo, const MeshTopology& topo,
                        const std::vector<double>& weights, int i);

/// Holds the reference side; compute() is const and thread-safe (one frame per thread).
class DeformationGradientSolver {
 public:
  /// @param reference  #V by 3 reference positions
  /// @param weights    w_ij per edge of topo (cotangent_weights)
  DeformationGradientSolver(const Vertices& reference, const Faces& faces, const MeshTopology& topo,
                            std::vector<double> weights);

  /// T_i of every vertex of `frame` (#V by 3, same connectivity); T is resized to #V.
  void compute(const Vertices& frame, std::vector<Matrix3>& T) const;

  const MeshTopology& topology() const { return topo_; }
  const std::vector<double>& weights() const { return weights_; }
  const Vertices& reference() const { return reference_; }
  const Faces& faces() const { return faces_; }

 private:
  Vertices reference_;
  Faces faces_;
  const MeshTopology& topo_;
  std::vector<double> weights_;
  Vertices pseudo_;             // ñ_i of the reference
  std::vector<Matrix3> a_inv_;  // A_i⁻¹ (pseudo-inverse where singular)
};

}  // namespace df::geometry
