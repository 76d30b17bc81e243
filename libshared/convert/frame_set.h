// The frames of one input that a consumer of results (eval-metrics, render-mesh) works on:
// an acap .h5 file (stored positions and/or features, gen-bdlstm's frame pairing) or mesh files
// (a directory, @LIST or files, read as obj2acap reads them). Positions that are not stored are
// reconstructed from the features on demand, with the exact solver factored once.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/acap_features.h"
#include "io/mesh_io.h"

namespace df::convert {

struct FrameSet {
  std::string path;
  Mesh tmpl;                           ///< the template (reference) mesh
  std::vector<std::int64_t> offsets;   ///< [S+1] sequence offsets
  std::vector<std::string> sequences;  ///< [S] sequence names
  std::vector<std::string> names;      ///< [N] frame names
  /// [N] #V by 3 positions (mesh units); an entry is empty until stored or reconstructed
  std::vector<Vertices> positions;
  bool positions_stored = false;
  Eigen::MatrixXd raw;  ///< [N, 9V] raw features; 0 rows if none
  std::optional<geometry::Normalization> normalization;
  std::vector<std::int64_t> source;  ///< gen-bdlstm's data frame of each frame, if present
  std::vector<std::int32_t> step;    ///< gen-bdlstm's steps after the last given frame, if present
  std::size_t size() const { return static_cast<std::size_t>(offsets.back()); }
  std::size_t vertices() const { return static_cast<std::size_t>(tmpl.vertices.rows()); }
  /// Length of the template's bounding-box diagonal (mesh units).
  double diagonal() const;
};

/// Reads an acap .h5 file (validated as such) or mesh files. Throws InvalidInput / IOError.
FrameSet read_frame_set(const std::string& path);

/// Fills positions[i] for the given frames (all when `frames` is null) that have none, from the
/// features: InvalidInput if the input has neither positions nor features. Frames in parallel.
void reconstruct(FrameSet& fs, const std::vector<std::size_t>* frames = nullptr);

/// Frame i's features in the normalized space of `nz` (raw when none): what the networks see.
Eigen::VectorXd normalized_features(const FrameSet& fs, std::size_t i,
                                    const std::optional<geometry::Normalization>& nz);

}  // namespace df::convert
