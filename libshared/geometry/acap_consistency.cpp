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

// Breadth-first over the one-rings from the vertices queued: each vertex not yet `known` is
// reached from the first queued neighbour, follow(i, j, ring index of j in i's ring) sets it.
template <class Known, class Follow>
void spread(const MeshTopology& t, std::queue<int>& q, Known known, Follow follow) {
  while (!q.empty()) {
    const int i = q.front();
    q.pop();
    for (int k = t.ring_offsets[i]; k < t.ring_offsets[i + 1]; ++k) {
      const int j = t.ring_vertices[k];
      if (known(j)) continue;
      follow(i, j, k);
      q.push(j);
    }
  }
}

// spread() from the root (when it is a vertex), then from the smallest vertex of each connected
// part not reached yet; start(v) makes a root known.
template <class Known, class Start, class Follow>
void spread_from_roots(const MeshTopology& t, int root, Known known, Start start, Follow follow) {
  std::queue<int> q;
  auto from = [&](int v) {
    if (v < 0 || v >= t.n_vertices || known(v)) return;
    start(v);
    q.push(v);
    spread(t, q, known, follow);
  };
  from(root);
  for (int v = 0; v < t.n_vertices; ++v) from(v);
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

// The two steps of the paper's §3 (Gao et al. 2019): axis signs o_i maximising A(o) = Σ s_e o_i
// o_j, then turns k_i minimising C(k) = Σ (φ_i − φ_j)², φ_i = θ'_i + 2πk_i; each step an
// initialisation (the previous frame's r where it decides, a breadth-first spread from the root
// elsewhere) and a local improvement; then a global turn.
ConsistencyReport AcapConsistency::solve(const std::vector<AxisAngle>& rot,
                                         const std::vector<Eigen::Vector3d>* previous,
                                         std::vector<Eigen::Vector3d>& r) const {
  const int n = topo_.n_vertices;
  ConsistencyReport rep;
  // s_e = sign(ω_i·ω_j) per edge.
  std::vector<int> s(topo_.edges.size());
  for (std::size_t e = 0; e < s.size(); ++e)
    s[e] = sgn(rot[topo_.edges[e][0]].axis.dot(rot[topo_.edges[e][1]].axis));

  std::vector<int> o = initial_signs(rot, previous, s);
  rep.axis_before = axis_agreement(rot, o);
  improve_signs(s, o, rep);
  // A(o) = A(−o): on a first frame keep the root's own axis.
  if (!previous && opt_.root >= 0 && opt_.root < n && o[opt_.root] < 0)
    for (auto& x : o) x = -x;
  rep.axis_after = axis_agreement(rot, o);

  std::vector<double> base(static_cast<std::size_t>(n));           // θ'_i
  std::vector<Eigen::Vector3d> axis(static_cast<std::size_t>(n));  // o_i ω_i
  for (int i = 0; i < n; ++i) {
    base[i] = o[i] > 0 ? rot[i].angle : kTwoPi - rot[i].angle;
    axis[i] = o[i] * rot[i].axis;
  }
  std::vector<long> k = initial_turns(base, axis, previous);
  std::vector<double> phi(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) phi[i] = base[i] + kTwoPi * static_cast<double>(k[i]);
  rep.angle_before = angle_spread(phi);
  improve_turns(base, k, phi, rep);
  rep.angle_after = angle_spread(phi);

  const long c = global_turn(axis, phi, previous);
  r.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) r[i] = axis[i] * (phi[i] + kTwoPi * static_cast<double>(c));
  return rep;
}

