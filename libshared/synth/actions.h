// Procedural labelled stick-figure actions on the 20-joint Kinect v1 skeleton, so that the
// ActGAN tools run and can be tested with no downloaded data:
//   walk   legs and arms swing in opposition, the body moves forward and bobs
//   wave   the right arm raised to the side, the forearm swinging over the head
//   jump   crouch, take off with the arms swinging up, land
//   kick   the right leg swings forward and up, the arms counter-balance
//   squat  knees and hips bend, the body goes down with the arms forward
// and arm gestures, classes that differ only in the path of the right arm (MSR-Action3D's
// kind): hammer, punch, side-box, throw, catch, clap (both hands), circle, draw-x, tick.
// Each sequence varies speed (0.8-1.25x), amplitude (0.8-1.2x) and phase at random, and belongs
// to one of --subjects simulated performers whose body size differs (0.9-1.1x).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/common_options.h"
#include "io/skeleton_file.h"

namespace df::synth {

/// The action classes synth-actions makes by default, in label order.
const std::vector<std::string>& action_names();

/// The arm gestures, made when named (--classes; 'gestures' names them all, in this order).
const std::vector<std::string>& gesture_names();

struct ActionParams {
  /// of action_names() and gesture_names(), "gestures" = all of the latter (empty = action_names())
  std::vector<std::string> classes;
  int per_class = 20;      ///< sequences of each class
  int frames = 60;         ///< frames per sequence
  double frame_rate = 30;  ///< frames per second
  int subjects = 5;        ///< simulated performers, assigned round robin
  double noise = 0.0;      ///< s.d. of Gaussian jitter on every coordinate, metres
  std::uint64_t seed = 0;
};

/// The actions as a skeleton file (raw coordinates in metres, y up). Sequence k of a class
/// draws from Rng(seed, global sequence index): the same seed gives the same file.
io::SkeletonFile make_actions(const ActionParams& p);

/// synth-actions: make_actions, written atomically to `output` (kind skeleton).
void synth_actions(const ActionParams& p, const std::string& output, const CommonOptions& common);

}  // namespace df::synth
