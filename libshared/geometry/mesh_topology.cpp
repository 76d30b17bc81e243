#include "geometry/mesh_topology.h"

#include <algorithm>

namespace df::geometry {

MeshTopology mesh_topology(const Faces& F, int n_vertices) {
  MeshTopology t;
  t.n_vertices = n_vertices;
  t.edges.reserve(static_cast<std::size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a == b) continue;
      t.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(t.edges.begin(), t.edges.end());
  t.edges.erase(std::unique(t.edges.begin(), t.edges.end()), t.edges.end());

  std::vector<int> count(static_cast<std::size_t>(n_vertices) + 1, 0);
  for (const auto& e : t.edges) {
    ++count[e[0] + 1];
    ++count[e[1] + 1];
  }
  t.ring_offsets.assign(count.size(), 0);
  for (std::size_t i = 1; i < count.size(); ++i)
    t.ring_offsets[i] = t.ring_offsets[i - 1] + count[i];
  t.ring_vertices.resize(static_cast<std::size_t>(t.ring_offsets.back()));
  t.ring_edges.resize(t.ring_vertices.size());
  std::vector<int> fill(t.ring_offsets.begin(), t.ring_offsets.end() - 1);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    auto [a, b] = t.edges[e];
    t.ring_vertices[fill[a]] = b;
    t.ring_edges[fill[a]++] = static_cast<int>(e);
    t.ring_vertices[fill[b]] = a;
    t.ring_edges[fill[b]++] = static_cast<int>(e);
  }
  // Edges are sorted by (i, j), so each ring is already sorted by neighbour for i's larger
  // neighbours; sort every ring to make it independent of edge order.
  for (int i = 0; i < n_vertices; ++i) {
    int b = t.ring_offsets[i], e = t.ring_offsets[i + 1];
    std::vector<std::pair<int, int>> ring;
    for (int k = b; k < e; ++k) ring.emplace_back(t.ring_vertices[k], t.ring_edges[k]);
    std::sort(ring.begin(), ring.end());
    for (int k = b; k < e; ++k) std::tie(t.ring_vertices[k], t.ring_edges[k]) = ring[k - b];
  }
  return t;
}

std::vector<int> connected_components(const MeshTopology& topo, int first, int* count) {
  std::vector<int> component(static_cast<std::size_t>(topo.n_vertices), -1);
  int n = 0;
  auto flood = [&](int seed) {
    std::vector<int> stack{seed};
    component[static_cast<std::size_t>(seed)] = n;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      for (int k = topo.ring_offsets[i]; k < topo.ring_offsets[i + 1]; ++k) {
        const int j = topo.ring_vertices[static_cast<std::size_t>(k)];
        if (component[static_cast<std::size_t>(j)] < 0) {
          component[static_cast<std::size_t>(j)] = n;
          stack.push_back(j);
        }
      }
    }
    ++n;
  };
  if (topo.n_vertices) flood(first);
  for (int i = 0; i < topo.n_vertices; ++i)
    if (component[static_cast<std::size_t>(i)] < 0) flood(i);
  if (count) *count = n;
  return component;
}

}  // namespace df::geometry