// The signs' start: the temporal prior where it decides, spread from there by s_e; then from the
// root; then from each other connected part's smallest vertex.
std::vector<int> AcapConsistency::initial_signs(const std::vector<AxisAngle>& rot,
                                                const std::vector<Eigen::Vector3d>* previous,
                                                const std::vector<int>& s) const {
  const int n = topo_.n_vertices;
  std::vector<int> o(static_cast<std::size_t>(n), 0);
  if (previous) {
    for (int i = 0; i < n; ++i) {
      double d = rot[i].axis.dot((*previous)[static_cast<std::size_t>(i)]);
      if (std::abs(d) > 1e-9) o[i] = d > 0 ? 1 : -1;
    }
  }
  std::queue<int> q;
  for (int i = 0; i < n; ++i)
    if (o[i]) q.push(i);
  const auto known = [&](int j) { return o[j] != 0; };
  const auto follow = [&](int i, int j, int ring) {
    o[j] = s[topo_.ring_edges[ring]] < 0 ? -o[i] : o[i];
  };
  spread(topo_, q, known, follow);  // from the vertices the prior decided
  spread_from_roots(
      topo_, opt_.root, known, [&](int root) { o[root] = 1; }, follow);
  return o;
}

// Single flips, then flips of whole clusters (vertices joined by agreeing edges), while anything
// improves A(o).
void AcapConsistency::improve_signs(const std::vector<int>& s, std::vector<int>& o,
                                    ConsistencyReport& rep) const {
  const int n = topo_.n_vertices;
  const auto& off = topo_.ring_offsets;
  const auto& nbr = topo_.ring_vertices;
  const auto& ring_edge = topo_.ring_edges;
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
}

// The turns' start: with a prior, the turn that puts r_i closest to it (its projection on the
// axis); without, each neighbour takes the turn nearest the vertex it was reached from.
std::vector<long> AcapConsistency::initial_turns(
    const std::vector<double>& base, const std::vector<Eigen::Vector3d>& axis,
    const std::vector<Eigen::Vector3d>* previous) const {
  const int n = topo_.n_vertices;
  std::vector<long> k(static_cast<std::size_t>(n), 0);
  if (previous) {
    for (int i = 0; i < n; ++i) {
      double target = axis[i].dot((*previous)[static_cast<std::size_t>(i)]);
      k[i] = std::lround((target - base[i]) / kTwoPi);
    }
    return k;
  }
  std::vector<char> set(static_cast<std::size_t>(n), 0);
  spread_from_roots(
      topo_, opt_.root, [&](int j) { return set[j] != 0; }, [&](int root) { set[root] = 1; },
      [&](int i, int j, int) {
        const double phi_i = base[i] + kTwoPi * static_cast<double>(k[i]);
        k[j] = std::lround((phi_i - base[j]) / kTwoPi);
        set[j] = 1;
      });
  return k;
}

// Single-vertex optimal turns, then shifts of whole clusters (vertices joined by edges whose
// angles differ by less than π) by ±1, while anything improves C(k).
void AcapConsistency::improve_turns(const std::vector<double>& base, std::vector<long>& k,
                                    std::vector<double>& phi, ConsistencyReport& rep) const {
  const int n = topo_.n_vertices;
  const auto& off = topo_.ring_offsets;
  const auto& nbr = topo_.ring_vertices;
  auto refresh = [&](int i) { phi[i] = base[i] + kTwoPi * static_cast<double>(k[i]); };
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
}

// The global turn c (C unchanged): the one nearest the prior, or the root's angle in (−π, π].
long AcapConsistency::global_turn(const std::vector<Eigen::Vector3d>& axis,
                                  const std::vector<double>& phi,
                                  const std::vector<Eigen::Vector3d>* previous) const {
  const int n = topo_.n_vertices;
  if (previous) {
    double num = 0, den = 0;
    for (int i = 0; i < n; ++i) {
      num += axis[i].dot((*previous)[static_cast<std::size_t>(i)] - axis[i] * phi[i]);
      den += axis[i].squaredNorm();
    }
    return den > 0 ? std::lround(num / (kTwoPi * den)) : 0;
  }
  if (opt_.root >= 0 && opt_.root < n) return -std::lround(phi[opt_.root] / kTwoPi);
  return 0;
}

}  // namespace df::geometry
