// The skeleton file kind (schemas/skeleton.json): labelled action sequences of joint positions,
// concatenated with CSR offsets, and the skeleton's joint hierarchy. Read by render-mesh (stick
// figures) and the ActGAN tools; written by synth-actions, skel2h5 and gen-actgan.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/h5.h"

namespace df::io {

/// poses = ((raw - raw[root_joint]) / scale - mean) / std, per joint and coordinate; mean and std
/// come from the training sequences (skel2h5), and every later tool undoes it with them.
struct SkeletonNormalization {
  int root_joint = 0;
  double scale = 1;
  std::vector<double> mean, std;  ///< [J, D]
  bool present() const { return !mean.empty(); }
};

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
  std::vector<std::int32_t> subjects;       ///< [S] performer of each sequence (optional)
  std::vector<std::int32_t> test;           ///< [S] 1 = held out for testing (optional)
  /// [S, C] the mixture of classes each sequence was generated for (optional; gen-actgan --mix):
  /// weights summing to 1, labels[s] its strongest class.
  std::vector<float> label_weights;
  SkeletonNormalization normalization;  ///< absent: poses are raw coordinates
  std::size_t sequences() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  /// Joint j of frame t, as (x, y, z) with z = 0 for 2-D data.
  void joint(std::size_t t, std::size_t j, double out[3]) const;
  std::size_t frame_size() const { return joints * static_cast<std::size_t>(dims); }
  std::size_t length(std::size_t s) const {
    return static_cast<std::size_t>(offsets[s + 1] - offsets[s]);
  }
  /// Whether sequence s was generated for a mixture of classes (more than one positive weight).
  bool is_mixture(std::size_t s) const;
  /// What sequence s shows: its class name, or its mixture ("walk 0.50 + wave 0.50").
  std::string label_text(std::size_t s) const;
  /// The raw coordinates of the poses (normalization undone; a copy of poses without one).
  std::vector<float> raw_poses() const;
};

/// The poses of `s` in the coordinates of normalization `target`: as stored when s has the same
/// normalization (or both none), else through raw coordinates (root-centred and normalized with
/// `target` when it is present).
std::vector<float> poses_normalized_as(const SkeletonFile& s, const SkeletonNormalization& target);

/// /classes/names and /skeleton/{parents,joint_names}: the parts of this kind the ActGAN model
/// kind carries too (the classes and skeleton it was trained on).
void write_classes_and_skeleton(h5::File& f, const std::vector<std::string>& class_names,
                                const std::vector<std::int32_t>& parents,
                                const std::vector<std::string>& joint_names);
void read_classes_and_skeleton(const h5::File& f, std::vector<std::string>& class_names,
                               std::vector<std::int32_t>& parents,
                               std::vector<std::string>& joint_names);
/// /normalization [J, dims] with its root joint and scale, written when present; read as absent
/// (empty) when the file has none.
void write_pose_normalization(h5::File& f, const SkeletonNormalization& n, int dims);
SkeletonNormalization read_pose_normalization(const h5::File& f);

/// The joint hierarchy of a Kinect v1 skeleton (UTKinect-Action3D, MSR-Action3D after
/// reordering, synth-actions): 20 joints, hip centre the root.
const std::vector<std::string>& kinect_joint_names();
const std::vector<std::int32_t>& kinect_joint_parents();

/// Opens and validates `path` as a skeleton file and reads it whole.
SkeletonFile read_skeleton_file(const std::string& path);

/// Writes `s` into an open file (the caller writes the header and makes the file atomic).
void write_skeleton_data(h5::File& f, const SkeletonFile& s);

}  // namespace df::io
