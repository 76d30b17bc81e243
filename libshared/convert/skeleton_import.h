// Readers of labelled skeleton recordings, each into one in-memory form (raw joint positions with
// per-frame times) that skel2h5 resamples, splits, clips and normalizes:
//   UTKinect-Action3D  joints_sXX_eYY.txt (per line a frame id + 20 x (x y z)) and actionLabel.txt
//                      (per take "sXX_eYY", then "class: start end" by frame id); segments are the
//                      frames whose id lies in [start, end]; time = id / 30 s
//   MSR-Action3D       aXX_sYY_eZZ_skeleton3D.txt: 20 lines "x y z confidence" per frame (15 fps);
//                      action, subject and take from the name; joints reordered to the Kinect
//                      order of UTKinect (io::kinect_joint_names)
//   BVH                forward kinematics of every joint's channels (assimp), one sequence per file
//   skeleton .h5       the project's own files (synth-actions; raw coordinates, or de-normalized)
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace df::convert {

struct RawSkeletonSequence {
  std::string name;           ///< e.g. s01_e01_walk, a02_s03_e01, 01_01
  std::string label;          ///< class name
  std::int32_t subject = 0;   ///< 0 = unknown
  std::vector<double> times;  ///< [frames] seconds, increasing
  std::vector<float> poses;   ///< [frames, J, 3]
};

struct RawSkeletonCollection {
  std::vector<std::string> joint_names;
  std::vector<std::int32_t> parents;
  double frame_rate = 30;     ///< the source's nominal rate
  std::vector<RawSkeletonSequence> sequences;
  std::size_t joints() const { return joint_names.size(); }
};

/// UTKinect-Action3D: `labels` is actionLabel.txt (or actionLabel_modified.txt); the joints files
/// are looked up beside it. A take the label file names whose joints file is missing, and a
/// segment whose start follows its end, are skipped with a warning; a malformed line is an
/// InvalidInput naming file and line.
RawSkeletonCollection read_utkinect(const std::string& labels);

/// MSR-Action3D skeleton files (any number, one sequence each).
RawSkeletonCollection read_msr_action3d(const std::vector<std::string>& files);

/// BVH motion capture (one sequence per file, labelled `label` or by the file's stem); every
/// file must have the same joint hierarchy.
RawSkeletonCollection read_bvh(const std::vector<std::string>& files, const std::string& label);

/// A skeleton .h5 (kind skeleton), its poses raw (de-normalized when it has a normalization).
RawSkeletonCollection read_skeleton_h5(const std::string& path);

/// MSR-Action3D's 20 action names (a01 .. a20).
const std::vector<std::string>& msr_action_names();

}  // namespace df::convert
