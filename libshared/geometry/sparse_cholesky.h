// A sparse symmetric positive definite system factored once and solved many times, from several
// threads at once (acap2obj solves its frames in parallel): CHOLMOD's Cholesky factorisation
// (SuiteSparse, Debian's libsuitesparse-dev), supernodal where CHOLMOD judges it pays (large
// templates: blocks of columns factored with dense kernels), simplicial otherwise, with its
// fill-reducing ordering; solved on a simplicial copy (no BLAS: the same bits whatever the BLAS's
// thread count). On a 136,000-vertex template it factors 2.4-2.7x faster than Eigen's
// SimplicialLDLT, which it replaced (with OpenBLAS as the system's BLAS; docs/speed.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace df::geometry {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Factors A (square, symmetric positive definite; its lower triangle is read).
  /// InvalidInput when A is not positive definite (e.g. a component with nothing pinned).
  void factor(const Eigen::SparseMatrix<double>& a);
  /// A⁻¹ b (b: one right-hand side per column). Thread-safe: every call has its own workspace.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  Eigen::Index rows() const { return rows_; }

  /// What the last factor() did: seconds in CHOLMOD's ordering and symbolic analysis, in the
  /// numeric factorisation and in the copy to a simplicial factor for the solves; the factor's
  /// non-zeros and CHOLMOD's count of its floating-point operations.
  struct Stats {
    double analyse_seconds = 0, factor_seconds = 0, simplicial_seconds = 0;
    double factor_nonzeros = 0, flops = 0;
  };
  const Stats& stats() const { return stats_; }

 private:
  struct Factor;
  std::unique_ptr<Factor> factor_;
  Eigen::Index rows_ = 0;
  Stats stats_;
};

}  // namespace df::geometry
