// Geodesic distances on a triangle mesh by the heat method (Crane, Weischedel & Wardetzky,
// "Geodesics in Heat", ACM TOG 2013): diffuse heat from the source for a short time t = h²
// (h = mean edge length), normalise the negated gradient of the heat per face into a unit field,
// and solve a Poisson problem with its divergence. The cotangent Laplacian and the heat operator
// are factored once (sparse LDLᵀ); each source then costs two back-substitutions, so distances
// from many sources run in parallel. On meshes with a boundary the heat is the average of the
// Neumann and Dirichlet solutions (§3.2 of the paper), which keeps the isolines straight near the
// boundary. Approximate: errors of a few percent of the distance on coarse meshes, shrinking with
// resolution (tests/unit/geometry/test_geodesic.cpp measures them on a plane and a sphere).
// Used by MSAE (SPEC §7): the mask around each component's centre needs d(i, c_k) / max d.
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

#include "core/mesh.h"

namespace df::geometry {

class HeatMethodDistance {
 public:
  /// Factors the operators of the mesh.
  /// @param V  #V by 3 positions; @param F  #F by 3 triangles (consistently oriented)
  /// @param t_factor  heat time = t_factor · (mean edge length)² (the paper's m = 1)
  HeatMethodDistance(const Vertices& V, const Faces& F, double t_factor = 1.0);
  ~HeatMethodDistance();
  HeatMethodDistance(const HeatMethodDistance&) = delete;
  HeatMethodDistance& operator=(const HeatMethodDistance&) = delete;

  /// #V distances (mesh units) from `source`, 0 at the source; +inf on other connected parts.
  /// Thread-safe: several sources may be solved at once.
  Eigen::VectorXd from(int source) const;
  /// The mesh's connected parts (edge-connected vertex sets).
  int parts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Normalized geodesic distances from chosen sources, solved on demand and kept: MSAE's sparsity
/// masks need d(i, c_k) only from the current component centres c_k, and the all-pairs matrix of
/// a 12,500-vertex mesh would take 600 MB. Rows are divided by the mesh's diameter, estimated by
/// farthest-point sweeps (from vertex 0 to its farthest vertex a, from a to its farthest b, ...
/// until the distance stops growing; exact on a plane or a sphere up to the heat method's error).
/// A vertex on another connected part than the source is as far as the straight line between
/// them (a mesh of separate pieces — a character's eyes, a bird's feathers — keeps its pieces
/// near each other instead of at the diameter; the sweeps use the same distances). Deterministic: a
/// row does not depend on the thread count or on which rows were solved before.
class GeodesicRows {
 public:
  GeodesicRows(const Vertices& V, const Faces& F);
  /// Restores a provider whose diameter is known (from a model file) without the sweeps.
  GeodesicRows(const Vertices& V, const Faces& F, double diameter);

  double diameter() const { return diameter_; }
  /// The mesh's connected parts (1: the bridging changes nothing).
  int parts() const { return heat_.parts(); }
  /// Solves the rows of `sources` not yet kept (in parallel); afterwards row(s) is cheap. Drops
  /// every kept row first when keeping them all would pass ~256 MB.
  void prepare(const std::vector<int>& sources);
  /// The normalized distances from `source` (#V, in [0, 1]); solved now when not prepared.
  const Eigen::VectorXf& row(int source);
  /// Adds a row solved elsewhere (e.g. read back from a model file).
  void keep(int source, Eigen::VectorXf row) { rows_[source] = std::move(row); }

 private:
  /// Mesh units from `source`: geodesic on its part, straight-line to the other parts.
  Eigen::VectorXd bridged(int source) const;
  Eigen::VectorXf normalized(const Eigen::VectorXd& d) const;

  HeatMethodDistance heat_;
  Vertices vertices_;
  Eigen::Index n_vertices_;
  double diameter_ = 0;
  std::map<int, Eigen::VectorXf> rows_;
};

}  // namespace df::geometry
