// As-consistent-as-possible rotation vectors (SPEC §4.5, Gao et al. TVCG 2019).
//
// Each vertex's rotation (ω_i, θ_i), θ_i ∈ [0, π], may be written with the flipped axis
// (−ω_i, 2π − θ_i) (sign o_i = −1) and any number of extra turns 2πk_i. We choose
//   1. signs o maximising the axis agreement  A(o) = Σ_(i,j)∈E sign(ω_i·ω_j) o_i o_j   (Ising),
//   then
//   2. turns k minimising the angle spread    C(k) = Σ_(i,j)∈E (φ_i − φ_j)²,
//      φ_i = θ'_i + 2πk_i, θ'_i = θ_i (o_i = 1) or 2π − θ_i (o_i = −1),
// and store r_i = o_i ω_i φ_i. The authors solve both exactly with Gurobi. Here:
//   * initialisation — first frame of a sequence: BFS from a root (a child's axis is flipped
//     if it opposes its parent's; its k puts it within π of its parent); later frames: the
//     previous frame's r_i is the prior (axis sign and turn closest to it), so a rotation that
//     grows past π keeps growing instead of jumping;
//   * improvement — alternate single-vertex moves and cluster moves (flip / shift a connected
//     cluster of mutually consistent vertices as one) while any move strictly improves the
//     objective, at most `max_sweeps` sweeps. Both objectives therefore never get worse than
//     their initialisation. Everything is sequential in a fixed order: deterministic.
//   * normalisation — first frame: the root's angle is put in (−π, π] (its k is 0);
//     later frames: the global turn (all k shifted alike, C unchanged) closest to the prior.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geometry/mesh_topology.h"
#include "geometry/rotation.h"

namespace df::geometry {

struct ConsistencyOptions {
  int root = 0;          ///< root vertex of the BFS on a sequence's first frame
  int max_sweeps = 200;  ///< bound on improvement sweeps per objective (deterministic)
};

struct ConsistencyReport {
  double axis_before = 0, axis_after = 0;    ///< A(o) at initialisation / after (higher is better)
  double angle_before = 0, angle_after = 0;  ///< C(k) at initialisation / after (lower is better)
  int sweeps = 0;
};

class AcapConsistency {
 public:
  AcapConsistency(const MeshTopology& topo, ConsistencyOptions opt = {});

  /// @param rot       per-vertex principal axis-angle of one frame (rotation_log)
  /// @param previous  the previous frame's r of the same sequence, or nullptr for a first frame
  /// @param r         out: per-vertex consistent rotation vectors θω
  ConsistencyReport solve(const std::vector<AxisAngle>& rot,
                          const std::vector<Eigen::Vector3d>* previous,
                          std::vector<Eigen::Vector3d>& r) const;

  /// The objectives, for tests and reports.
  double axis_agreement(const std::vector<AxisAngle>& rot, const std::vector<int>& o) const;
  double angle_spread(const std::vector<double>& phi) const;

 private:
  std::vector<int> initial_signs(const std::vector<AxisAngle>& rot,
                                 const std::vector<Eigen::Vector3d>* previous,
                                 const std::vector<int>& s) const;
  void improve_signs(const std::vector<int>& s, std::vector<int>& o, ConsistencyReport& rep) const;
  std::vector<long> initial_turns(const std::vector<double>& base,
                                  const std::vector<Eigen::Vector3d>& axis,
                                  const std::vector<Eigen::Vector3d>* previous) const;
  void improve_turns(const std::vector<double>& base, std::vector<long>& k,
                     std::vector<double>& phi, ConsistencyReport& rep) const;
  long global_turn(const std::vector<Eigen::Vector3d>& axis, const std::vector<double>& phi,
                   const std::vector<Eigen::Vector3d>* previous) const;

  const MeshTopology& topo_;
  ConsistencyOptions opt_;
};

}  // namespace df::geometry
