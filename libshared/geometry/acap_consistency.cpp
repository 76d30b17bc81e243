#include "geometry/acap_consistency.h"

#include <cmath>
#include <numbers>
#include <numeric>
#include <queue>

namespace df::geometry {
namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(static_cast<std::size_t>(n)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // smallest index is the root
  }
};

int sgn(double x) {
  return (x > 0) - (x < 0);
}

// Vertices grouped into clusters joined by edges for which `joined(edge)` holds: the clusters in
// order of their smallest vertex (vertex lists) and each vertex's cluster.
struct Clusters {
  std::vector<std::vector<int>> groups;
  std::vector<int> member;
};

template <class Joined>
Clusters clusters(const MeshTopology& t, Joined joined) {
  UnionFind uf(t.n_vertices);
  for (std::size_t e = 0; e < t.edges.size(); ++e)
    if (joined(e)) uf.unite(t.edges[e][0], t.edges[e][1]);
  std::vector<int> id(static_cast<std::size_t>(t.n_vertices), -1);
  Clusters out;
  out.member.resize(static_cast<std::size_t>(t.n_vertices));
  for (int v = 0; v < t.n_vertices; ++v) {
    int r = uf.find(v);
    if (id[r] < 0) {
      id[r] = static_cast<int>(out.groups.size());
      out.groups.emplace_back();
    }
    out.member[v] = id[r];
    out.groups[static_cast<std::size_t>(id[r])].push_back(v);
  }
  return out;
}

}  // namespace

AcapConsistency::AcapConsistency(const MeshTopology& topo, ConsistencyOptions opt)
    : topo_(topo), opt_(opt) {}

double AcapConsistency::axis_agreement(const std::vector<AxisAngle>& rot,
                                       const std::vector<int>& o) const {
  double a = 0;
  for (const auto& [i, j] : topo_.edges) a += sgn(rot[i].axis.dot(rot[j].axis)) * o[i] * o[j];
  return a;
}

double AcapConsistency::angle_spread(const std::vector<double>& phi) const {
  double c = 0;
  for (const auto& [i, j] : topo_.edges) c += (phi[i] - phi[j]) * (phi[i] - phi[j]);
  return c;
}

