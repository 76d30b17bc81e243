// The skeleton file kind (schemas/skeleton.json): labelled action sequences of joint positions,
// concatenated with CSR offsets, and the skeleton's joint hierarchy. Read by render-mesh (stick
// figures) and the ActGAN tools; written by synth-actions, skel2h5 and gen-actgan.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/h5.h"

namespace df::io {

struct SkeletonFile {
  std::size_t frames = 0, joints = 0;
  int dims = 3;                             ///< coordinates per joint (2 or 3)
  std::vector<float> poses;                 ///< [frames, joints, dims]
  std::vector<std::int64_t> offsets;        ///< [S+1]
  std::vector<std::string> sequence_names;  ///< [S] ("" entries when the file has none)
  std::vector<std::int32_t> labels;         ///< [S] class of each sequence
  std::vector<std::string> class_names;     ///< [C]
  std::vector<std::int32_t> parents;        ///< [J] parent joint, −1 for a root
  std::vector<std::string> joint_names;     ///< [J]
  double frame_rate = 30;                   ///< frames per second
  std::size_t sequences() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  /// Joint j of frame t, as (x, y, z) with z = 0 for 2-D data.
  void joint(std::size_t t, std::size_t j, double out[3]) const;
};

/// Opens and validates `path` as a skeleton file and reads it whole.
SkeletonFile read_skeleton_file(const std::string& path);

/// Writes `s` into an open file (the caller writes the header and makes the file atomic).
void write_skeleton_data(h5::File& f, const SkeletonFile& s);

}  // namespace df::io
