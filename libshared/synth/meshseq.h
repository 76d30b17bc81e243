// Procedural mesh sequences with known structure, so that the project runs with no downloaded
// data and its methods can be scored against ground truth:
//   finger  a capped cylinder bending (up to amplitude x 90 deg) and twisting about its axis
//           (--twist degrees at the tip; past 180 and 360 to test ACAP consistency)
//   flag    a cloth grid pinned at x = 0 with travelling waves
//   bumps   a grid surface with planted smooth localized deformations at two scales (2 coarse,
//           4 fine regions by default); each frame activates every region with a random weight,
//           and the regions, their scales, centres and weights are recorded (ground truth for
//           MSAE)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "io/mesh_io.h"

namespace df::synth {

enum class MeshSeqKind { finger, flag, bumps };
MeshSeqKind mesh_seq_kind_from_name(const std::string& name);
const char* mesh_seq_kind_name(MeshSeqKind k);

/// The most fine regions bumps plants (more do not fit the surface apart at any seed tried).
constexpr int kMaxFineRegions = 16;

struct MeshSeqParams {
  MeshSeqKind kind = MeshSeqKind::finger;
  int frames = 100;           ///< frames per sequence
  int sequences = 1;          ///< independent variations, stored one after another
  int resolution = 16;        ///< finger: segments around (4x rings along); grids: quads per side
  double amplitude = 1.0;     ///< deformation scale (finger bend: amplitude x 90 deg)
  double twist_degrees = 90;  ///< finger: twist of the tip at the peak of each period
  double periods = 2;         ///< motion periods per sequence
  int fine_regions = 4;       ///< bumps: planted fine regions (beside the 2 coarse ones)
  std::uint64_t seed = 0;
};

/// One planted deformation region of the `bumps` surface.
struct Region {
  int center = 0;                  ///< vertex index nearest to the centre
  int scale = 0;                   ///< 0 coarse, 1 fine
  double radius = 0;               ///< in mesh units
  double height = 0;               ///< peak displacement at weight 1
  std::vector<std::uint8_t> mask;  ///< per vertex: 1 inside the region
};

/// Generates frames on demand; frame(t) is a pure function of (params, t), so frames can be
/// made in parallel in any order.
class MeshSequenceGenerator {
 public:
  explicit MeshSequenceGenerator(const MeshSeqParams& p);

  const Mesh& rest() const { return rest_; }
  int total_frames() const { return params_.frames * params_.sequences; }
  /// #V by 3 positions of global frame t in [0, total_frames()).
  Vertices frame(int t) const;
  const std::vector<Region>& regions() const { return regions_; }
  /// Weight of each region in global frame t (bumps only).
  std::vector<double> region_weights(int t) const;
  const MeshSeqParams& params() const { return params_; }

 private:
  void build_finger();   // rest_ and the finger's cylinder coordinates
  void plant_regions();  // the bumps surface's coarse and fine regions
  Vertices finger(int seq, double phase) const;
  Vertices flag(int seq, double phase) const;
  Vertices bumps(int t) const;

  MeshSeqParams params_;
  Mesh rest_;
  std::vector<double> seq_scale_;  // per-sequence amplitude variation
  std::vector<Region> regions_;
  // finger: per-vertex (arc length s, cross-section x, y) on the rest shape
  std::vector<double> s_, x_, y_;
  double length_ = 4.0;
};

/// Writes the sequence to `output`: an .h5/.hdf5 path gets the acap file kind with
/// /frames/positions (and /synthetic ground truth), any other path a directory of mesh files
/// in `mesh_format` (obj, ply, off).
void synth_meshseq(const MeshSeqParams& p, const std::string& output,
                   const std::string& mesh_format, const CommonOptions& common);

}  // namespace df::synth