ConsistencyReport AcapConsistency::solve(const std::vector<AxisAngle>& rot,
                                         const std::vector<Eigen::Vector3d>* previous,
                                         std::vector<Eigen::Vector3d>& r) const {
  const int n = topo_.n_vertices;
  const auto& off = topo_.ring_offsets;
  const auto& nbr = topo_.ring_vertices;
  const auto& ring_edge = topo_.ring_edges;
  ConsistencyReport rep;

  // s_e = sign(ω_i·ω_j) per edge.
  std::vector<int> s(topo_.edges.size());
  for (std::size_t e = 0; e < s.size(); ++e)
    s[e] = sgn(rot[topo_.edges[e][0]].axis.dot(rot[topo_.edges[e][1]].axis));

  // --- 1. axis signs: initialisation (temporal prior where it decides, BFS elsewhere)
  std::vector<int> o(static_cast<std::size_t>(n), 0);
  if (previous) {
    for (int i = 0; i < n; ++i) {
      double d = rot[i].axis.dot((*previous)[static_cast<std::size_t>(i)]);
      if (std::abs(d) > 1e-9) o[i] = d > 0 ? 1 : -1;
    }
  }
  {
    std::queue<int> q;
    for (int i = 0; i < n; ++i)
      if (o[i]) q.push(i);
    auto bfs = [&] {
      while (!q.empty()) {
        int i = q.front();
        q.pop();
        for (int k = off[i]; k < off[i + 1]; ++k) {
          int j = nbr[k];
          if (o[j]) continue;
          o[j] = s[ring_edge[k]] < 0 ? -o[i] : o[i];
          q.push(j);
        }
      }
    };
    bfs();  // from the vertices the prior decided
    auto seed = [&](int root) {
      if (root < 0 || root >= n || o[root]) return;
      o[root] = 1;
      q.push(root);
      bfs();
    };
    seed(opt_.root);
    for (int i = 0; i < n; ++i) seed(i);  // other components: their smallest vertex is the root
  }
  rep.axis_before = axis_agreement(rot, o);

  // --- improvement of A(o): single flips, then cluster flips, while anything improves
  for (int sweep = 0; sweep < opt_.max_sweeps; ++sweep) {
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      int h = 0;
      for (int k = off[i]; k < off[i + 1]; ++k) h += s[ring_edge[k]] * o[nbr[k]];
      if (o[i] * h < 0) {
        o[i] = -o[i];
        changed = true;
      }
    }
    auto [groups, member] = clusters(topo_, [&](std::size_t e) {
      return s[e] * o[topo_.edges[e][0]] * o[topo_.edges[e][1]] > 0;
    });
    if (groups.size() > 1) {
      for (std::size_t c = 0; c < groups.size(); ++c) {
        int boundary = 0;  // Σ s o_i o_j over edges leaving the cluster, with the current o
        for (int i : groups[c])
          for (int k = off[i]; k < off[i + 1]; ++k)
            if (member[nbr[k]] != static_cast<int>(c))
              boundary += s[ring_edge[k]] * o[i] * o[nbr[k]];
        if (boundary < 0) {
          for (int i : groups[c]) o[i] = -o[i];
          changed = true;
        }
      }
    }
    rep.sweeps = std::max(rep.sweeps, sweep + 1);
    if (!changed) break;
  }
  // A(o) = A(−o): on a first frame keep the root's own axis.
  if (!previous && opt_.root >= 0 && opt_.root < n && o[opt_.root] < 0)
    for (auto& x : o) x = -x;
  rep.axis_after = axis_agreement(rot, o);

  // --- 2. turns: φ_i = θ'_i + 2πk_i
  std::vector<double> base(static_cast<std::size_t>(n));           // θ'_i
  std::vector<Eigen::Vector3d> axis(static_cast<std::size_t>(n));  // o_i ω_i
  for (int i = 0; i < n; ++i) {
    base[i] = o[i] > 0 ? rot[i].angle : kTwoPi - rot[i].angle;
    axis[i] = o[i] * rot[i].axis;
  }
  std::vector<long> k(static_cast<std::size_t>(n), 0);
  std::vector<char> set(static_cast<std::size_t>(n), 0);
  if (previous) {
    // The turn that puts r_i closest to the prior: its projection on the axis.
    for (int i = 0; i < n; ++i) {
      double target = axis[i].dot((*previous)[static_cast<std::size_t>(i)]);
      k[i] = std::lround((target - base[i]) / kTwoPi);
      set[i] = 1;
    }
  } else {
    std::queue<int> q;
    auto bfs_from = [&](int root) {
      set[root] = 1;
      q.push(root);
      while (!q.empty()) {
        int i = q.front();
        q.pop();
        double phi_i = base[i] + kTwoPi * static_cast<double>(k[i]);
        for (int kk = off[i]; kk < off[i + 1]; ++kk) {
          int j = nbr[kk];
          if (set[j]) continue;
          k[j] = std::lround((phi_i - base[j]) / kTwoPi);
          set[j] = 1;
          q.push(j);
        }
      }
    };
    if (opt_.root >= 0 && opt_.root < n) bfs_from(opt_.root);
    for (int i = 0; i < n; ++i)
      if (!set[i]) bfs_from(i);
  }
  std::vector<double> phi(static_cast<std::size_t>(n));
  auto refresh = [&](int i) { phi[i] = base[i] + kTwoPi * static_cast<double>(k[i]); };
  for (int i = 0; i < n; ++i) refresh(i);
  rep.angle_before = angle_spread(phi);

  // --- improvement of C(k): single-vertex optimal turns, then cluster shifts by ±1
  for (int sweep = 0; sweep < opt_.max_sweeps; ++sweep) {
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      int d = topo_.degree(i);
      if (!d) continue;
      double mean = 0;
      for (int kk = off[i]; kk < off[i + 1]; ++kk) mean += phi[nbr[kk]];
      mean /= d;
      long best = std::lround((mean - base[i]) / kTwoPi);
      if (best == k[i]) continue;
      double now = base[i] + kTwoPi * static_cast<double>(best), delta = 0;
      for (int kk = off[i]; kk < off[i + 1]; ++kk) {
        double pj = phi[nbr[kk]];
        delta += (now - pj) * (now - pj) - (phi[i] - pj) * (phi[i] - pj);
      }
      if (delta < -1e-12) {
        k[i] = best;
        refresh(i);
        changed = true;
      }
    }
    auto [groups, member] = clusters(topo_, [&](std::size_t e) {
      return std::abs(phi[topo_.edges[e][0]] - phi[topo_.edges[e][1]]) < std::numbers::pi;
    });
    if (groups.size() > 1) {
      for (std::size_t c = 0; c < groups.size(); ++c) {
        double sum_d = 0;
        int count = 0;
        for (int i : groups[c])
          for (int kk = off[i]; kk < off[i + 1]; ++kk)
            if (member[nbr[kk]] != static_cast<int>(c)) {
              sum_d += phi[i] - phi[nbr[kk]];
              ++count;
            }
        // Shifting the cluster by δ = ±1 changes C by Σ (d + 2πδ)² − d² = 4πδ Σd + 4π² count.
        const double sq = kTwoPi * kTwoPi * count;
        double up = 2 * kTwoPi * sum_d + sq, down = -2 * kTwoPi * sum_d + sq;
        int shift = up < down ? 1 : -1;
        if (std::min(up, down) < -1e-9) {
          for (int i : groups[c]) {
            k[i] += shift;
            refresh(i);
          }
          changed = true;
        }
      }
    }
    rep.sweeps = std::max(rep.sweeps, sweep + 1);
    if (!changed) break;
  }
  rep.angle_after = angle_spread(phi);

  // --- normalisation: a global turn c (C unchanged)
  long c = 0;
  if (previous) {
    double num = 0, den = 0;
    for (int i = 0; i < n; ++i) {
      num += axis[i].dot((*previous)[static_cast<std::size_t>(i)] - axis[i] * phi[i]);
      den += axis[i].squaredNorm();
    }
    if (den > 0) c = std::lround(num / (kTwoPi * den));
  } else if (opt_.root >= 0 && opt_.root < n) {
    c = -std::lround(phi[opt_.root] / kTwoPi);
  }
  r.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) r[i] = axis[i] * (phi[i] + kTwoPi * static_cast<double>(c));
  return rep;
}

}  // namespace df::geometry
