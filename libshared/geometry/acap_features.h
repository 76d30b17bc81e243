// ACAP features of mesh frames (SPEC §4): per vertex 9 numbers, r = (L01, L02, L12) of the
// skew matrix L = log R (L01 = −θω_z, L02 = θω_y, L12 = −θω_x) then
// s = (S00, S01, S02, S11, S12, S22) of the stretch S, where T = R S is the polar
// decomposition of the deformation gradient from the reference to the frame. The reference
// itself has r = 0, s = (1,0,0,1,0,1).
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "core/feature_normalization.h"
#include "core/mesh.h"
#include "geometry/acap_consistency.h"
#include "geometry/deformation_gradient.h"
#include "geometry/mesh_topology.h"
#include "geometry/rotation.h"

namespace df::geometry {

inline constexpr int kFeatureDims = kAcapFeatureDims;

/// The rotations (principal axis-angle) and stretches of one frame, before consistency.
struct FrameDecomposition {
  std::vector<AxisAngle> rotation;
  std::vector<Eigen::Matrix3d> stretch;
};

/// Template-side data shared by all frames: topology, weights, the deformation-gradient
/// solver and the consistency solver. decompose() is const and thread-safe.
class AcapFeatureExtractor {
 public:
  /// @param reference  #V by 3 reference positions; @param faces  #F by 3
  AcapFeatureExtractor(const Vertices& reference, const Faces& faces, ConsistencyOptions opt = {});

  const MeshTopology& topology() const { return topo_; }
  const std::vector<double>& weights() const { return gradients_->weights(); }
  int n_vertices() const { return topo_.n_vertices; }

  /// T → (R, S) → principal log of R, for every vertex of a frame (#V by 3).
  void decompose(const Vertices& frame, FrameDecomposition& out) const;

  /// Consistent rotation vectors of a decomposed frame (`previous`: the previous frame of the
  /// same sequence, or nullptr).
  ConsistencyReport make_consistent(const FrameDecomposition& d,
                                    const std::vector<Eigen::Vector3d>* previous,
                                    std::vector<Eigen::Vector3d>& r) const;

 private:
  MeshTopology topo_;
  std::unique_ptr<DeformationGradientSolver> gradients_;
  AcapConsistency consistency_;
};

/// The in-order part of computing features of a sequence (obj2acap's, and sequence_features'):
/// each decomposed frame's rotation logs made consistent in space and with the previous frame
/// of its sequence (`consistency`; principal logs otherwise), then packed.
class FeatureSequence {
 public:
  FeatureSequence(const AcapFeatureExtractor& ex, bool consistency)
      : ex_(ex), consistency_(consistency) {}
  /// Writes the frame's 9 features per vertex to `out`; `start`: the first frame of a sequence
  /// (no temporal prior). The consistency solve's report (zeros without consistency).
  ConsistencyReport add(const FrameDecomposition& d, bool start, double* out);

 private:
  const AcapFeatureExtractor& ex_;
  bool consistency_;
  std::vector<Eigen::Vector3d> previous_, r_;
};

/// Raw features [frames][9V] of frames in time order, as obj2acap computes them: each frame
/// decomposed (in parallel), then a FeatureSequence (`starts[f]` marks frame f as a sequence's
/// first; frame 0 always is). InvalidInput naming the frame when one has another vertex count.
std::vector<double> sequence_features(const AcapFeatureExtractor& ex,
                                      const std::vector<Vertices>& frames,
                                      const std::vector<char>& starts, bool consistency);

/// Writes the 9 features of each vertex (row-major #V by 9) from rotation vectors and stretches.
void pack_features(const std::vector<Eigen::Vector3d>& r, const std::vector<Eigen::Matrix3d>& S,
                   double* out);

/// Reads vertex i's features back: the rotation vector r = θω and the stretch S.
void unpack_features(const double* f9, Eigen::Vector3d& r, Eigen::Matrix3d& S);

/// Per-vertex principal-log rotation vectors (no consistency): what a naive per-vertex log
/// gives, for comparisons.
std::vector<Eigen::Vector3d> principal_rotation_vectors(const FrameDecomposition& d);

// --- normalization to [−0.95, 0.95] for tanh networks (SPEC §4.7)

// The numbers themselves are core/feature_normalization.h's (io/acap_file.h writes them).
using Normalization = FeatureNormalization;

/// The reference's own features (r = 0, S = I), normalized by `nz` when given: X_r of the MSAE
/// paper, the zero of "deformation".
std::array<double, kFeatureDims> identity_features(const Normalization* nz = nullptr);

/// Running minima/maxima of features, merged into a Normalization at the end.
class NormalizationBuilder {
 public:
  explicit NormalizationBuilder(NormalizationMode mode) : mode_(mode) {
    lo_.fill(1e300), hi_.fill(-1e300);
  }
  /// @param features  n rows of 9 (row-major)
  void add(const double* features, std::size_t rows);
  void merge(const NormalizationBuilder& other);
  /// group: one range over all r entries, one over all s entries; per-dim: each dimension;
  /// every range widened by 1e-6 on both sides.
  Normalization finish() const;

 private:
  NormalizationMode mode_;
  std::array<double, kFeatureDims> lo_, hi_;
};

}  // namespace df::geometry
