#include "geometry/subspace_edit.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "geometry/acap_features.h"
#include "geometry/rotation.h"

namespace df::geometry {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
constexpr Eigen::Index kChunk =
    2048;  // edges per partial sum: fixed, so sums do not depend on threads

// J_r(ρ): exp([ρ + δ]×) ≈ exp([ρ]×) exp([J_r(ρ) δ]×) to first order.
Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& r) {
  const double t = r.norm();
  const Eigen::Matrix3d K = skew(r), I = Eigen::Matrix3d::Identity();
  if (t < 1e-5) return I - 0.5 * K + K * K / 6.0;
  return I - (1 - std::cos(t)) / (t * t) * K + (t - std::sin(t)) / (t * t * t) * K * K;
}

// dT/dw_k at a vertex, T = exp(ρ) S = R S, its rotation vector and stretch moving along (dr, dS):
// R ([J dr]× S + dS).
Eigen::Matrix3d transform_change(const Eigen::Matrix3d& R, const Eigen::Matrix3d& J,
                                 const Eigen::Matrix3d& S, const Eigen::Vector3d& dr,
                                 const Eigen::Matrix3d& dS) {
  return R * (skew(J * dr) * S + dS);
}

}  // namespace

SubspaceEditor::SubspaceEditor(const Vertices& reference, const Faces& faces,
                               const std::vector<int>& handles, const Eigen::MatrixXd& directions,
                               std::vector<double> base)
    : rec_(reference, faces, handles),
      directions_(directions),
      base_(std::move(base)),
      reference_(reference) {
  const auto n9 = static_cast<Eigen::Index>(kFeatureDims) * reference.rows();
  if (directions_.cols() != n9 || static_cast<Eigen::Index>(base_.size()) != n9)
    throw InvalidInput(
        "the directions and base features do not have 9 numbers per template vertex");
  scale_ = 0;
  const auto& c = rec_.edge_weights();
  for (std::size_t e = 0; e < rec_.topology().edges.size(); ++e) {
    auto [i, j] = rec_.topology().edges[e];
    scale_ += c[e] * (reference.row(i) - reference.row(j)).squaredNorm();
  }
  if (!(scale_ > 0)) throw InvalidInput("the template's edges have no positive total weight");
  for (int m = 0; m < kFeatureDims; ++m) {
    double unit[kFeatureDims] = {};
    unit[m] = 1;
    unpack_features(unit, unit_rotation_[static_cast<std::size_t>(m)],
                    unit_stretch_[static_cast<std::size_t>(m)]);
  }
}

std::vector<double> SubspaceEditor::features(const Eigen::VectorXd& w) const {
  Eigen::Map<const Eigen::VectorXd> f0(base_.data(), static_cast<Eigen::Index>(base_.size()));
  Eigen::VectorXd f = f0 + directions_.transpose() * w;
  return {f.data(), f.data() + f.size()};
}

Eigen::Matrix3d SubspaceEditor::transform(const Eigen::VectorXd& w, int vertex) const {
  const auto f = features(w);
  Eigen::Vector3d r;
  Eigen::Matrix3d S;
  unpack_features(f.data() + kFeatureDims * vertex, r, S);
  return rotation_exp(r) * S;
}

Eigen::Matrix3d SubspaceEditor::transform_derivative(const Eigen::VectorXd& w, int vertex,
                                                     int k) const {
  const auto f = features(w);
  Eigen::Vector3d r, dr;
  Eigen::Matrix3d S, dS;
  unpack_features(f.data() + kFeatureDims * vertex, r, S);
  unpack_features(directions_.row(k).data() + kFeatureDims * vertex, dr, dS);
  return transform_change(rotation_exp(r), right_jacobian(r), S, dr, dS);
}

struct SubspaceEditor::Transforms {
  std::vector<Eigen::Matrix3d> R, S, J;
};

