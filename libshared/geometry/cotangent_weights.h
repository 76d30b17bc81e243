// Cotangent edge weights mapped to positive least-squares weights (SPEC §4.1):
//   c_ij = ½(cot α_ij + cot β_ij)   (one term on a boundary edge),
//   w_ij = sqrt(sexp(c_ij)),  sexp(x) = eˣ for x ≤ 0, 1 + x for x > 0,
//   a NaN or > 1e5 weight, or a non-finite cotangent (degenerate triangles), becomes 1.
// The mapping is what the ACAP authors' public C++ code does: obtuse triangles never give
// negative weights.
#pragma once

#include <vector>

#include "geometry/mesh_topology.h"

namespace df::geometry {

/// Raw cotangent sums c_ij per edge of `topo` (may be negative, NaN on degenerate faces).
/// @param V  #V by 3 positions of the reference mesh
std::vector<double> cotangent_sums(const Vertices& V, const Faces& F, const MeshTopology& topo);

/// The positive weight w = sqrt(sexp(c)) of one cotangent sum, with the NaN/1e5 rule.
double positive_weight(double c);

/// w_ij per edge of `topo`.
std::vector<double> cotangent_weights(const Vertices& V, const Faces& F, const MeshTopology& topo);

}  // namespace df::geometry
