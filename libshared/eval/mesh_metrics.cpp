#include "eval/mesh_metrics.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <set>

namespace df::eval {

Vertices align_translation(const Vertices& pred, const Vertices& truth,
                           const std::vector<int>& component, int n_components) {
  Eigen::MatrixXd shift = Eigen::MatrixXd::Zero(n_components, 3);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(n_components);
  for (Eigen::Index v = 0; v < pred.rows(); ++v) {
    shift.row(component[static_cast<std::size_t>(v)]) += truth.row(v) - pred.row(v);
    count[component[static_cast<std::size_t>(v)]] += 1;
  }
  Vertices out = pred;
  for (Eigen::Index v = 0; v < pred.rows(); ++v) {
    const int c = component[static_cast<std::size_t>(v)];
    out.row(v) += shift.row(c) / count[c];
  }
  return out;
}

Vertices align_rigid(const Vertices& pred, const Vertices& truth, const std::vector<int>& component,
                     int n_components) {
  const auto nc = static_cast<std::size_t>(n_components);
  std::vector<Eigen::RowVector3d> cp(nc, Eigen::RowVector3d::Zero()),
      ct(nc, Eigen::RowVector3d::Zero());
  std::vector<double> count(nc, 0.0);
  for (Eigen::Index v = 0; v < pred.rows(); ++v) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
    cp[c] += pred.row(v), ct[c] += truth.row(v), count[c] += 1;
  }
  std::vector<Eigen::Matrix3d> cross(nc, Eigen::Matrix3d::Zero());
  for (std::size_t c = 0; c < nc; ++c)
    if (count[c] > 0) cp[c] /= count[c], ct[c] /= count[c];
  for (Eigen::Index v = 0; v < pred.rows(); ++v) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
    cross[c] += (pred.row(v) - cp[c]).transpose() * (truth.row(v) - ct[c]);
  }
  // Row vectors: aligned = (p − p̄) R + t̄ with R = U diag(1, 1, ±1) Vᵀ of cross = U Σ Vᵀ.
  std::vector<Eigen::Matrix3d> rot(nc, Eigen::Matrix3d::Identity());
  for (std::size_t c = 0; c < nc; ++c) {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cross[c],
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    rot[c] = svd.matrixU() * d * svd.matrixV().transpose();
  }
  Vertices out(pred.rows(), 3);
  for (Eigen::Index v = 0; v < pred.rows(); ++v) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(v)]);
    out.row(v) = (pred.row(v) - cp[c]) * rot[c] + ct[c];
  }
  return out;
}

double mean_vertex_error(const Vertices& pred, const Vertices& truth) {
  return (pred - truth).rowwise().norm().mean();
}

double unit_ball_squared_error(const Vertices& pred, const Vertices& truth) {
  const Eigen::RowVector3d c = truth.colwise().mean();
  const double r = (truth.rowwise() - c).rowwise().norm().maxCoeff();
  const double s = r > 0 ? 1.0 / r : 1.0;
  return ((pred - truth) * s).squaredNorm();
}

MeshParts mesh_parts(const Faces& faces, Eigen::Index vertices) {
  if (faces.rows() == 0) return {std::vector<int>(static_cast<std::size_t>(vertices), 0), 1};
  return mesh_parts(geometry::mesh_topology(faces, static_cast<int>(vertices)));
}

MeshParts mesh_parts(const geometry::MeshTopology& topo) {
  MeshParts p;
  p.of_vertex = geometry::connected_components(topo, 0, &p.count);
  return p;
}

Vertices align_parts(const Vertices& pred, const Vertices& truth, const MeshParts& parts,
                     Alignment how) {
  return how == Alignment::rigid ? align_rigid(pred, truth, parts.of_vertex, parts.count)
                                 : align_translation(pred, truth, parts.of_vertex, parts.count);
}

double erms_share(const Vertices& pred, const Vertices& truth, const MeshParts& parts) {
  return unit_ball_squared_error(align_parts(pred, truth, parts), truth);
}

