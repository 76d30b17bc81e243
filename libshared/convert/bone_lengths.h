// The bone-length check of every skeleton import: a bone joins two points of one rigid body part,
// so its length stays nearly constant over a recording; a wrong joint order (a format read in
// another format's order, a shuffled file) joins joints whose distance varies with the motion.
// Per bone (joint, parent) and recording: the spread of its length over the recording's frames,
// relative to its median length, as a robust standard deviation (interquartile range / 1.349:
// a tracker's occasional lost joint does not count, a length that changes with the motion does);
// per bone the spread a quarter of the recordings reach (the 75th percentile: a wrong bone may
// move in some actions only, one badly tracked take does not condemn a bone) and the worst
// recording. On UTKinect's real Kinect segments no bone exceeds 0.25 (the hands, 8 cm bones,
// are the noisiest); in a wrong joint order some bones reach 0.44 to 0.61 (docs/actgan.md).
#pragma once

#include <string>
#include <vector>

#include "convert/skeleton_import.h"

namespace df::convert {

struct BoneSpread {
  int joint = 0, parent = 0;
  std::string name;            ///< "parent-joint", e.g. "elbow_left-wrist_left"
  double typical = 0;          ///< 75th percentile over recordings of its length's relative spread
  double worst = 0;            ///< the largest recording's spread
  std::string worst_sequence;  ///< the recording it was found in
  double mean_length = 0;      ///< mean length over every frame of every recording
};

/// Every bone's spread, worst (largest typical spread) first. Frames where either joint is
/// untracked (both points at the origin) are left out.
std::vector<BoneSpread> bone_length_spread(const RawSkeletonCollection& c);

/// Warns (or, when `strict`, throws InvalidInput) naming the bones whose typical spread exceeds
/// `tolerance` (up to five, worst first), with the hint that the joint order may be wrong; logs
/// the worst bone's spread at -v otherwise. `source` names the input in the message.
void check_bone_lengths(const RawSkeletonCollection& c, double tolerance, bool strict,
                        const std::string& source);

}  // namespace df::convert
