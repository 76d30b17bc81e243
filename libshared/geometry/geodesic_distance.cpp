#include "geometry/geodesic_distance.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.h"
#include "geometry/mesh_topology.h"

namespace df::geometry {

using Sparse = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

struct HeatMethodDistance::Impl {
  Vertices V;
  Faces F;
  std::vector<std::array<double, 3>> cot;  // per face, cotangent of the angle at each corner
  std::vector<Eigen::Vector3d> normal;     // per face, unit normal
  std::vector<double> area;                // per face
  std::vector<char> boundary;              // per vertex
  std::vector<int> interior_index;         // per vertex, -1 on the boundary
  std::vector<int> component;
  int n_components = 0;
  Eigen::VectorXd mass;  // lumped (barycentric) vertex areas
  Eigen::SimplicialLDLT<Sparse> heat_neumann, heat_dirichlet, poisson;
  bool has_boundary = false;

  void face_geometry();
  Triplets cotangent_laplacian()
      const;  // L = Σ c_ij (e_i − e_j)(e_i − e_j)ᵀ, positive semi-definite
  void factor(double t);
  Eigen::VectorXd heat(int source) const;
  Eigen::VectorXd divergence_of_unit_field(const Eigen::VectorXd& u) const;
};

void HeatMethodDistance::Impl::face_geometry() {
  const auto nf = static_cast<std::size_t>(F.rows());
  cot.resize(nf), normal.resize(nf), area.resize(nf);
  mass = Eigen::VectorXd::Zero(V.rows());
  for (std::size_t f = 0; f < nf; ++f) {
    const auto fi = static_cast<Eigen::Index>(f);
    const Eigen::Vector3d p[3] = {V.row(F(fi, 0)).transpose(), V.row(F(fi, 1)).transpose(),
                                  V.row(F(fi, 2)).transpose()};
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    area[f] = 0.5 * n.norm();
    normal[f] = area[f] > 0 ? Eigen::Vector3d(n / (2 * area[f])) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      const double s = a.cross(b).norm();
      cot[f][static_cast<std::size_t>(k)] = s > 0 ? a.dot(b) / s : 0.0;
      mass[F(fi, k)] += area[f] / 3;
    }
  }
}

Triplets HeatMethodDistance::Impl::cotangent_laplacian() const {
  Triplets t;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {  // the edge opposite corner k, weight ½ cot(angle at k)
      const int i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      const double w = 0.5 * cot[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
      t.emplace_back(i, i, w), t.emplace_back(j, j, w), t.emplace_back(i, j, -w),
          t.emplace_back(j, i, -w);
    }
  return t;
}

void HeatMethodDistance::Impl::factor(double t) {
  const auto n = V.rows();
  Triplets L = cotangent_laplacian();
  // Heat operator M + tL (Neumann), and the same on interior vertices only (Dirichlet u = 0).
  Triplets heat = L;
  for (auto& e : heat) e = Eigen::Triplet<double>(e.row(), e.col(), t * e.value());
  for (Eigen::Index i = 0; i < n; ++i) heat.emplace_back(i, i, mass[i]);
  Sparse A(n, n);
  A.setFromTriplets(heat.begin(), heat.end());
  heat_neumann.compute(A);
  if (heat_neumann.info() != Eigen::Success)
    throw InvalidInput("geodesics: the heat operator cannot be factored");
  if (has_boundary) {
    int m = 0;
    interior_index.assign(static_cast<std::size_t>(n), -1);
    for (Eigen::Index i = 0; i < n; ++i)
      if (!boundary[static_cast<std::size_t>(i)]) interior_index[static_cast<std::size_t>(i)] = m++;
    Triplets inner;
    for (const auto& e : heat) {
      const int r = interior_index[static_cast<std::size_t>(e.row())],
                c = interior_index[static_cast<std::size_t>(e.col())];
      if (r >= 0 && c >= 0) inner.emplace_back(r, c, e.value());
    }
    Sparse D(m, m);
    D.setFromTriplets(inner.begin(), inner.end());
    heat_dirichlet.compute(D);
    if (heat_dirichlet.info() != Eigen::Success)
      throw InvalidInput("geodesics: the Dirichlet heat operator cannot be factored");
  }
  // Poisson: L is singular (constants); a tiny multiple of M pins the free constant.
  Sparse P(n, n);
  P.setFromTriplets(L.begin(), L.end());
  const double shift = 1e-10 * P.diagonal().mean() / std::max(mass.mean(), 1e-300);
  for (Eigen::Index i = 0; i < n; ++i) P.coeffRef(i, i) += shift * mass[i];
  poisson.compute(P);
  if (poisson.info() != Eigen::Success)
    throw InvalidInput("geodesics: the cotangent Laplacian cannot be factored");
}

Eigen::VectorXd HeatMethodDistance::Impl::heat(int source) const {
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(V.rows());
  delta[source] = 1;
  Eigen::VectorXd u = heat_neumann.solve(delta);
  if (has_boundary &&
      !boundary[static_cast<std::size_t>(source)]) {  // average with u = 0 on the boundary
    Eigen::VectorXd d = Eigen::VectorXd::Zero(heat_dirichlet.rows());
    d[interior_index[static_cast<std::size_t>(source)]] = 1;
    const Eigen::VectorXd ud = heat_dirichlet.solve(d);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      const int k = interior_index[static_cast<std::size_t>(i)];
      u[i] = 0.5 * (u[i] + (k >= 0 ? ud[k] : 0.0));
    }
  }
  return u;
}

