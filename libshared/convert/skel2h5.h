// skel2h5: labelled skeleton recordings (UTKinect-Action3D, MSR-Action3D, BVH, the project's own
// skeleton files) -> one skeleton file ready for ActGAN: resampled to one frame rate, split into
// training and test sequences (by subject or at random per class), cut into fixed-length clips,
// and normalized with numbers from the training part only (stored; every later tool undoes it).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "convert/skeleton_import.h"
#include "core/common_options.h"
#include "io/skeleton_file.h"

namespace df::convert {

struct Skel2h5Options {
  std::vector<std::string> inputs;
  std::string output;
  std::string format = "auto";  ///< auto, utkinect, msr, bvh, npy, skeleton
  std::string label;  ///< bvh, npy: the class of every file ("" = bvh: its stem, npy: its folder)
  JointArrayOptions arrays;        ///< npy: labels file, joint layout, frame rate
  double fps = 0;                  ///< 0 = the source's rate
  int length = 0;                  ///< frames per clip; 0 = whole sequences
  int clip_stride = 0;             ///< frames between clip starts; 0 = --length
  std::vector<int> test_subjects;  ///< sequences of these subjects are held out
  double test_fraction = 0;        ///< or this fraction of each class, drawn by the seed
  int root_joint = 0;
  bool normalize = true;
  /// The z-score's s.d. of every coordinate at least this (in units of the body scale): a
  /// still joint's sensor jitter is then not blown up to unit variance. 0 = none.
  double sd_floor = 0;
  double bone_tolerance = 0.3;  ///< a bone's relative length spread that warns (bone_lengths.h)
  bool strict = false;          ///< the bone-length warning becomes an error
};

/// Every sequence at `fps` frames per second from its first to its last time (linear
/// interpolation of the joints between the two nearest source frames).
void resample(RawSkeletonCollection& c, double fps);

/// 1 for held-out sequences: those of test_subjects, or round(test_fraction x n) of each class's
/// n sequences drawn with Rng(seed); 0 for the rest.
std::vector<std::int32_t> assign_test_split(const RawSkeletonCollection& c,
                                            const Skel2h5Options& opt, std::uint64_t seed);

/// The skeleton file: sequences (or clips of opt.length frames every opt.clip_stride; shorter
/// sequences are dropped with a warning) in input order, classes in order of appearance, the
/// normalization fitted on the training clips (when opt.normalize).
io::SkeletonFile build_skeleton_file(const RawSkeletonCollection& c,
                                     const std::vector<std::int32_t>& test,
                                     const Skel2h5Options& opt);

/// root-centre, then divide by the mean joint distance from the root, then z-score per joint and
/// coordinate, each s.d. raised to `sd_floor` where it is below (the root joint's, 0, stays
/// 1); all fitted on the sequences with test == 0. Applied to s.poses in place.
void normalize_skeletons(io::SkeletonFile& s, int root_joint, double sd_floor = 0);

/// The tool: read (every format through the bone-length check), resample, split, clip, normalize,
/// write atomically.
void skel2h5(const Skel2h5Options& opt, const CommonOptions& common);

}  // namespace df::convert
