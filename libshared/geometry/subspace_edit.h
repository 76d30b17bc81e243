// Shape editing in a subspace of ACAP deformations (data-driven deformation, Gao et al., as the
// MSAE paper's §5 uses it): K deformation directions D_k (raw ACAP features, per vertex a rotation
// vector ρ_ik and a stretch change ΔS_ik) span the shapes
//   T_i(w) = exp(ρ_i(w)) S_i(w),  ρ_i(w) = ρ⁰_i + Σ_k w_k ρ_ik,  S_i(w) = S⁰_i + Σ_k w_k ΔS_ik
// about a base (f⁰: the reference, or a shape edited before). A few handle vertices are held at
// their targets; the other positions and the weights minimise
//   E(w, p) = Σ_(i,j)∈E c_ij ‖(p_i − p_j) − ½(T_i + T_j)(q_i − q_j)‖² / Σ c_ij ‖q_i − q_j‖² + λ‖w‖²
//             (+ an optional sparsity term, SubspaceEditOptions::l1)
// (the edge system acap2obj solves, q the reference, c the cotangent weights). For fixed w the
// positions are one solve with the Laplacian factored once per handle set (geometry::Reconstructor
// with the handles pinned); the weights are found by Levenberg-Marquardt on the energy with p
// eliminated (p = p*(w)), whose Gauss-Newton matrix needs dT_i/dw_k — the rotation's through the
// right Jacobian of SO(3), dexp(ρ)[δ] = exp(ρ)[J_r(ρ) δ]× — and K more solves with the same
// factor; the gradient comes from the adjoint (cheap), the matrix is kept while steps succeed.
// Its fixed points are those of alternating the two steps, reached in a few iterations.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "geometry/reconstruction.h"

namespace df::geometry {

struct SubspaceEditOptions {
  double l2 = 1e-4;  ///< λ
  /// μ of a sparsity term μ Σ_k (√(w_k² + ε²) − ε), ε = 1e-3 (a smooth |w_k|: the ACAP paper's
  /// data-driven deformation favours few active components); 0 = none
  double l1 = 0;
  int max_iterations = 100;  ///< Levenberg-Marquardt steps
  double tolerance = 1e-7;   ///< stop when a step lowers E by less than this (relative)
};

struct SubspaceEditResult {
  Eigen::VectorXd weights;       ///< [K]
  Vertices positions;            ///< [V, 3]
  std::vector<double> features;  ///< [V * 9] raw ACAP features of the edited shape
  std::vector<double> energy;    ///< E at the start and after each accepted step
  int iterations = 0;
  bool converged = false;
};

/// E and, when asked, its gradient and Gauss-Newton matrix at w (for the solver and its tests).
struct SubspaceEnergy {
  double value = 0, fit = 0;  ///< E, and its first term alone
  Eigen::VectorXd gradient;
  Eigen::MatrixXd gauss_newton;
  Vertices positions;
};

class SubspaceEditor {
 public:
  /// Factors the system with `handles` pinned (every connected component without a handle gets
  /// its lowest vertex pinned too). @param directions  [K, 9V] raw feature directions D_k;
  /// @param base  [9V] raw features f⁰ at w = 0
  SubspaceEditor(const Vertices& reference, const Faces& faces, const std::vector<int>& handles,
                 const Eigen::MatrixXd& directions, std::vector<double> base);

  /// Minimises E from `start` [K]. `pinned` [V, 3]: the handles' targets at their rows, and the
  /// positions the other pinned vertices keep (e.g. the shape edited from). `progress` gets each
  /// iteration and E.
  SubspaceEditResult edit(const Eigen::VectorXd& start, const Vertices& pinned,
                          const SubspaceEditOptions& opt,
                          const std::function<void(int, double)>& progress = {}) const;

  enum class EnergyParts { value, gradient, gauss_newton };
  /// E, and its gradient (cheap: the adjoint) or its gradient and Gauss-Newton matrix (K more
  /// solves, O(E K²)).
  SubspaceEnergy energy(const Eigen::VectorXd& w, const Vertices& pinned,
                        const SubspaceEditOptions& reg, EnergyParts parts) const;
  /// f⁰ + Σ w_k D_k
  std::vector<double> features(const Eigen::VectorXd& w) const;
  /// dT_i/dw_k [3, 3] at w (for the tests' finite differences).
  Eigen::Matrix3d transform_derivative(const Eigen::VectorXd& w, int vertex, int k) const;
  Eigen::Matrix3d transform(const Eigen::VectorXd& w, int vertex) const;

  int directions() const { return static_cast<int>(directions_.rows()); }
  const Reconstructor& reconstructor() const { return rec_; }
  double factor_seconds() const { return rec_.factor_seconds(); }

 private:
  struct Transforms;  // each vertex's R = exp(ρ), S and J_r(ρ) at one w
  Transforms transforms(const std::vector<double>& f) const;
  Eigen::Vector3d edge_vector(Eigen::Index e) const;  // q_e on the reference
  /// The weighted fit Σ c_e ‖r_e‖² (unscaled), r_e per edge into `residual` [E, 3].
  double fit(const Transforms& t, const Vertices& positions, Eigen::MatrixXd& residual) const;
  /// ∂E/∂f by the adjoint: the 9 numbers per vertex that D maps to E's gradient (without Ω).
  Eigen::VectorXd feature_gradient(const Transforms& t, const Eigen::MatrixXd& residual) const;
  /// JᵀCJ [K, K] of the fit with the positions eliminated.
  Eigen::MatrixXd fit_gauss_newton(const Transforms& t) const;

  Reconstructor rec_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> directions_;  // [K, 9V]
  std::vector<double> base_;
  Vertices reference_;
  double scale_ = 1;  // Σ c_ij ‖q_i − q_j‖²
  // the rotation vector and stretch of each of the 9 unit feature vectors (the features' layout)
  std::array<Eigen::Vector3d, 9> unit_rotation_;
  std::array<Eigen::Matrix3d, 9> unit_stretch_;
};

}  // namespace df::geometry
