#include "geometry/cotangent_weights.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace df::geometry {
namespace {
int edge_index(const MeshTopology& t, int a, int b) {
  int lo = t.ring_offsets[a], hi = t.ring_offsets[a + 1];
  auto it = std::lower_bound(t.ring_vertices.begin() + lo, t.ring_vertices.begin() + hi, b);
  return t.ring_edges[static_cast<std::size_t>(it - t.ring_vertices.begin())];
}
}  // namespace

std::vector<double> cotangent_sums(const Vertices& V, const Faces& F, const MeshTopology& topo) {
  std::vector<double> c(topo.edges.size(), 0.0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      int o = F(f, k), a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);  // angle at o, opposite (a,b)
      if (a == b || a == o || b == o) continue;
      Eigen::Vector3d u = V.row(a) - V.row(o), v = V.row(b) - V.row(o);
      double cot = u.dot(v) / u.cross(v).norm();  // inf/NaN on a degenerate face
      c[static_cast<std::size_t>(edge_index(topo, a, b))] += 0.5 * cot;
    }
  }
  return c;
}

double positive_weight(double c) {
  if (!std::isfinite(c)) return 1.0;  // a degenerate triangle's ±inf/NaN cotangent
  double s = c <= 0 ? std::exp(c) : 1.0 + c;
  double w = std::sqrt(s);
  if (!std::isfinite(w) || w > 1e5) return 1.0;
  return w;
}

std::vector<double> cotangent_weights(const Vertices& V, const Faces& F, const MeshTopology& topo) {
  std::vector<double> w = cotangent_sums(V, F, topo);
  std::transform(w.begin(), w.end(), w.begin(), positive_weight);
  return w;
}

}  // namespace df::geometry
