// What a trained ActGAN's frame decoder can reach. Each pose of a skeleton file
// (its test part, or some subjects' poses) gets the latent code h that brings Dec(h, y) nearest to
// it (Adam on |Dec(h, y) - x|^2 from h = 0, the decoder's own weights fixed), and its error is
// set beside two references from the training part: the mean training pose and the nearest
// training pose of the same class. A decoder that reconstructs held-out poses no better than the
// nearest training pose cannot generate poses the training set lacks (issue 71's diagnosis).
#pragma once

#include <string>
#include <vector>

#include "io/skeleton_file.h"
#include "models/actgan/model.h"

namespace df::models {

struct ActganInspectOptions {
  std::string model, input;
  bool all = false;  ///< every sequence's poses, not only the test part
  /// The poses of these subjects instead (a validation part: the test part stays unseen); the
  /// references then come from the other subjects outside the test part
  std::vector<int> subjects;
  int steps = 300;   ///< Adam steps per batch of poses
  double lr = 0.05;  ///< Adam's initial rate (decays tenfold over the steps)
  std::string json;  ///< "" or a file (or "-")
};

/// One way of reaching the poses: the RMS over every coordinate in the model's normalized
/// coordinates, and the mean per-joint distance in the data's root-centred units.
struct PoseError {
  double rms = 0, joint_distance = 0;
};

struct DecoderReach {
  std::string part;  ///< "test", "subjects" or "all"
  std::size_t poses = 0, training_poses = 0;
  PoseError fitted;                   ///< Dec(h*, y), h* fitted
  PoseError start;                    ///< Dec(0, y), where the fit starts
  PoseError mean_pose;                ///< the mean training pose
  PoseError nearest;                  ///< the nearest training pose of the same class
  std::size_t without_reference = 0;  ///< poses with no reference of their class (nearest: 0)
  std::vector<std::string> classes;
  std::vector<PoseError> fitted_by_class, nearest_by_class;
  std::vector<std::size_t> poses_by_class;
};

/// Fits latent codes to `poses` [N, P] (model coordinates) with labels `labels` (model class
/// indices): the decoder's reconstructions [N, P].
nn::Matrix<float> fit_latent_codes(const ActganModel& m, const nn::Matrix<float>& poses,
                                   const std::vector<int>& labels, int steps, double lr);

/// The decoder's reach of the poses `opt` selects from `s` (opt.all, opt.subjects, opt.steps,
/// opt.lr), with the references; InvalidInput for the direct-pose baseline or no pose to fit.
DecoderReach decoder_reach(const ActganModel& m, const io::SkeletonFile& s,
                           const ActganInspectOptions& opt);

}  // namespace df::models