SubspaceEditor::Transforms SubspaceEditor::transforms(const std::vector<double>& f) const {
  const int V = rec_.n_vertices();
  Transforms t{std::vector<Eigen::Matrix3d>(static_cast<std::size_t>(V)),
               std::vector<Eigen::Matrix3d>(static_cast<std::size_t>(V)),
               std::vector<Eigen::Matrix3d>(static_cast<std::size_t>(V))};
  tbb::parallel_for(0, V, [&](int i) {
    Eigen::Vector3d r;
    unpack_features(f.data() + kFeatureDims * i, r, t.S[static_cast<std::size_t>(i)]);
    t.R[static_cast<std::size_t>(i)] = rotation_exp(r);
    t.J[static_cast<std::size_t>(i)] = right_jacobian(r);
  });
  return t;
}

Eigen::Vector3d SubspaceEditor::edge_vector(Eigen::Index e) const {
  auto [i, j] = rec_.topology().edges[static_cast<std::size_t>(e)];
  return reference_.row(i) - reference_.row(j);
}

SubspaceEnergy SubspaceEditor::energy(const Eigen::VectorXd& w, const Vertices& pinned,
                                      const SubspaceEditOptions& reg, EnergyParts parts) const {
  constexpr double eps = 1e-3;  // the sparsity term's smoothing
  const Eigen::ArrayXd root = (w.array().square() + eps * eps).sqrt();
  const auto f = features(w);
  SubspaceEnergy out;
  out.positions = rec_.solve(f.data(), &pinned);
  const Transforms t = transforms(f);
  Eigen::MatrixXd residual;
  out.fit = fit(t, out.positions, residual) / scale_;
  out.value = out.fit + reg.l2 * w.squaredNorm() + reg.l1 * (root - eps).sum();
  if (parts == EnergyParts::value) return out;

  out.gradient = directions_ * feature_gradient(t, residual) + 2 * reg.l2 * w;
  out.gradient.array() += reg.l1 * w.array() / root;
  if (parts == EnergyParts::gradient) return out;

  const Eigen::MatrixXd JCJ = fit_gauss_newton(t);
  out.gauss_newton = 2 / scale_ * 0.5 * (JCJ + JCJ.transpose());
  out.gauss_newton.diagonal().array() += 2 * reg.l2 + reg.l1 * eps * eps / root.cube();
  return out;
}

// r_e = (p_i − p_j) − ½(T_i + T_j) q_e; the fit summed in fixed chunks of edges, then in order:
// the same sum at any thread count.
double SubspaceEditor::fit(const Transforms& t, const Vertices& positions,
                           Eigen::MatrixXd& residual) const {
  const auto& edges = rec_.topology().edges;
  const auto& c = rec_.edge_weights();
  const auto E = static_cast<Eigen::Index>(edges.size());
  residual.resize(E, 3);
  const Eigen::Index chunks = (E + kChunk - 1) / kChunk;
  std::vector<double> sums(static_cast<std::size_t>(chunks), 0.0);
  tbb::parallel_for(Eigen::Index{0}, chunks, [&](Eigen::Index ch) {
    for (Eigen::Index e = ch * kChunk; e < std::min(E, (ch + 1) * kChunk); ++e) {
      auto [i, j] = edges[static_cast<std::size_t>(e)];
      const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
      const Eigen::Vector3d d = (positions.row(i) - positions.row(j)).transpose() -
                                0.5 * (t.R[a] * t.S[a] + t.R[b] * t.S[b]) * edge_vector(e);
      residual.row(e) = d.transpose();
      sums[static_cast<std::size_t>(ch)] += c[static_cast<std::size_t>(e)] * d.squaredNorm();
    }
  });
  double total = 0;
  for (double x : sums) total += x;
  return total;
}

