#include "geometry/sparse_cholesky.h"

#include <cholmod.h>
#include <dlfcn.h>

#include <chrono>
#include <cstring>
#include <string>

#include "core/error.h"

namespace df::geometry {
namespace {

// A cholmod_common started and finished with its scope, silent (errors come back as status).
struct Common {
  cholmod_common c;
  Common() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

// The supernodal factorisation's dense kernels come from the system's BLAS: Debian's reference
// BLAS (~3 GFLOP/s), or OpenBLAS where it is installed (libopenblas0-pthread, which
// scripts/install-deps.sh installs; 2.6x faster on a 136,000-vertex template). OpenBLAS runs the
// factorisation on one thread — its own threads would compete with TBB's, and its blocking may
// follow its thread count, which must not change the factor's bits — and gets its thread count
// back afterwards (the Python module shares the process with the user's numpy).
class BlasOnOneThread {
 public:
  BlasOnOneThread() {
    if (set_ && get_) {
      previous_ = get_();
      set_(1);
    }
  }
  ~BlasOnOneThread() {
    if (set_ && get_) set_(previous_);
  }
  BlasOnOneThread(const BlasOnOneThread&) = delete;
  BlasOnOneThread& operator=(const BlasOnOneThread&) = delete;

 private:
  using Set = void (*)(int);
  using Get = int (*)();
  static inline const Set set_ =
      reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  static inline const Get get_ =
      reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  int previous_ = 1;
};

}  // namespace

struct SparseCholesky::Factor {
  Common common;  // the one the factor was made with (freed with it)
  cholmod_factor* l = nullptr;
  ~Factor() {
    if (l) cholmod_free_factor(&l, &common.c);
  }
};

SparseCholesky::SparseCholesky() = default;
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::factor(const Eigen::SparseMatrix<double>& a) {
  if (a.rows() != a.cols()) throw Error("internal: SparseCholesky of a non-square matrix");
  factor_ = std::make_unique<Factor>();
  cholmod_common* c = &factor_->common.c;
  // The lower triangle as CHOLMOD's packed, sorted column-compressed matrix (stype −1).
  const Eigen::SparseMatrix<double> lower = a.triangularView<Eigen::Lower>();
  cholmod_sparse* m =
      cholmod_allocate_sparse(static_cast<size_t>(lower.rows()), static_cast<size_t>(lower.cols()),
                              static_cast<size_t>(lower.nonZeros()), 1, 1, -1, CHOLMOD_REAL, c);
  if (!m) throw Error("out of memory for the reconstruction system");
  std::memcpy(m->p, lower.outerIndexPtr(), sizeof(int) * static_cast<size_t>(lower.cols() + 1));
  std::memcpy(m->i, lower.innerIndexPtr(), sizeof(int) * static_cast<size_t>(lower.nonZeros()));
  std::memcpy(m->x, lower.valuePtr(), sizeof(double) * static_cast<size_t>(lower.nonZeros()));
  bool ok = false;
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  stats_ = {};
  {
    const BlasOnOneThread one;
    auto t = Clock::now();
    factor_->l = cholmod_analyze(m, c);
    stats_.analyse_seconds = seconds_since(t);
    t = Clock::now();
    ok = factor_->l && cholmod_factorize(m, factor_->l, c) && c->status == CHOLMOD_OK;
    stats_.factor_seconds = seconds_since(t);
    stats_.factor_nonzeros = c->lnz;
    stats_.flops = c->fl;
  }
  // Solves on a simplicial copy of the factor: a supernodal solve calls the BLAS, whose thread
  // count (OpenBLAS: the machine's cores) changed the solutions' last bits (823 of 3.3 M
  // coordinates on a 135,610-vertex template); the simplicial solve is plain loops.
  const auto t = Clock::now();
  if (ok && factor_->l->is_super)
    ok = cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/true, /*to_super=*/false, /*to_packed=*/true,
                               /*to_monotonic=*/true, factor_->l, c) &&
         c->status == CHOLMOD_OK;
  stats_.simplicial_seconds = seconds_since(t);
  cholmod_free_sparse(&m, c);
  if (!ok) {
    const int status = c->status;
    factor_.reset();
    throw InvalidInput(status == CHOLMOD_NOT_POSDEF
                           ? "the reconstruction system cannot be factored (not positive definite)"
                           : "the reconstruction system cannot be factored (CHOLMOD status " +
                                 std::to_string(status) + ")");
  }
  rows_ = a.rows();
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const {
  if (!factor_) throw Error("internal: SparseCholesky::solve before factor");
  if (b.rows() != rows_)
    throw Error("internal: SparseCholesky::solve with the wrong number of rows");
  Common own;  // this call's workspace: solves may run on several threads at once
  cholmod_dense in;
  in.nrow = in.d = static_cast<size_t>(b.rows());
  in.ncol = static_cast<size_t>(b.cols());
  in.nzmax = in.nrow * in.ncol;
  in.x = const_cast<double*>(b.data());  // read only
  in.z = nullptr;
  in.xtype = CHOLMOD_REAL;
  in.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* out = cholmod_solve(CHOLMOD_A, factor_->l, &in, &own.c);
  if (!out) throw Error("out of memory solving the reconstruction system");
  Eigen::MatrixXd x =
      Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(out->x), b.rows(), b.cols());
  cholmod_free_dense(&out, &own.c);
  return x;
}

}  // namespace df::geometry
