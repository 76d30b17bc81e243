#include "models/common/splocs.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/log.h"

namespace df::models {

using Eigen::Index;
using Mat = nn::Matrix<double>;

namespace {

// The reference code's weight projection: non-negative, largest 1.
Eigen::VectorXd project_weight(Eigen::VectorXd w) {
  w = w.cwiseMax(0.0);
  const double top = w.size() ? w.maxCoeff() : 0.0;
  return top > 0 ? Eigen::VectorXd(w / top) : w;
}

// 0 up to d_min, 1 from d_max, linear between.
Eigen::VectorXd support_map(const Eigen::VectorXf& d, const SplocsOptions& o) {
  Eigen::VectorXd s(d.size());
  for (Index i = 0; i < d.size(); ++i)
    s[i] =
        (std::clamp(static_cast<double>(d[i]), o.d_min, o.d_max) - o.d_min) / (o.d_max - o.d_min);
  return s;
}

}  // namespace

Index strongest_vertex(const Eigen::RowVectorXd& c, Index g) {
  Index best = 0;
  double top = -1;
  for (Index i = 0; i < c.size() / g; ++i)
    if (const double n = c.segment(g * i, g).squaredNorm(); n > top) top = n, best = i;
  return best;
}

Splocs fit_splocs(const Mat& x, const SplocsOptions& o,
                  const std::function<Eigen::VectorXf(int)>& distance, int group) {
  const Index g = group, F = x.rows(), D = x.cols(), V = D / g, K = o.components;
  if (g < 1 || D % g != 0) throw Error("internal: fit_splocs needs whole groups per vertex");
  Splocs s;
  s.mean = x.colwise().mean();
  Mat X = x.rowwise() - s.mean.row(0);
  s.scale = std::sqrt(X.squaredNorm() / static_cast<double>(X.size()));
  if (!(s.scale > 0))
    throw InvalidInput("the training shapes do not deform: nothing for SPLOCS to explain");
  X /= s.scale;

  // Greedy initialisation: each component explains the vertex of largest residual motion.
  Mat R = X, W = Mat::Zero(F, K), C = Mat::Zero(K, D);
  for (Index k = 0; k < K; ++k) {
    Index idx = 0;
    double top = -1;
    for (Index i = 0; i < V; ++i)
      if (const double m = R.middleCols(g * i, g).squaredNorm(); m > top) top = m, idx = i;
    const Mat Ri = R.middleCols(g * idx, g);  // [F, g]
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e(Ri.transpose() * Ri);
    const Eigen::VectorXd w = Ri * e.eigenvectors().col(g - 1);
    const Eigen::VectorXd wp = project_weight(w), wn = project_weight(-w);
    const Eigen::VectorXd wk = wp.norm() > wn.norm() ? wp : wn;
    const double ww = wk.squaredNorm();
    if (ww > 0) {
      const Eigen::VectorXd keep =
          Eigen::VectorXd::Ones(V) - support_map(distance(static_cast<int>(idx)), o);
      Eigen::RowVectorXd ck = (wk.transpose() * R) / ww;
      for (Index i = 0; i < V; ++i) ck.segment(g * i, g) *= keep[i];
      C.row(k) = ck;
    }
    W.col(k) = wk;
    R -= wk * C.row(k);
  }

  Mat lambda(K, V), U(K, D);
  for (int it = 0; it < o.iterations; ++it) {
    // Weights, one component at a time against the residual.
    Mat Rf = X - W * C;
    for (Index k = 0; k < K; ++k) {
      const double cc = C.row(k).squaredNorm();
      if (cc <= 1e-8) {
        Rf += W.col(k) * C.row(k);
        W.col(k).setZero();
        continue;
      }
      Rf += W.col(k) * C.row(k);
      W.col(k) = project_weight(Rf * C.row(k).transpose() / cc);
      Rf -= W.col(k) * C.row(k);
    }
    // Where each component may live: its support map around its strongest vertex.
    for (Index k = 0; k < K; ++k)
      lambda.row(k) =
          o.lambda *
          support_map(distance(static_cast<int>(strongest_vertex(C.row(k), g))), o).transpose();
    // Components by ADMM: a least-squares step and the group-ℓ1/ℓ2 shrinkage.
    const Eigen::LLT<Eigen::MatrixXd> solve(W.transpose() * W +
                                            o.rho * Eigen::MatrixXd::Identity(K, K));
    const Mat c = W.transpose() * X;
    Mat Z = C;
    U.setZero();
    for (int a = 0; a < o.admm_iterations; ++a) {
      C = solve.solve(c + o.rho * (Z - U));
      Z = C + U;
      for (Index k = 0; k < K; ++k)
        for (Index i = 0; i < V; ++i) {
          auto z = Z.row(k).segment(g * i, g);
          const double len = z.norm();
          z *= len > 0 ? std::max(0.0, 1 - lambda(k, i) / o.rho / len) : 0.0;
        }
      U += C - Z;
    }
    C = Z;
    log::debug("splocs iteration {}: residual {:.6g}", it + 1, (X - W * C).squaredNorm());
  }
  s.components = C * s.scale;
  return s;
}

}  // namespace df::models