// The gradient by the adjoint: p* is stationary, so dE/dw_k = Σ_i ⟨∂E/∂T_i, dT_i/dw_k⟩ + 2λw_k
// with ∂E/∂T_i = −M_i / s, M_i = Σ_(e∋i) c_e r_e q_eᵀ; ⟨M_i, dT_i/dw_k⟩ is linear in direction
// k's 9 numbers at i, so the gradient is D h for one vector h of 9 numbers per vertex.
Eigen::VectorXd SubspaceEditor::feature_gradient(const Transforms& t,
                                                 const Eigen::MatrixXd& residual) const {
  const int V = rec_.n_vertices();
  const auto& topo = rec_.topology();
  const auto& c = rec_.edge_weights();
  Eigen::VectorXd h(static_cast<Eigen::Index>(kFeatureDims) * V);
  tbb::parallel_for(0, V, [&](int i) {
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (int n = topo.ring_offsets[i]; n < topo.ring_offsets[i + 1]; ++n) {
      const auto e = static_cast<Eigen::Index>(topo.ring_edges[n]);
      M +=
          c[static_cast<std::size_t>(e)] * residual.row(e).transpose() * edge_vector(e).transpose();
    }
    const auto v = static_cast<std::size_t>(i);
    const Eigen::Matrix3d N = t.R[v].transpose() * M, NS = N * t.S[v];
    // ⟨N, [x]× S⟩ = x · (NS₂₁ − NS₁₂, NS₀₂ − NS₂₀, NS₁₀ − NS₀₁); x = J dr
    const Eigen::Vector3d a =
        t.J[v].transpose() *
        Eigen::Vector3d(NS(2, 1) - NS(1, 2), NS(0, 2) - NS(2, 0), NS(1, 0) - NS(0, 1));
    for (int m = 0; m < kFeatureDims; ++m)
      h[kFeatureDims * i + m] =
          -(a.dot(unit_rotation_[m]) + (N.array() * unit_stretch_[m].array()).sum()) / scale_;
  });
  return h;
}

// The Gauss-Newton matrix. G: dg_e/dw_k in rows 3e..3e+2 (CG: times c_e), g_e = ½(T_i + T_j)q_e;
// B = Aᵀ C G, the right-hand sides' change, in three blocks of K columns (one per coordinate).
// With p eliminated J = A L⁻¹ B − G, and since the residual is orthogonal to A's range at p*,
// JᵀCJ = GᵀCG − (L⁻¹B)ᵀB.
Eigen::MatrixXd SubspaceEditor::fit_gauss_newton(const Transforms& t) const {
  const int V = rec_.n_vertices();
  const auto K = directions_.rows();
  const auto& topo = rec_.topology();
  const auto& edges = topo.edges;
  const auto& c = rec_.edge_weights();
  const auto E = static_cast<Eigen::Index>(edges.size());
  std::vector<Eigen::Matrix3d> dT(static_cast<std::size_t>(V * K));  // dT_i/dw_k at i * K + k
  tbb::parallel_for(0, V, [&](int i) {
    const auto v = static_cast<std::size_t>(i);
    Eigen::Vector3d dr;
    Eigen::Matrix3d dS;
    for (Eigen::Index k = 0; k < K; ++k) {
      unpack_features(directions_.row(k).data() + kFeatureDims * i, dr, dS);
      dT[static_cast<std::size_t>(i * K + k)] = transform_change(t.R[v], t.J[v], t.S[v], dr, dS);
    }
  });
  RowMatrix G(3 * E, K), CG(3 * E, K);
  tbb::parallel_for(Eigen::Index{0}, E, [&](Eigen::Index e) {
    auto [i, j] = edges[static_cast<std::size_t>(e)];
    const Eigen::Vector3d qe = edge_vector(e);
    for (Eigen::Index k = 0; k < K; ++k) {
      const Eigen::Vector3d g =
          0.5 *
          (dT[static_cast<std::size_t>(i * K + k)] + dT[static_cast<std::size_t>(j * K + k)]) * qe;
      G.block<3, 1>(3 * e, k) = g;
      CG.block<3, 1>(3 * e, k) = c[static_cast<std::size_t>(e)] * g;
    }
  });
  const auto& reduced = rec_.reduced_index();
  const auto free = static_cast<Eigen::Index>(
      reduced.size() - static_cast<std::size_t>(std::count(reduced.begin(), reduced.end(), -1)));
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(free, 3 * K);
  tbb::parallel_for(0, V, [&](int v) {  // gathered per vertex over its edges
    const int rv = reduced[static_cast<std::size_t>(v)];
    if (rv < 0) return;
    for (int n = topo.ring_offsets[v]; n < topo.ring_offsets[v + 1]; ++n) {
      const auto e = static_cast<Eigen::Index>(topo.ring_edges[n]);
      const double sign = edges[static_cast<std::size_t>(e)][0] == v ? 1.0 : -1.0;
      for (int a = 0; a < 3; ++a) B.row(rv).segment(a * K, K) += sign * CG.row(3 * e + a);
    }
  });
  Eigen::MatrixXd X(free, 3 * K);
  tbb::parallel_for(Eigen::Index{0}, 3 * K,
                    [&](Eigen::Index col) { X.col(col) = rec_.solve_reduced(B.col(col)); });
  const Eigen::Index chunks = (E + kChunk - 1) / kChunk;
  std::vector<Eigen::MatrixXd> part(static_cast<std::size_t>(chunks));  // GᵀCG by fixed chunks
  tbb::parallel_for(Eigen::Index{0}, chunks, [&](Eigen::Index ch) {
    const Eigen::Index first = 3 * ch * kChunk,
                       rows = 3 * (std::min(E, (ch + 1) * kChunk) - ch * kChunk);
    part[static_cast<std::size_t>(ch)] =
        G.middleRows(first, rows).transpose() * CG.middleRows(first, rows);
  });
  Eigen::MatrixXd JCJ = Eigen::MatrixXd::Zero(K, K);
  for (const auto& m : part) JCJ += m;
  for (int a = 0; a < 3; ++a)
    JCJ.noalias() -= X.middleCols(a * K, K).transpose() * B.middleCols(a * K, K);
  return JCJ;
}

