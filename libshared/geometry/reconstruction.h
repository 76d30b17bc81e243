// Positions from ACAP features (SPEC §4, reconstruction): rebuild T_i = exp(L_i) S_i and solve
//   min_p' Σ_(i,j)∈E w_ij ‖(p'_i − p'_j) − ½(T_i + T_j)(p_i − p_j)‖²
// with one anchor vertex pinned per connected component (the chosen anchor for its component,
// the lowest-index vertex of every other component; all at their reference positions, since
// the features carry no translation). The normal equations L p' = b have the weighted graph
// Laplacian L of the template, which Reconstructor factors once (sparse LDLᵀ); every frame is
// then two triangular solves, and frames may be solved in parallel.
//
// Exact mode (enable_exact): the SPEC's system has a residual wherever a one-ring does not
// deform affinely, so even features computed from a real mesh do not give that mesh back.
// The features fix every T_i = B_i A_i⁻¹, so the original mesh satisfies
//   Σ_j w_ij (p'_j − p'_i) e_ijᵀ + ñ'_i ñ_iᵀ = T_i A_i     (A_i: reference one-ring moment)
// exactly. Multiplying on the right by P_i = I − n̂_i n̂_iᵀ (n̂_i: the reference pseudo-edge's
// direction) removes the unknown ñ'_i:
//   Σ_j w_ij (p'_j − p'_i) (P_i e_ij)ᵀ = T_i A_i P_i,
// linear in p', separate per coordinate: a sparse 3V×V least-squares system whose normal
// matrix depends only on the template (factored once), one solve per frame. Features of a real
// mesh give that mesh back (to rounding); other (e.g. generated) features get the positions
// whose deformation gradients fit them best in this sense.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <memory>
#include <vector>

#include "geometry/mesh_topology.h"

namespace df::geometry {

class Reconstructor {
 public:
  /// @param reference  #V by 3 reference positions; @param faces  #F by 3
  /// @param anchor     pinned vertex; its position is `anchor_position` (default: reference)
  Reconstructor(const io::Vertices& reference, const io::Faces& faces, int anchor = 0);
  Reconstructor(const io::Vertices& reference, const io::Faces& faces, int anchor,
                const Eigen::Vector3d& anchor_position);
  ~Reconstructor();

  /// Positions (#V by 3) from one frame's raw features (#V rows of 9, row-major). Pinned
  /// vertices take their positions from `pinned_positions` (#V by 3, e.g. the original frame)
  /// when given, else from the reference (and the anchor position). Thread-safe.
  io::Vertices solve(const double* features, const io::Vertices* pinned_positions = nullptr) const;

  /// Solve the exact (deformation-gradient) system instead of the SPEC's (see above).
  void enable_exact();
  bool exact() const { return exact_; }

  int n_vertices() const { return topo_.n_vertices; }
  /// Number of connected components (= pinned vertices).
  int components() const { return static_cast<int>(pinned_.size()); }
  /// Connected component of each vertex (0 = the anchor's).
  const std::vector<int>& component_of() const { return component_; }
  double factor_seconds() const { return factor_seconds_; }

 private:
  void factor();

  io::Vertices reference_;
  MeshTopology topo_;
  std::vector<double> weights_;
  int anchor_;
  Eigen::Vector3d anchor_position_;
  std::vector<int> pinned_;   // one vertex per connected component
  std::vector<int> component_;
  std::vector<int> reduced_;  // vertex -> row of the reduced system (−1 for a pinned vertex)
  io::Vertices pinned_position_;  // #V by 3, meaningful for pinned vertices
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  double factor_seconds_ = 0;

  // exact mode
  io::Faces faces_;
  bool exact_ = false;
  std::vector<Eigen::Matrix3d> moment_;  // A_i P_i
  Eigen::SparseMatrix<double> m_free_;  // rows 3i+k, columns = free vertices
  struct PinnedTerm {
    int row, vertex;
    double coefficient;
  };
  std::vector<PinnedTerm> pinned_terms_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> exact_ldlt_;
};

/// One-off reconstruction of a frame (factors, solves once).
io::Vertices reconstruct(const io::Vertices& reference, const io::Faces& faces, const double* features,
                         int anchor = 0);

}  // namespace df::geometry
