#include "synth/actions.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/rng.h"
#include "io/file_header.h"

namespace df::synth {
namespace {

using Vec = std::array<double, 3>;  // x to the figure's left, y up, z forward

Vec add(const Vec& a, const Vec& b, double s = 1) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}

// A limb's direction from hanging straight down: swung forward by `flex` in the sagittal plane
// and out to the side (x sign `side`) by `abduct`.
Vec limb(double flex, double abduct, double side) {
  return {side * std::sin(abduct), -std::cos(abduct) * std::cos(flex),
          std::cos(abduct) * std::sin(flex)};
}

// Joint angles (radians) and root motion of one frame; [0] left, [1] right.
struct Angles {
  double hip_flex[2] = {0, 0}, knee_flex[2] = {0, 0};
  double shoulder_flex[2] = {0, 0}, shoulder_abduct[2] = {0.08, 0.08};
  double elbow_flex[2] = {0.2, 0.2}, elbow_abduct[2] = {0, 0};
  double root_height = 0, root_forward = 0, lean = 0;
};

// Forward kinematics on the Kinect joint order (io::kinect_joint_names) for a body of size `s`.
void pose_joints(const Angles& a, double s, float* out) {
  std::array<Vec, 20> j{};
  const Vec up{0, std::cos(a.lean), std::sin(a.lean)};
  j[0] = {0, 0.95 * s + a.root_height, a.root_forward};
  j[1] = add(j[0], up, 0.22 * s);
  j[2] = add(j[1], up, 0.28 * s);
  j[3] = add(j[2], up, 0.2 * s);
  for (int k = 0; k < 2; ++k) {
    const double side = k == 0 ? 1.0 : -1.0;
    const int arm = 4 + 4 * k, leg = 12 + 4 * k;
    j[arm] = add(j[2], Vec{side * 0.18 * s, -0.04 * s, 0});
    j[arm + 1] = add(j[arm], limb(a.shoulder_flex[k], a.shoulder_abduct[k], side), 0.28 * s);
    const Vec forearm =
        limb(a.shoulder_flex[k] + a.elbow_flex[k], a.shoulder_abduct[k] + a.elbow_abduct[k], side);
    j[arm + 2] = add(j[arm + 1], forearm, 0.25 * s);
    j[arm + 3] = add(j[arm + 2], forearm, 0.08 * s);
    j[leg] = add(j[0], Vec{side * 0.1 * s, -0.06 * s, 0});
    j[leg + 1] = add(j[leg], limb(a.hip_flex[k], 0, side), 0.42 * s);
    j[leg + 2] = add(j[leg + 1], limb(a.hip_flex[k] - a.knee_flex[k], 0, side), 0.42 * s);
    j[leg + 3] = add(j[leg + 2], Vec{0, -0.04 * s, 0.12 * s});
  }
  for (std::size_t i = 0; i < j.size(); ++i)
    for (int c = 0; c < 3; ++c) out[3 * i + c] = static_cast<float>(j[i][c]);
}

double pos(double x) {
  return std::max(0.0, x);
}

// The right arm's (shoulder flex, shoulder abduct) along the closed polygon through `corners`
// at phase psi: the hand drawing a figure in front of the body, one round per cycle.
void trace(const std::vector<std::array<double, 2>>& corners, double psi, double amp, Angles& a) {
  const double u =
      std::fmod(psi / (2 * std::numbers::pi), 1.0) * static_cast<double>(corners.size());
  const auto i = static_cast<std::size_t>(u) % corners.size();
  const auto& p = corners[i];
  const auto& q = corners[(i + 1) % corners.size()];
  const double w = u - std::floor(u), centre_flex = 1.3, centre_abduct = 0.35;
  a.shoulder_flex[1] = centre_flex + amp * ((1 - w) * p[0] + w * q[0] - centre_flex);
  a.shoulder_abduct[1] = centre_abduct + amp * ((1 - w) * p[1] + w * q[1] - centre_abduct);
  a.elbow_flex[1] = 0.1;
}

// The arm gestures (MSR-Action3D's kind of classes: the same body, one arm's path differs).
void arm_gesture(const std::string& name, double psi, double amp, Angles& a) {
  const double sn = std::sin(psi), out = (1 + sn) / 2;  // out: 0 pulled in .. 1 reached out
  if (name == "hammer") {  // upper arm forward and up, the forearm chopping down and up
    a.shoulder_flex[1] = 1.5;
    a.elbow_flex[1] = 0.7 + 0.7 * amp * sn;
  } else if (name == "punch") {  // forward punch: the fist from the chest straight ahead
    a.shoulder_flex[1] = 0.3 + 1.2 * amp * out;
    a.elbow_flex[1] = 1.9 * (1 - out);
    a.shoulder_abduct[1] = 0.15;
  } else if (name == "side-box") {  // the same punch out to the side
    a.shoulder_abduct[1] = 0.4 + 1.1 * amp * out;
    a.shoulder_flex[1] = 0.3;
    a.elbow_flex[1] = 1.8 * (1 - out);
  } else if (name == "throw") {  // high throw: from behind the shoulder over the head and forward
    a.shoulder_flex[1] = 1.2 + 1.5 * amp * sn;
    a.elbow_flex[1] = 1.0 * pos(-sn) + 0.2;
  } else if (name == "catch") {  // reach forward and up, pull the hand back in
    a.shoulder_flex[1] = 0.3 + 1.3 * amp * pos(sn);
    a.shoulder_abduct[1] = 0.15 + 0.35 * pos(sn);
    a.elbow_flex[1] = 0.9 * (1 - pos(sn));
  } else if (name == "clap") {  // both hands in front, opening and meeting
    for (int k = 0; k < 2; ++k) {
      a.shoulder_flex[k] = 1.3;
      a.shoulder_abduct[k] = -0.25 + 0.8 * amp * out;
      a.elbow_flex[k] = 0.3;
    }
  } else if (name == "circle") {  // draw a circle in front
    a.shoulder_flex[1] = 1.3 + 0.4 * amp * sn;
    a.shoulder_abduct[1] = 0.35 + 0.4 * amp * std::cos(psi);
    a.elbow_flex[1] = 0.1;
  } else if (name == "draw-x") {  // two diagonals joined by the X's sides
    trace({{1.75, -0.05}, {0.85, 0.75}, {1.75, 0.75}, {0.85, -0.05}}, psi, amp, a);
  } else if (name == "tick") {  // a short stroke down, a long one up, back
    trace({{1.35, -0.05}, {1.0, 0.15}, {1.8, 0.75}}, psi, amp, a);
  }
}

// The angles of action `name` at phase psi (radians), amplitude amp, time `seconds`.
Angles action_angles(const std::string& name, double psi, double amp, double seconds) {
  Angles a;
  const double sn = std::sin(psi);
  if (name == "walk") {
    for (int k = 0; k < 2; ++k) {
      const double side = k == 0 ? 1.0 : -1.0;
      a.hip_flex[k] = 0.45 * amp * side * sn;
      a.knee_flex[k] = 0.7 * amp * pos(std::sin(psi + side * std::numbers::pi / 2));
      a.shoulder_flex[k] = -0.35 * amp * side * sn;
      a.elbow_flex[k] = 0.3;
    }
    a.root_height = 0.02 * amp * std::cos(2 * psi);
    a.root_forward = 0.7 * amp * seconds;
  } else if (name == "wave") {
    a.shoulder_abduct[1] = 2.4;
    a.elbow_abduct[1] = 0.5 * amp * sn;
    a.elbow_flex[1] = 0.3;
  } else if (name == "jump") {
    const double air = 0.25 * amp * pos(sn), crouch = 0.15 * amp * pos(-sn);
    a.root_height = air - crouch;
    for (int k = 0; k < 2; ++k) {
      a.knee_flex[k] = 8 * crouch;
      a.hip_flex[k] = 4 * crouch;
      a.shoulder_flex[k] = 2.5 * amp * pos(sn) - 0.6 * crouch / 0.15;
    }
    a.lean = 2 * crouch;
  } else if (name == "kick") {
    const double k = pos(sn);
    a.hip_flex[1] = 1.3 * amp * k;
    a.knee_flex[1] = 0.6 * amp * pos(std::sin(psi - 0.6));
    a.shoulder_abduct[0] = a.shoulder_abduct[1] = 0.6;
    a.shoulder_flex[0] = 0.4 * amp * k;
    a.lean = -0.2 * amp * k;
  } else if (name == "squat") {
    const double d = amp * (1 - std::cos(psi)) / 2;
    for (int k = 0; k < 2; ++k) {
      a.knee_flex[k] = 1.8 * d;
      a.hip_flex[k] = 1.4 * d;
      a.shoulder_flex[k] = 1.4 * d;
    }
    a.lean = 0.4 * d;
    a.root_height = -0.45 * d;
  } else {
    arm_gesture(name, psi, amp, a);
  }
  return a;
}

// Motion cycles per second of each action at speed 1.
double base_frequency(const std::string& name) {
  if (name == "walk") return 1.0;
  if (name == "wave") return 1.5;
  if (name == "jump") return 0.8;
  if (name == "kick") return 0.7;
  if (name == "squat") return 0.5;
  return 0.8;  // the arm gestures
}

bool is_known(const std::vector<std::string>& names, const std::string& c) {
  return std::find(names.begin(), names.end(), c) != names.end();
}

void check_params(const ActionParams& p) {
  if (p.per_class < 1 || p.frames < 2 || p.subjects < 1 || !(p.frame_rate > 0) || p.noise < 0)
    throw UsageError(
        "--per-class and --subjects must be positive, --frames at least 2, --fps positive, --noise "
        "not negative");
  for (const auto& c : p.classes)
    if (!is_known(action_names(), c) && !is_known(gesture_names(), c) && c != "gestures")
      throw UsageError(
          fmt::format("unknown action '{}' (known: {}, {}, or 'gestures' for the last {})", c,
                      fmt::join(action_names(), ", "), fmt::join(gesture_names(), ", "),
                      gesture_names().size()));
}

// The classes asked for, 'gestures' expanded.
std::vector<std::string> class_list(const ActionParams& p) {
  if (p.classes.empty()) return action_names();
  std::vector<std::string> out;
  for (const auto& c : p.classes) {
    if (c == "gestures")
      out.insert(out.end(), gesture_names().begin(), gesture_names().end());
    else
      out.push_back(c);
  }
  std::vector<std::string> sorted = out;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw UsageError(fmt::format("--classes names an action twice: {}", fmt::join(out, ", ")));
  return out;
}

}  // namespace

