// Edges and one-rings of a triangle mesh, as flat arrays (CSR), built once per template.
#pragma once

#include <array>
#include <vector>

#include "core/mesh.h"

namespace df::geometry {

struct MeshTopology {
  int n_vertices = 0;
  /// Unique undirected edges (i < j), sorted.
  std::vector<std::array<int, 2>> edges;
  /// One-ring of vertex i: ring_vertices[ring_offsets[i] .. ring_offsets[i+1]), sorted by vertex,
  /// with the index of the connecting edge in ring_edges at the same position.
  std::vector<int> ring_offsets, ring_vertices, ring_edges;

  int degree(int i) const { return ring_offsets[i + 1] - ring_offsets[i]; }
};

/// @param F  #F by 3 triangles; @param n_vertices  #V (vertices in no face get an empty ring)
MeshTopology mesh_topology(const Faces& F, int n_vertices);

/// The connected component of every vertex: `first`'s component is 0, the others are numbered
/// in order of their lowest vertex. @param count  receives the number of components
std::vector<int> connected_components(const MeshTopology& topo, int first, int* count);

}  // namespace df::geometry
