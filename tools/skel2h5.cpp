// skel2h5: labelled skeleton recordings -> one normalized skeleton file for the ActGAN tools.
#include "convert/skel2h5.h"

#include "core/tool.h"

int main(int argc, char** argv) {
  df::Tool tool(
      "skel2h5",
      "Import labelled skeleton action recordings into one skeleton file (paper 3's data):\n"
      "  UTKinect-Action3D  a directory (or its actionLabel.txt / actionLabel_modified.txt)\n"
      "                     with joints_sXX_eYY.txt: one sequence per labelled segment, the\n"
      "                     frames whose id lies in [start, end]; time = id / 30 s\n"
      "  MSR-Action3D       aXX_sYY_eZZ_skeleton3D.txt files or a directory of them (20 lines\n"
      "                     'x y z confidence' per frame, 15 fps): action, subject and take from\n"
      "                     the name; the dataset's joint order mapped to the Kinect order of\n"
      "                     UTKinect, left and right told from the geometry (subjects facing the\n"
      "                     camera); other files beside them are left out with a warning\n"
      "  BVH                .bvh files (forward kinematics of their channels, through assimp),\n"
      "                     one sequence each, class --label or the file's stem\n"
      "  joint arrays       .npy files of [frames, joints, 3] positions, one sequence each\n"
      "                     (HumanAct12, NTU's processed skeletons, AMASS-derived sets), .npz\n"
      "                     archives of them (np.savez: each member [frames, joints, 3] or\n"
      "                     [n, frames, joints, 3] a sequence or n; a member 'label', 'labels',\n"
      "                     'action' or 'y' their classes, 'subject(s)' their subjects, one per\n"
      "                     sequence in the archive's order), or a directory of them or of class\n"
      "                     folders; at --source-fps; classes from --labels FILE, --label, the\n"
      "                     archive, or each file's folder; joints named by --joints FILE or\n"
      "                     recognised by their count (22, 24: SMPL; 25: Kinect v2)\n"
      "  skeleton .h5       the project's files (synth-actions, an earlier skel2h5)\n"
      "Then: resampling to --fps (linear interpolation in time), a train/test split of whole\n"
      "sequences (--test-subjects, or --test-fraction of each class by --seed), clips of\n"
      "--length frames every --clip-stride, and normalization fitted on the training clips\n"
      "only: root-centred (--root-joint), divided by the mean joint distance from the root,\n"
      "z-scored per joint and coordinate; the numbers are stored (/normalization) and every\n"
      "later tool uses them. Every import checks its bones: a bone's length should stay nearly\n"
      "constant over a recording (a wrong joint order joins joints whose distance varies); bones\n"
      "whose length spread (interquartile range / 1.349 / median) exceeds --bone-tolerance in a\n"
      "quarter of the recordings are named in a warning, an error with --strict. Malformed\n"
      "input: one-line errors naming file and line; a take without a joints file or a segment\n"
      "that ends before it starts: a warning.\n"
      "\n"
      "OUTPUT: a skeleton .h5 (/poses, /sequences/{offsets,labels,names,subjects,test},\n"
      "/classes/names, /skeleton/{parents,joint_names}, /normalization).");
  tool.with_seed(0).with_force();
  df::convert::Skel2h5Options opt;
  auto& app = tool.app();
  app.add_option("INPUT", opt.inputs, "Directory, label file, skeleton/BVH files or a .h5")
      ->required();
  app.add_option("-o,--output", opt.output, "Output skeleton file (.h5)")->required();
  app.add_option("--format", opt.format, "Input format")
      ->default_val(opt.format)
      ->check(CLI::IsMember({"auto", "utkinect", "msr", "bvh", "npy", "skeleton"}));
  app.add_option("--label", opt.label,
                 "BVH, npy: the class of every file (default: BVH the file's stem, npy its\n"
                 "folder's name)");
  app.add_option(
      "--labels", opt.arrays.labels_file,
      "npy: lines 'NAME CLASS [SUBJECT]', NAME a file's stem or, in a .npz of several\n"
      "sequences, STEM/MEMBER (STEM/MEMBER_i of an [n, ...] member) (# comments); every\n"
      "sequence needs one. SUBJECT (a positive integer) is what --test-subjects holds out");
  app.add_option("--joints", opt.arrays.joints_file,
                 "npy: lines 'NAME PARENT' in the arrays' joint order, PARENT an earlier joint's\n"
                 "name or - for the root (default: recognised by the count: 22 SMPL body joints,\n"
                 "24 SMPL, 25 Kinect v2)");
  app.add_option("--source-fps", opt.arrays.fps, "npy: the arrays' frame rate")
      ->default_val(opt.arrays.fps);
  app.add_option("--fps", opt.fps,
                 "Frame rate to resample to (default: the source's: UTKinect 30,\n"
                 "MSR-Action3D 15, BVH its frame time)")
      ->default_val(opt.fps);
  app.add_option("--length", opt.length, "Frames per clip (0: whole sequences)")
      ->default_val(opt.length);
  app.add_option("--clip-stride", opt.clip_stride, "Frames between clip starts (0: --length)")
      ->default_val(opt.clip_stride);
  app.add_option("--test-subjects", opt.test_subjects,
                 "Hold out the sequences of these subjects, comma-separated (UTKinect: 1-10)")
      ->delimiter(',')
      ->allow_extra_args(false);  // one comma-separated word: a positional may follow
  app.add_option("--test-fraction", opt.test_fraction,
                 "Or hold out this fraction of each class's sequences, drawn by --seed")
      ->default_val(opt.test_fraction);
  app.add_option("--root-joint", opt.root_joint,
                 "Joint subtracted from every pose (Kinect: 0 = hip centre)")
      ->default_val(opt.root_joint);
  app.add_option("--bone-tolerance", opt.bone_tolerance,
                 "Largest spread of a bone's length within a recording (relative to its median,\n"
                 "reached in a quarter of the recordings) before the import warns: real Kinect\n"
                 "data reach 0.25 at the hands, a wrong joint order 0.5 and more")
      ->default_val(opt.bone_tolerance);
  app.add_flag("--strict", opt.strict, "Bones over --bone-tolerance are an error, not a warning");
  app.add_option("--sd-floor", opt.sd_floor,
                 "Raise each joint coordinate's s.d. (units of the body scale, the mean joint\n"
                 "distance from the root) to at least this before z-scoring, so that a still\n"
                 "joint's sensor jitter (about 0.03 on Kinect gestures) is not blown up to the\n"
                 "moving joints' size; 0 = a plain z-score (docs/actgan.md, issue 71)")
      ->default_val(opt.sd_floor)
      ->check(CLI::Range(0.0, 10.0));
  app.add_flag("!--raw", opt.normalize,
               "Keep raw coordinates (no root-centring, scaling, z-score)");
  tool.footer(
      "Examples:\n"
      "  skel2h5 UTKinect/joints --fps 15 --length 30 --clip-stride 10 --test-subjects 2,4,6,8,10 "
      "-o utk.h5\n"
      "  skel2h5 MSRAction3DSkeletonReal3D --test-subjects 1,3,5,7,9 -o msr.h5\n"
      "  skel2h5 --label boxing Boxing_Toes.bvh --fps 30 --length 60 -o box.h5\n"
      "  skel2h5 --labels labels.txt --source-fps 20 --length 40 --test-subjects 1,2 joints/ "
      "-o ha12.h5\n"
      "  skel2h5 actions.h5 --length 30 --test-fraction 0.2 -o train.h5");
  return tool.run(argc, argv, [&] { df::convert::skel2h5(opt, tool.common()); });
}