double erms_from_sum(double unit_ball_sum, double frames, double vertices) {
  return 1000.0 * std::sqrt(unit_ball_sum / (3.0 * frames * vertices));
}

std::vector<std::vector<int>> edge_neighbourhoods(const geometry::MeshTopology& topo, int rings) {
  std::vector<std::vector<int>> out(static_cast<std::size_t>(topo.n_vertices));
  for (int i = 0; i < topo.n_vertices; ++i) {
    std::set<int> verts{i}, frontier{i}, edges;
    for (int r = 0; r < rings; ++r) {
      std::set<int> next;
      for (int v : frontier)
        for (int k = topo.ring_offsets[v]; k < topo.ring_offsets[v + 1]; ++k) {
          edges.insert(topo.ring_edges[static_cast<std::size_t>(k)]);
          const int w = topo.ring_vertices[static_cast<std::size_t>(k)];
          if (verts.insert(w).second) next.insert(w);
        }
      frontier = std::move(next);
    }
    out[static_cast<std::size_t>(i)].assign(edges.begin(), edges.end());
  }
  return out;
}

double sted_spatial(const Vertices& pred, const Vertices& truth, const geometry::MeshTopology& topo,
                    const std::vector<std::vector<int>>& neighbourhoods) {
  const std::size_t ne = topo.edges.size();
  std::vector<double> ed(ne), len(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const auto [a, b] = topo.edges[e];
    const double l = (truth.row(a) - truth.row(b)).norm(), lp = (pred.row(a) - pred.row(b)).norm();
    len[e] = l;
    ed[e] = l > 0 ? std::abs(lp - l) / l : 0.0;
  }
  double total = 0;
  for (const auto& nb : neighbourhoods) {
    double w = 0, m = 0;
    for (int e : nb)
      w += len[static_cast<std::size_t>(e)],
          m += len[static_cast<std::size_t>(e)] * ed[static_cast<std::size_t>(e)];
    if (w <= 0) continue;
    m /= w;
    double var = 0;
    for (int e : nb) {
      const double d = ed[static_cast<std::size_t>(e)] - m;
      var += len[static_cast<std::size_t>(e)] * d * d;
    }
    total += std::sqrt(var / w);
  }
  return neighbourhoods.empty() ? 0.0 : total / static_cast<double>(neighbourhoods.size());
}

double sted_temporal(const Vertices& pred0, const Vertices& pred1, const Vertices& truth0,
                     const Vertices& truth1, const geometry::MeshTopology& topo, double dt) {
  auto speed = [&](const Vertices& p0, const Vertices& p1, int i) {
    double l = 0;
    const int d = topo.degree(i);
    for (int k = topo.ring_offsets[i]; k < topo.ring_offsets[i + 1]; ++k)
      l += (p0.row(i) - p0.row(topo.ring_vertices[static_cast<std::size_t>(k)])).norm();
    l = d ? l / d : 1.0;
    return l > 0 ? (p1.row(i) - p0.row(i)).norm() / (dt * l) : 0.0;
  };
  double total = 0;
  for (int i = 0; i < topo.n_vertices; ++i)
    total += std::abs(speed(pred0, pred1, i) - speed(truth0, truth1, i));
  return topo.n_vertices ? total / topo.n_vertices : 0.0;
}

double relative_squared_error(const Eigen::Ref<const Eigen::VectorXd>& x,
                              const Eigen::Ref<const Eigen::VectorXd>& xhat) {
  const double n = x.squaredNorm();
  return n > 0 ? (x - xhat).squaredNorm() / n : 0.0;
}

double feature_change(const Eigen::Ref<const Eigen::VectorXd>& xt,
                      const Eigen::Ref<const Eigen::VectorXd>& xt1) {
  const double n = xt.norm();
  return n > 0 ? (xt - xt1).norm() / n : 0.0;
}

}  // namespace df::eval