Eigen::VectorXd HeatMethodDistance::Impl::divergence_of_unit_field(const Eigen::VectorXd& u) const {
  Eigen::VectorXd div = Eigen::VectorXd::Zero(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const auto fs = static_cast<std::size_t>(f);
    if (!(area[fs] > 0)) continue;
    const int idx[3] = {F(f, 0), F(f, 1), F(f, 2)};
    const Eigen::Vector3d p[3] = {V.row(idx[0]).transpose(), V.row(idx[1]).transpose(),
                                  V.row(idx[2]).transpose()};
    // ∇u = 1/(2A) Σ_k u_k (N × e_k), e_k the edge opposite corner k (counter-clockwise).
    Eigen::Vector3d grad = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      grad += u[idx[k]] * normal[fs].cross(p[(k + 2) % 3] - p[(k + 1) % 3]);
    const double len = grad.norm();
    if (!(len > 0)) continue;
    const Eigen::Vector3d X = -grad / len;
    // ∇·X at corner k: ½ (cot θ₁ (e₁·X) + cot θ₂ (e₂·X)), e₁, e₂ the edges leaving corner k and
    // θ₁, θ₂ the angles opposite them.
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      div[idx[k]] += 0.5 * (cot[fs][static_cast<std::size_t>(b)] * (p[a] - p[k]).dot(X) +
                            cot[fs][static_cast<std::size_t>(a)] * (p[b] - p[k]).dot(X));
    }
  }
  return div;
}

HeatMethodDistance::HeatMethodDistance(const Vertices& V, const Faces& F, double t_factor)
    : impl_(std::make_unique<Impl>()) {
  auto& m = *impl_;
  if (V.rows() == 0 || F.rows() == 0) throw InvalidInput("geodesics need a mesh with triangles");
  m.V = V, m.F = F;
  m.face_geometry();
  // Boundary vertices: on an edge used by one face only.
  std::map<std::pair<int, int>, int> edge_faces;
  double edge_sum = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = F(f, k), j = F(f, (k + 1) % 3);
      ++edge_faces[{std::min(i, j), std::max(i, j)}];
      edge_sum += (V.row(i) - V.row(j)).norm();
    }
  m.boundary.assign(static_cast<std::size_t>(V.rows()), 0);
  for (const auto& [e, count] : edge_faces)
    if (count == 1)
      m.boundary[static_cast<std::size_t>(e.first)] =
          m.boundary[static_cast<std::size_t>(e.second)] = 1,
      m.has_boundary = true;
  const double h = edge_sum / (3.0 * static_cast<double>(F.rows()));
  m.component =
      connected_components(mesh_topology(F, static_cast<int>(V.rows())), 0, &m.n_components);
  m.factor(t_factor * h * h);
}