const std::vector<std::string>& action_names() {
  static const std::vector<std::string> names{"walk", "wave", "jump", "kick", "squat"};
  return names;
}

const std::vector<std::string>& gesture_names() {
  static const std::vector<std::string> names{"hammer", "punch",  "side-box", "throw", "catch",
                                              "clap",   "circle", "draw-x",   "tick"};
  return names;
}

io::SkeletonFile make_actions(const ActionParams& p) {
  check_params(p);
  io::SkeletonFile s;
  s.class_names = class_list(p);
  s.joints = 20;
  s.dims = 3;
  s.joint_names = io::kinect_joint_names();
  s.parents = io::kinect_joint_parents();
  s.frame_rate = p.frame_rate;
  const std::size_t count = s.class_names.size() * static_cast<std::size_t>(p.per_class);
  s.frames = count * static_cast<std::size_t>(p.frames);
  s.poses.resize(s.frames * s.frame_size());
  s.offsets.push_back(0);
  for (std::size_t c = 0; c < s.class_names.size(); ++c) {
    for (int k = 0; k < p.per_class; ++k) {
      const std::size_t seq = s.labels.size();
      Rng rng(p.seed, seq);
      const int subject = k % p.subjects;
      const double body =
          Rng(p.seed, 1'000'000 + static_cast<std::uint64_t>(subject)).uniform(0.9, 1.1);
      const double speed = rng.uniform(0.8, 1.25), amp = rng.uniform(0.8, 1.2);
      const double phase = rng.uniform(0, 2 * std::numbers::pi);
      const double omega = 2 * std::numbers::pi * base_frequency(s.class_names[c]) * speed;
      for (int t = 0; t < p.frames; ++t) {
        const double seconds = t / p.frame_rate;
        float* out = s.poses.data() +
                     (seq * static_cast<std::size_t>(p.frames) + static_cast<std::size_t>(t)) *
                         s.frame_size();
        pose_joints(action_angles(s.class_names[c], omega * seconds + phase, amp, seconds), body,
                    out);
        if (p.noise > 0)
          for (std::size_t i = 0; i < s.frame_size(); ++i)
            out[i] += static_cast<float>(rng.normal(0, p.noise));
      }
      s.labels.push_back(static_cast<std::int32_t>(c));
      s.subjects.push_back(subject + 1);
      s.sequence_names.push_back(fmt::format("{}_{:03d}", s.class_names[c], k));
      s.offsets.push_back(s.offsets.back() + p.frames);
    }
  }
  return s;
}

void synth_actions(const ActionParams& p, const std::string& output, const CommonOptions& common) {
  const io::SkeletonFile s = make_actions(p);
  AtomicOutput out(output, AtomicOutput::Kind::file, common.force);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, output);
    io::write_header(f, "skeleton");
    io::write_skeleton_data(f, s);
  }
  out.commit();
  log::info("wrote {}: {} actions x {} sequences of {} frames ({} joints, {} subjects)", output,
            s.class_names.size(), p.per_class, p.frames, s.joints, p.subjects);
}

}  // namespace df::synth
