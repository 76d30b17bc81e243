// Positions from ACAP features (SPEC §4, reconstruction): rebuild T_i = exp(L_i) S_i and solve
//   min_p' Σ_(i,j)∈E w_ij ‖(p'_i − p'_j) − ½(T_i + T_j)(p_i − p_j)‖²
// with one anchor vertex pinned per connected component (the chosen anchor for its component,
// the lowest-index vertex of every other component; all at their reference positions, since
// the features carry no translation). The normal equations L p' = b have the weighted graph
// Laplacian L of the template, which Reconstructor factors once (sparse Cholesky,
// geometry/sparse_cholesky); every frame is then two triangular solves, and frames may be solved in
// parallel.
//
// ReconstructionSolver::gradients: the SPEC's system has a residual wherever a one-ring does not
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
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "geometry/mesh_topology.h"
#include "geometry/sparse_cholesky.h"

namespace df::geometry {

/// Which system Reconstructor solves (see above).
enum class ReconstructionSolver {
  edges,     ///< the SPEC/papers' edge system
  gradients  ///< the exact deformation-gradient system
};

class Reconstructor {
 public:
  /// Factors the chosen system once.
  /// @param reference  #V by 3 reference positions; @param faces  #F by 3
  /// @param anchor     pinned vertex of its component (at its reference position)
  Reconstructor(const Vertices& reference, const Faces& faces, int anchor = 0,
                ReconstructionSolver solver = ReconstructionSolver::edges);
  /// Pins the given vertices (e.g. an edit's handles, at the positions solve() is given) and
  /// the lowest-index vertex of every connected component that holds none of them. Only the edge
  /// system; InvalidInput for a vertex out of range.
  Reconstructor(const Vertices& reference, const Faces& faces, const std::vector<int>& pinned);
  ~Reconstructor();

  /// Positions (#V by 3) from one frame's raw features (#V rows of 9, row-major). Pinned
  /// vertices take their positions from `pinned_positions` (#V by 3, e.g. the original frame)
  /// when given, else from the reference. Thread-safe.
  Vertices solve(const double* features, const Vertices* pinned_positions = nullptr) const;

  ReconstructionSolver solver() const { return solver_; }
  int n_vertices() const { return topo_.n_vertices; }
  /// Number of connected components (= pinned vertices with an anchor).
  int components() const { return n_components_; }
  /// Connected component of each vertex (0 = the anchor's, or vertex 0's).
  const std::vector<int>& component_of() const { return component_; }
  double factor_seconds() const { return factor_seconds_; }
  /// Of factor_seconds(): the system's assembly, and what the factorisation itself did.
  double assemble_seconds() const { return assemble_seconds_; }
  const SparseCholesky::Stats& factor_stats() const { return cholesky_.stats(); }

  // The edge system's parts, for solvers built on it (geometry/subspace_edit):
  const MeshTopology& topology() const { return topo_; }
  const std::vector<double>& edge_weights() const { return weights_; }  ///< w_ij per edge
  /// The unknown of each vertex in the reduced system, −1 for a pinned one.
  const std::vector<int>& reduced_index() const { return reduced_; }
  /// L⁻¹ b for right-hand sides over the free vertices (rows: reduced_index()).
  Eigen::MatrixXd solve_reduced(const Eigen::MatrixXd& b) const { return cholesky_.solve(b); }

 private:
  void pin_components(int anchor);
  void pin_vertices(const std::vector<int>& pinned);
  void number_free();
  void factor();
  Eigen::SparseMatrix<double> edge_system() const;
  Eigen::SparseMatrix<double> gradient_system();

  Vertices reference_;
  Faces faces_;
  MeshTopology topo_;
  std::vector<double> weights_;
  ReconstructionSolver solver_;
  std::vector<int> pinned_;     // one vertex per connected component
  std::vector<int> component_;  // component of each vertex
  int n_components_ = 0;
  std::vector<int> reduced_;  // vertex -> unknown of the reduced system (−1 for a pinned vertex)
  SparseCholesky cholesky_;
  double factor_seconds_ = 0, assemble_seconds_ = 0;

  // gradient system: rows 3i+k of M (columns = free vertices), A_i P_i, pinned columns of M
  std::vector<Eigen::Matrix3d> moment_;
  Eigen::SparseMatrix<double> m_free_;
  struct PinnedTerm {
    int row, vertex;
    double coefficient;
  };
  std::vector<PinnedTerm> pinned_terms_;
};

}  // namespace df::geometry