SubspaceEditResult SubspaceEditor::edit(const Eigen::VectorXd& start, const Vertices& pinned,
                                        const SubspaceEditOptions& opt,
                                        const std::function<void(int, double)>& progress) const {
  if (start.size() != directions_.rows())
    throw InvalidInput("the start weights do not match the directions");
  SubspaceEditResult res;
  res.weights = start;
  SubspaceEnergy cur = energy(res.weights, pinned, opt, EnergyParts::gauss_newton);
  Eigen::MatrixXd H =
      cur.gauss_newton;  // kept while steps succeed: the costly part, refreshed on failure
  bool fresh = true;
  int stale_steps = 0;
  res.energy.push_back(cur.value);
  if (progress) progress(0, cur.value);
  double mu = 1e-4;  // Marquardt's damping, relative to the diagonal
  while (res.iterations < opt.max_iterations) {
    Eigen::MatrixXd A = H;
    A.diagonal() *= 1 + mu;
    A.diagonal().array() += 1e-14 * (1 + A.diagonal().cwiseAbs().maxCoeff());
    const Eigen::VectorXd step = A.ldlt().solve(-cur.gradient);
    SubspaceEnergy trial = energy(res.weights + step, pinned, opt, EnergyParts::gradient);
    const bool lower = trial.value < cur.value;
    const double gain = lower ? (cur.value - trial.value) / std::max(cur.value, 1e-300) : 0.0;
    const bool small =
        step.lpNorm<Eigen::Infinity>() < 1e-13 * (1 + res.weights.lpNorm<Eigen::Infinity>());
    // Only a step that lowers E by the tolerance is taken: one below it changes E at the level of
    // rounding, where whether it is "lower" at all depends on the machine's arithmetic, and taking
    // it would make the step count (and the file's energy trace) differ between builds.
    if (lower && gain >= opt.tolerance && !small) {
      res.weights += step;
      cur = std::move(trial);
      res.energy.push_back(cur.value);
      ++res.iterations;
      if (progress) progress(res.iterations, cur.value);
      mu = std::max(mu / 3, 1e-12);
      // the old matrix converges linearly: take the current one every few steps
      if (++stale_steps % 4 == 0) {
        H = energy(res.weights, pinned, opt, EnergyParts::gauss_newton).gauss_newton;
        fresh = true;
      } else {
        fresh = false;
      }
      continue;
    }
    if (!fresh) {  // a failed or tiny step with an old matrix: take the current one first
      H = energy(res.weights, pinned, opt, EnergyParts::gauss_newton).gauss_newton;
      fresh = true;
      continue;
    }
    if (lower || small || mu > 1e10) {  // converged: no progress with the current matrix
      res.converged = true;
      break;
    }
    mu *= 4;
  }
  res.positions = std::move(cur.positions);
  res.features = features(res.weights);
  return res;
}

}  // namespace df::geometry