HeatMethodDistance::~HeatMethodDistance() = default;

int HeatMethodDistance::parts() const {
  return impl_->n_components;
}

Eigen::VectorXd HeatMethodDistance::from(int source) const {
  const auto& m = *impl_;
  if (source < 0 || source >= m.V.rows())
    throw InvalidInput("geodesics: source vertex out of range");
  const Eigen::VectorXd div = m.divergence_of_unit_field(m.heat(source));
  Eigen::VectorXd phi = m.poisson.solve(-div);  // L φ = −∇·X (L positive semi-definite)
  const int c = m.component[static_cast<std::size_t>(source)];
  const double origin = phi[source];
  for (Eigen::Index i = 0; i < phi.size(); ++i)
    phi[i] = m.component[static_cast<std::size_t>(i)] == c
                 ? std::max(0.0, phi[i] - origin)
                 : std::numeric_limits<double>::infinity();
  return phi;
}

GeodesicRows::GeodesicRows(const Vertices& V, const Faces& F)
    : heat_(V, F), vertices_(V), n_vertices_(V.rows()) {
  // Farthest-point sweeps: each solve starts from the vertex farthest from the previous source.
  int source = 0;
  for (int sweep = 0; sweep < 8; ++sweep) {
    const Eigen::VectorXd d = bridged(source);
    int far = source;
    double best = 0;
    for (Eigen::Index i = 0; i < d.size(); ++i)
      if (std::isfinite(d[i]) && d[i] > best) best = d[i], far = static_cast<int>(i);
    if (best <= diameter_ * (1 + 1e-9)) break;
    diameter_ = best;
    source = far;
  }
  if (!(diameter_ > 0))
    throw InvalidInput("the template has no extent: geodesic distances are all zero");
}

GeodesicRows::GeodesicRows(const Vertices& V, const Faces& F, double diameter)
    : heat_(V, F), vertices_(V), n_vertices_(V.rows()), diameter_(diameter) {
  if (!(diameter_ > 0)) throw InvalidInput("geodesic diameter must be positive");
}

Eigen::VectorXd GeodesicRows::bridged(int source) const {
  Eigen::VectorXd d = heat_.from(source);
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (!std::isfinite(d[i])) d[i] = (vertices_.row(i) - vertices_.row(source)).norm();
  return d;
}

Eigen::VectorXf GeodesicRows::normalized(const Eigen::VectorXd& d) const {
  Eigen::VectorXf out(d.size());
  for (Eigen::Index i = 0; i < d.size(); ++i)
    out[i] = std::isfinite(d[i]) ? static_cast<float>(std::min(1.0, d[i] / diameter_)) : 1.0f;
  return out;
}

void GeodesicRows::prepare(const std::vector<int>& sources) {
  std::vector<int> missing;
  for (int s : sources)
    if (!rows_.count(s) && std::find(missing.begin(), missing.end(), s) == missing.end())
      missing.push_back(s);
  if (missing.empty()) return;
  constexpr std::size_t kBudget = std::size_t{256} << 20;
  if ((rows_.size() + missing.size()) * static_cast<std::size_t>(n_vertices_) * sizeof(float) >
      kBudget)
    rows_.clear();
  std::vector<Eigen::VectorXf> solved(missing.size());
  tbb::parallel_for(std::size_t{0}, missing.size(),
                    [&](std::size_t k) { solved[k] = normalized(bridged(missing[k])); });
  for (std::size_t k = 0; k < missing.size(); ++k) rows_[missing[k]] = std::move(solved[k]);
}

const Eigen::VectorXf& GeodesicRows::row(int source) {
  auto it = rows_.find(source);
  if (it == rows_.end()) it = rows_.emplace(source, normalized(bridged(source))).first;
  return it->second;
}

}  // namespace df::geometry
