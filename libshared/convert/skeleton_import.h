// Readers of labelled skeleton recordings, each into one in-memory form (raw joint positions with
// per-frame times) that skel2h5 resamples, splits, clips and normalizes:
//   UTKinect-Action3D  joints_sXX_eYY.txt (per line a frame id + 20 x (x y z)) and actionLabel.txt
//                      (per take "sXX_eYY", then "class: start end" by frame id); segments are the
//                      frames whose id lies in [start, end]; time = id / 30 s
//   MSR-Action3D       aXX_sYY_eZZ_skeleton3D.txt: 20 lines "x y z confidence" per frame (15 fps);
//                      action, subject and take from the name; joints reordered from the
//                      dataset's own order to the Kinect order of UTKinect
//                      (io::kinect_joint_names), left and right told from the geometry
//   BVH                forward kinematics of every joint's channels (assimp), one sequence per file
//   skeleton .h5       the project's own files (synth-actions; raw coordinates, or de-normalized)
//   joint arrays       .npy files of [frames, joints, 3] positions, one sequence each (HumanAct12,
//                      NTU's processed skeletons, AMASS-derived joint sets), the joints' layout
//                      given or recognised by their count, classes from a list, one label or the
//                      files' folders
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
  double frame_rate = 30;  ///< the source's nominal rate
  std::vector<RawSkeletonSequence> sequences;
  std::size_t joints() const { return joint_names.size(); }
};

/// UTKinect-Action3D: `labels` is actionLabel.txt (or actionLabel_modified.txt); the joints files
/// are looked up beside it. A take the label file names whose joints file is missing, and a
/// segment whose start follows its end, are skipped with a warning; a malformed line is an
/// InvalidInput naming file and line.
RawSkeletonCollection read_utkinect(const std::string& labels);

/// MSR-Action3D skeleton files (any number, one sequence each), joints in the Kinect order. The
/// dataset's order (1-based): 1, 2 shoulders; 3 shoulder centre; 4 spine; 5, 6 hips; 7 hip
/// centre; 8, 9 elbows; 10, 11 wrists; 12, 13 hands; 14, 15 knees; 16, 17 ankles; 18, 19 feet;
/// 20 head, the chains 1-8-10-12 / 2-9-11-13 (arms) and 5-14-16-18 / 6-15-17-19 (legs) on
/// opposite sides. Which chain is the left one is decided once for all files, by most
/// recordings: the subjects face the camera, so the subject's left is (head - hip centre) x
/// (towards the camera) in a right-handed frame whose depth axis is z.
RawSkeletonCollection read_msr_action3d(const std::vector<std::string>& files);

/// Whether a file name has MSR-Action3D's form aXX_sYY_eZZ_skeleton3D.txt.
bool is_msr_action3d_name(const std::string& path);

/// BVH motion capture (one sequence per file, labelled `label` or by the file's stem); every
/// file must have the same joint hierarchy.
RawSkeletonCollection read_bvh(const std::vector<std::string>& files, const std::string& label);

/// A skeleton .h5 (kind skeleton), its poses raw (de-normalized when it has a normalization).
RawSkeletonCollection read_skeleton_h5(const std::string& path);

/// How joint arrays are labelled and laid out.
struct JointArrayOptions {
  /// Lines "NAME CLASS [SUBJECT]" (NAME: a file's stem; '#' starts a comment); "" = none
  std::string labels_file;
  /// Lines "NAME PARENT" in the arrays' joint order (PARENT: an earlier joint's name, or - for the
  /// root); "" = recognise the layout by the joint count (joint_array_layouts)
  std::string joints_file;
  double fps = 30;  ///< the arrays' frame rate
};

/// Joint-position arrays, one .npy file per sequence ([frames, joints, 3], any float or integer
/// type), or .npz archives of them (np.savez; each member [frames, joints, 3] one sequence, each
/// [n, frames, joints, 3] n, named STEM/MEMBER(_i) — the stem alone when the archive holds one;
/// members 'label' / 'labels' / 'action' / 'y' (text or integers) and 'subject' / 'subjects' one
/// value per sequence in the archive's order; other members left out with a warning): every
/// sequence must have the same joint count. A layout is recognised by its count: 22
/// (SMPL's body joints without the hands, as HumanML3D and other AMASS-derived sets keep them),
/// 24 (SMPL, as HumanAct12 has them), 25 (Kinect v2, as NTU RGB+D has them); any other count needs
/// `joints_file`. A sequence's class: its line in `labels_file`, else `label` (every file's), else
/// its archive's label, else its folder's name. InvalidInput naming the file (and line) on a
/// malformed array or list, a file without a class, a parent that is not an earlier joint.
RawSkeletonCollection read_joint_arrays(const std::vector<std::string>& files,
                                        const std::string& label, const JointArrayOptions& opt);

/// The joint layouts read_joint_arrays recognises: names and parents (-1 for the root), by count.
struct JointLayout {
  const char* what;
  std::vector<std::string> names;
  std::vector<std::int32_t> parents;
};
const std::vector<JointLayout>& joint_array_layouts();

/// MSR-Action3D's 20 action names (a01 .. a20).
const std::vector<std::string>& msr_action_names();

}  // namespace df::convert
