#include "convert/skeleton_import.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "core/error.h"
#include "core/log.h"
#include "core/word_lines.h"
#include "io/npy_file.h"
#include "io/npz_file.h"
#include "io/skeleton_file.h"

namespace fs = std::filesystem;

namespace df::convert {
namespace {

constexpr double kUtkinectRate = 30, kMsrRate = 15;

std::string at_line(const std::string& file, std::size_t line) {
  return fmt::format("{}:{}", file, line);
}

// The whitespace-separated numbers of a line; InvalidInput (file:line) on anything else.
std::vector<double> numbers(const std::string& line, const std::string& file, std::size_t lineno) {
  std::vector<double> v;
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
    if (p == end) break;
    const char* token = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r') ++p;
    double x = 0;
    const auto [stop, ec] = std::from_chars(token, p, x);
    if (ec != std::errc() || stop != p || !std::isfinite(x))
      throw InvalidInput(
          fmt::format("field {} is not a finite number: '{}'", v.size() + 1, std::string(token, p)),
          at_line(file, lineno));
    v.push_back(x);
  }
  return v;
}

// UTKinect marks a segment it could not label with "NaN NaN".
bool is_nan_token(std::string t) {
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return t == "nan";
}

std::ifstream open_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IOError("cannot read", path);
  return in;
}

RawSkeletonCollection kinect_collection(double rate) {
  RawSkeletonCollection c;
  c.joint_names = io::kinect_joint_names();
  c.parents = io::kinect_joint_parents();
  c.frame_rate = rate;
  return c;
}

// One UTKinect take: frame ids and their 20 joints, in file order (ids increasing; a frame whose
// id does not increase is dropped).
struct Take {
  std::vector<double> ids;
  std::vector<float> poses;
};

Take read_utkinect_take(const std::string& path) {
  auto in = open_text(path);
  Take take;
  std::size_t lineno = 0, dropped = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineno;
    const auto v = numbers(line, path, lineno);
    if (v.empty()) continue;
    if (v.size() != 61)
      throw InvalidInput(
          fmt::format("expected a frame id and 20 joints x (x y z) = 61 numbers, found {}",
                      v.size()),
          at_line(path, lineno));
    if (!take.ids.empty() && v[0] <= take.ids.back()) {
      ++dropped;
      continue;
    }
    take.ids.push_back(v[0]);
    for (std::size_t k = 1; k < v.size(); ++k) take.poses.push_back(static_cast<float>(v[k]));
  }
  if (dropped) log::debug("{}: {} frame(s) whose id repeats an earlier one dropped", path, dropped);
  return take;
}

}  // namespace

RawSkeletonCollection read_utkinect(const std::string& labels) {
  auto in = open_text(labels);
  const fs::path dir = fs::path(labels).parent_path();
  RawSkeletonCollection c = kinect_collection(kUtkinectRate);
  static const std::regex take_re(R"(^\s*s(\d+)_e(\d+)\s*$)");
  static const std::regex segment_re(R"(^\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(\S+)\s+(\S+)\s*$)");
  std::map<std::string, Take> takes;
  std::string take_name;
  std::int32_t subject = 0;
  bool take_missing = false;
  std::size_t lineno = 0;
  for (std::string line; std::getline(in, line);) {
    ++lineno;
    std::smatch m;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    if (std::regex_match(line, m, take_re)) {
      take_name = fmt::format("s{}_e{}", m[1].str(), m[2].str());
      subject = std::stoi(m[1].str());
      const fs::path joints = dir / ("joints_" + take_name + ".txt");
      take_missing = !fs::exists(joints);
      if (take_missing)
        log::warn("{}: take {} has no joints file {}; its segments are skipped",
                  at_line(labels, lineno), take_name, joints.string());
      else if (!takes.count(take_name))
        takes.emplace(take_name, read_utkinect_take(joints.string()));
      continue;
    }
    if (!std::regex_match(line, m, segment_re))
      throw InvalidInput("expected a take 'sXX_eYY' or a segment 'class: start end'",
                         at_line(labels, lineno));
    if (take_name.empty())
      throw InvalidInput("a segment before the first take line", at_line(labels, lineno));
    if (take_missing) continue;
    const std::string label = m[1].str();
    if (is_nan_token(m[2].str()) || is_nan_token(m[3].str())) {
      log::warn("{}: segment {} of {} has no frame range ({} {}); skipped", at_line(labels, lineno),
                label, take_name, m[2].str(), m[3].str());
      continue;
    }
    const auto bounds = numbers(m[2].str() + " " + m[3].str(), labels, lineno);
    if (bounds[0] > bounds[1]) {
      log::warn("{}: segment {} starts at frame id {} after its end {}; skipped",
                at_line(labels, lineno), label, bounds[0], bounds[1]);
      continue;
    }
    const Take& take = takes.at(take_name);
    RawSkeletonSequence s;
    s.name = take_name + "_" + label;
    s.label = label;
    s.subject = subject;
    for (std::size_t f = 0; f < take.ids.size(); ++f) {
      if (take.ids[f] < bounds[0] || take.ids[f] > bounds[1]) continue;
      s.times.push_back(take.ids[f] / kUtkinectRate);
      s.poses.insert(s.poses.end(), take.poses.begin() + static_cast<std::ptrdiff_t>(f * 60),
                     take.poses.begin() + static_cast<std::ptrdiff_t>(f * 60 + 60));
    }
    if (s.times.size() < 2) {
      log::warn("{}: segment {} holds {} frame(s) of {}; skipped", at_line(labels, lineno), label,
                s.times.size(), take_name);
      continue;
    }
    c.sequences.push_back(std::move(s));
  }
  if (c.sequences.empty()) throw InvalidInput("no segment with frames", labels);
  return c;
}

const std::vector<std::string>& msr_action_names() {
  static const std::vector<std::string> names{
      "high_arm_wave", "horizontal_arm_wave", "hammer",        "hand_catch",
      "forward_punch", "high_throw",          "draw_x",        "draw_tick",
      "draw_circle",   "hand_clap",           "two_hand_wave", "side_boxing",
      "bend",          "forward_kick",        "side_kick",     "jogging",
      "tennis_swing",  "tennis_serve",        "golf_swing",    "pickup_throw"};
  return names;
}

namespace {

// MSR-Action3D lists its 20 joints in its own order (1-based, as the dataset's drawing script
// connects them: 20-3, 1-3, 2-3, 1-8, 8-10, 10-12, 2-9, 9-11, 11-13, 3-4, 4-7, 7-5, 7-6, 5-14,
// 14-16, 16-18, 6-15, 15-17, 17-19): 3 shoulder centre, 4 spine, 7 hip centre, 20 head, and two
// arm chains (shoulder, elbow, wrist, hand) 1-8-10-12 and 2-9-11-13, two leg chains (hip, knee,
// ankle, foot) 5-14-16-18 and 6-15-17-19. Which chain is the subject's left is told from the
// geometry. 0-based here.
constexpr int kMsrHead = 19, kMsrShoulderCentre = 2, kMsrSpine = 3, kMsrHipCentre = 6;
using Chain = std::array<int, 4>;
constexpr Chain kMsrArmA{0, 7, 9, 11}, kMsrArmB{1, 8, 10, 12};
constexpr Chain kMsrLegA{4, 13, 15, 17}, kMsrLegB{5, 14, 16, 18};

// +1 when joint a lies on the subject's left of joint b over the recording, -1 on the right, 0
// when it cannot be told. The subject faces the camera, which looks along the depth axis z (the
// Kinect's camera space and the image frame (x right, y down, z depth) are both right-handed):
// facing = -sign(mean z) z, up = head - hip centre, and the subject's left = up x facing.
int side_vote(const RawSkeletonSequence& s, int a, int b) {
  const std::size_t fs = 60, frames = s.poses.size() / fs;
  double mean_z = 0;
  for (std::size_t t = 0; t < frames; ++t) mean_z += s.poses[t * fs + kMsrHipCentre * 3 + 2];
  if (mean_z == 0) return 0;
  const double facing_z = mean_z > 0 ? -1 : 1;
  double score = 0;
  for (std::size_t t = 0; t < frames; ++t) {
    const float* p = s.poses.data() + t * fs;
    const double up[2] = {double(p[kMsrHead * 3]) - p[kMsrHipCentre * 3],
                          double(p[kMsrHead * 3 + 1]) - p[kMsrHipCentre * 3 + 1]};
    // up x (0, 0, facing_z) = (up_y facing_z, -up_x facing_z, 0)
    const double left[2] = {up[1] * facing_z, -up[0] * facing_z};
    const double norm = std::hypot(left[0], left[1]);
    if (norm == 0) continue;
    score += ((double(p[a * 3]) - p[b * 3]) * left[0] +
              (double(p[a * 3 + 1]) - p[b * 3 + 1]) * left[1]) /
             norm;
  }
  return score > 0 ? 1 : score < 0 ? -1 : 0;
}

// Whether chain `a` is the subject's left in most recordings (ties: yes, the order the dataset's
// users publish), with one line saying how clear the geometry was.
bool chain_a_is_left(const RawSkeletonCollection& c, const Chain& a, const Chain& b,
                     const char* what) {
  std::size_t left = 0, right = 0;
  for (const auto& s : c.sequences) {
    const int v = side_vote(s, a[0], b[0]);
    left += v > 0;
    right += v < 0;
  }
  const bool a_left = left >= right;
  const Chain& l = a_left ? a : b;
  log::info(
      "MSR-Action3D: joints {}, {}, {}, {} taken as the {} (on the subject's left in {} of {} "
      "recordings, subjects facing the camera)",
      l[0] + 1, l[1] + 1, l[2] + 1, l[3] + 1, what, a_left ? left : right, c.sequences.size());
  if (std::min(left, right) * 5 > left + right)
    log::warn("MSR-Action3D: the {}'s side is unclear ({} recordings one way, {} the other)", what,
              left, right);
  return a_left;
}

// The recordings' joints from MSR-Action3D's order into the Kinect order (io::kinect_joint_names).
void reorder_msr_joints(RawSkeletonCollection& c) {
  const bool arm_a = chain_a_is_left(c, kMsrArmA, kMsrArmB, "left arm");
  const bool leg_a = chain_a_is_left(c, kMsrLegA, kMsrLegB, "left leg");
  const Chain& arm_l = arm_a ? kMsrArmA : kMsrArmB;
  const Chain& arm_r = arm_a ? kMsrArmB : kMsrArmA;
  const Chain& leg_l = leg_a ? kMsrLegA : kMsrLegB;
  const Chain& leg_r = leg_a ? kMsrLegB : kMsrLegA;
  std::array<int, 20> from{kMsrHipCentre, kMsrSpine, kMsrShoulderCentre, kMsrHead};
  for (std::size_t k = 0; k < 4; ++k) {
    from[4 + k] = arm_l[k];
    from[8 + k] = arm_r[k];
    from[12 + k] = leg_l[k];
    from[16 + k] = leg_r[k];
  }
  for (auto& s : c.sequences) {
    std::vector<float> kinect(s.poses.size());
    for (std::size_t t = 0; t * 60 < s.poses.size(); ++t)
      for (std::size_t j = 0; j < 20; ++j)
        for (std::size_t d = 0; d < 3; ++d)
          kinect[t * 60 + j * 3 + d] = s.poses[t * 60 + static_cast<std::size_t>(from[j]) * 3 + d];
    s.poses = std::move(kinect);
  }
}

}  // namespace

bool is_msr_action3d_name(const std::string& path) {
  static const std::regex name_re(R"(^a\d+_s\d+_e\d+_skeleton3D\.txt$)");
  return std::regex_match(fs::path(path).filename().string(), name_re);
}

RawSkeletonCollection read_msr_action3d(const std::vector<std::string>& files) {
  RawSkeletonCollection c = kinect_collection(kMsrRate);
  static const std::regex name_re(R"(^a(\d+)_s(\d+)_e(\d+)_skeleton3D\.txt$)");
  for (const auto& path : files) {
    const std::string base = fs::path(path).filename().string();
    std::smatch m;
    if (!std::regex_match(base, m, name_re))
      throw InvalidInput("not an MSR-Action3D skeleton file name (aXX_sYY_eZZ_skeleton3D.txt)",
                         path);
    const int action = std::stoi(m[1].str());
    RawSkeletonSequence s;
    s.name = fmt::format("a{}_s{}_e{}", m[1].str(), m[2].str(), m[3].str());
    s.label = action >= 1 && action <= 20 ? msr_action_names()[static_cast<std::size_t>(action - 1)]
                                          : "a" + m[1].str();
    s.subject = std::stoi(m[2].str());
    auto in = open_text(path);
    std::size_t lineno = 0, joint = 0;
    for (std::string line; std::getline(in, line);) {
      ++lineno;
      const auto v = numbers(line, path, lineno);
      if (v.empty()) continue;
      if (v.size() != 4)
        throw InvalidInput(fmt::format("expected 'x y z confidence', found {} numbers", v.size()),
                           at_line(path, lineno));
      for (int k = 0; k < 3; ++k)
        s.poses.push_back(static_cast<float>(v[static_cast<std::size_t>(k)]));
      if (++joint == 20) {
        s.times.push_back(static_cast<double>(s.times.size()) / kMsrRate);
        joint = 0;
      }
    }
    if (joint != 0)
      throw InvalidInput(fmt::format("the last frame has {} of 20 joint lines", joint),
                         at_line(path, lineno));
    if (s.times.size() < 2) throw InvalidInput(fmt::format("{} frame(s)", s.times.size()), path);
    c.sequences.push_back(std::move(s));
  }
  reorder_msr_joints(c);
  return c;
}

const std::vector<JointLayout>& joint_array_layouts() {
  static const std::vector<JointLayout> layouts = [] {
    const std::vector<std::string> smpl{
        "pelvis",     "left_hip",      "right_hip",      "spine1",      "left_knee",
        "right_knee", "spine2",        "left_ankle",     "right_ankle", "spine3",
        "left_foot",  "right_foot",    "neck",           "left_collar", "right_collar",
        "head",       "left_shoulder", "right_shoulder", "left_elbow",  "right_elbow",
        "left_wrist", "right_wrist",   "left_hand",      "right_hand"};
    const std::vector<std::int32_t> smpl_parents{-1, 0, 0, 0,  1,  2,  3,  4,  5,  6,  7,  8,
                                                 9,  9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21};
    return std::vector<JointLayout>{
        {"SMPL's 22 body joints (HumanML3D, AMASS-derived sets)",
         {smpl.begin(), smpl.begin() + 22},
         {smpl_parents.begin(), smpl_parents.begin() + 22}},
        {"SMPL's 24 joints (HumanAct12)", smpl, smpl_parents},
        {"Kinect v2's 25 joints (NTU RGB+D)",
         {"spine_base",     "spine_mid",     "neck",       "head",           "shoulder_left",
          "elbow_left",     "wrist_left",    "hand_left",  "shoulder_right", "elbow_right",
          "wrist_right",    "hand_right",    "hip_left",   "knee_left",      "ankle_left",
          "foot_left",      "hip_right",     "knee_right", "ankle_right",    "foot_right",
          "spine_shoulder", "hand_tip_left", "thumb_left", "hand_tip_right", "thumb_right"},
         {-1, 0, 20, 2, 20, 4, 5, 6, 20, 8, 9, 10, 0, 12, 13, 14, 0, 16, 17, 18, 1, 7, 7, 11, 11}}};
  }();
  return layouts;
}

namespace {

// The joints' names and parents from a "NAME PARENT" list, or the layout of their count.
void joint_layout(RawSkeletonCollection& c, std::size_t joints, const std::string& joints_file,
                  const std::string& first_file) {
  if (joints_file.empty()) {
    for (const auto& l : joint_array_layouts())
      if (l.names.size() == joints) {
        log::info("{} joints: taken as {} (give --joints FILE if they are not)", joints, l.what);
        c.joint_names = l.names, c.parents = l.parents;
        return;
      }
    throw InvalidInput(fmt::format("{} joints per frame, not a layout skel2h5 knows (22, 24 or "
                                   "25): give --joints FILE, lines 'NAME PARENT' in their order",
                                   joints),
                       first_file);
  }
  for (const auto& [n, w] : read_word_lines(joints_file, "the joint list")) {
    if (w.size() != 2)
      throw InvalidInput("expected 'NAME PARENT' (PARENT an earlier joint's name, or -)",
                         at_line(joints_file, n));
    std::int32_t parent = -1;
    if (w[1] != "-") {
      const auto it = std::find(c.joint_names.begin(), c.joint_names.end(), w[1]);
      if (it == c.joint_names.end())
        throw InvalidInput(fmt::format("parent '{}' is not an earlier joint", w[1]),
                           at_line(joints_file, n));
      parent = static_cast<std::int32_t>(it - c.joint_names.begin());
    }
    if (std::find(c.joint_names.begin(), c.joint_names.end(), w[0]) != c.joint_names.end())
      throw InvalidInput(fmt::format("joint '{}' named twice", w[0]), at_line(joints_file, n));
    c.joint_names.push_back(w[0]);
    c.parents.push_back(parent);
  }
  if (std::count(c.parents.begin(), c.parents.end(), -1) != 1)
    throw InvalidInput("the joints need exactly one root (parent -)", joints_file);
  if (c.joint_names.size() != joints)
    throw InvalidInput(
        fmt::format("names {} joints, the arrays have {} per frame", c.joint_names.size(), joints),
        joints_file);
}

}  // namespace

namespace {

// One sequence's joint array and what its file says of it.
struct ArraySequence {
  std::string name;   ///< the file's stem, or STEM/KEY (and _i) inside a .npz of several
  std::string where;  ///< for errors: the file, or "FILE (KEY)"
  std::int64_t frames = 0, joints = 0;
  std::vector<double> poses;  ///< [frames, joints, 3]
  std::string label;          ///< from the archive ("" = none)
  std::int32_t subject = 0;   ///< from the archive (0 = none)
};

bool is_sequence_array(const io::NpyArray& a) {
  return !a.is_text() &&
         ((a.shape.size() == 3 && a.shape[2] == 3) || (a.shape.size() == 4 && a.shape[3] == 3));
}

// A .npy file: one sequence, [frames, joints, 3].
ArraySequence npy_sequence(const std::string& path) {
  io::NpyArray a = io::read_npy(path);
  if (a.is_text() || a.shape.size() != 3 || a.shape[2] != 3)
    throw InvalidInput(fmt::format("an array of shape ({}): joint positions are [frames, "
                                   "joints, 3]",
                                   fmt::join(a.shape, ", ")),
                       path);
  ArraySequence q;
  q.name = fs::path(path).stem().string();
  q.where = path;
  q.frames = a.shape[0];
  q.joints = a.shape[1];
  q.poses = std::move(a.values);
  return q;
}

// An archive member's values as class names (integers as their decimal text) or subjects.
std::vector<std::string> label_texts(const io::NpyArray& a, const std::string& where) {
  if (a.is_text()) return a.strings;
  std::vector<std::string> out;
  for (const double v : a.values) {
    if (v != std::floor(v) || std::abs(v) > 1e15)
      throw InvalidInput(fmt::format("label {} is neither text nor an integer", v), where);
    out.push_back(fmt::format("{}", static_cast<std::int64_t>(v)));
  }
  return out;
}

// A .npz archive (np.savez): each member [frames, joints, 3] one sequence, each [n, frames,
// joints, 3] n of them; a member 'label' / 'labels' / 'action' / 'y' gives their classes and
// 'subject' / 'subjects' their subjects, one per sequence in the archive's order.
std::vector<ArraySequence> npz_sequences(const std::string& path) {
  const std::vector<io::NpzMember> members = io::read_npz(path);
  const std::string stem = fs::path(path).stem().string();
  std::vector<ArraySequence> out;
  const io::NpzMember *labels = nullptr, *subjects = nullptr;
  std::vector<std::string> ignored;
  for (const auto& m : members) {
    const std::string where = fmt::format("{} ({})", path, m.name);
    if (m.name == "label" || m.name == "labels" || m.name == "action" || m.name == "y") {
      if (labels) throw InvalidInput("labels given by two members", where);
      labels = &m;
    } else if (m.name == "subject" || m.name == "subjects") {
      if (subjects) throw InvalidInput("subjects given by two members", where);
      subjects = &m;
    } else if (!is_sequence_array(m.array)) {
      ignored.push_back(fmt::format("{} ({})", m.name, fmt::join(m.array.shape, ", ")));
    } else {
      const auto& a = m.array;
      const bool several = a.shape.size() == 4;
      const std::int64_t n = several ? a.shape[0] : 1;
      const auto size =
          static_cast<std::size_t>(a.shape[several ? 1 : 0] * a.shape[several ? 2 : 1] * 3);
      for (std::int64_t i = 0; i < n; ++i) {
        ArraySequence q;
        q.name =
            several ? fmt::format("{}/{}_{}", stem, m.name, i) : fmt::format("{}/{}", stem, m.name);
        q.where = where;
        q.frames = a.shape[several ? 1 : 0];
        q.joints = a.shape[several ? 2 : 1];
        const auto first =
            a.values.begin() + static_cast<std::ptrdiff_t>(i) * static_cast<std::ptrdiff_t>(size);
        q.poses.assign(first, first + static_cast<std::ptrdiff_t>(size));
        out.push_back(std::move(q));
      }
    }
  }
  if (out.empty())
    throw InvalidInput(fmt::format("no member of shape [frames, joints, 3] (members: {})",
                                   fmt::join(ignored, ", ")),
                       path);
  if (!ignored.empty())
    log::warn("{}: members that are not joint arrays were left out: {}", path,
              fmt::join(ignored, ", "));
  if (out.size() == 1) out.front().name = stem;
  const auto one_per_sequence = [&](const io::NpzMember& m) {
    const std::string where = fmt::format("{} ({})", path, m.name);
    std::vector<std::string> v = label_texts(m.array, where);
    if (v.size() != out.size())
      throw InvalidInput(
          fmt::format("{} values for the archive's {} sequences", v.size(), out.size()), where);
    return v;
  };
  if (labels) {
    const auto v = one_per_sequence(*labels);
    for (std::size_t i = 0; i < out.size(); ++i) out[i].label = v[i];
  }
  if (subjects) {
    const auto v = one_per_sequence(*subjects);
    for (std::size_t i = 0; i < out.size(); ++i) {
      std::int32_t s = 0;
      const auto [stop, ec] = std::from_chars(v[i].data(), v[i].data() + v[i].size(), s);
      if (ec != std::errc() || stop != v[i].data() + v[i].size() || s < 1)
        throw InvalidInput(fmt::format("subject '{}' is not a positive integer", v[i]),
                           fmt::format("{} ({})", path, subjects->name));
      out[i].subject = s;
    }
  }
  return out;
}

}  // namespace

RawSkeletonCollection read_joint_arrays(const std::vector<std::string>& files,
                                        const std::string& label, const JointArrayOptions& opt) {
  if (!(opt.fps > 0)) throw UsageError("--source-fps must be positive");
  struct Label {
    std::string label;
    std::int32_t subject = 0;
  };
  std::map<std::string, Label> labels;  // by file stem
  if (!opt.labels_file.empty())
    for (const auto& [n, w] : read_word_lines(opt.labels_file, "the labels list")) {
      if (w.size() < 2 || w.size() > 3)
        throw InvalidInput("expected 'NAME CLASS [SUBJECT]'", at_line(opt.labels_file, n));
      std::int32_t subject = 0;
      if (w.size() == 3) {
        const auto [stop, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), subject);
        if (ec != std::errc() || stop != w[2].data() + w[2].size() || subject < 1)
          throw InvalidInput(fmt::format("subject '{}' is not a positive integer", w[2]),
                             at_line(opt.labels_file, n));
      }
      if (!labels.emplace(w[0], Label{w[1], subject}).second)
        throw InvalidInput(fmt::format("'{}' is labelled twice", w[0]),
                           at_line(opt.labels_file, n));
    }
  RawSkeletonCollection c;
  c.frame_rate = opt.fps;
  for (const auto& path : files) {
    std::vector<ArraySequence> found;
    if (fs::path(path).extension() == ".npz")
      found = npz_sequences(path);
    else
      found.push_back(npy_sequence(path));
    for (auto& a : found) {
      if (a.frames < 1 || a.joints < 1)
        throw InvalidInput(fmt::format("an array of {} frames of {} joints", a.frames, a.joints),
                           a.where);
      const auto joints = static_cast<std::size_t>(a.joints);
      if (c.joint_names.empty()) joint_layout(c, joints, opt.joints_file, a.where);
      if (joints != c.joints())
        throw InvalidInput(
            fmt::format("{} joints per frame where {} had {}", joints, files.front(), c.joints()),
            a.where);
      for (std::size_t k = 0; k < a.poses.size(); ++k)
        if (!std::isfinite(a.poses[k]))
          throw InvalidInput(fmt::format("a non-finite coordinate at frame {} joint {}",
                                         k / (joints * 3), k / 3 % joints),
                             a.where);
      RawSkeletonSequence q;
      q.name = a.name;
      if (!opt.labels_file.empty()) {
        const auto it = labels.find(q.name);
        if (it == labels.end())
          throw InvalidInput(fmt::format("has no line '{} CLASS' in {}", q.name, opt.labels_file),
                             a.where);
        q.label = it->second.label, q.subject = it->second.subject;
      } else {
        q.label = !label.empty()     ? label
                  : !a.label.empty() ? a.label
                                     : fs::path(path).parent_path().filename().string();
        q.subject = a.subject;
        if (q.label.empty() || q.label == "." || q.label == "..")
          throw InvalidInput(
              "has no class: give --labels FILE or --label, put each class's files in a folder "
              "of its name, or (.npz) store a member 'label'",
              a.where);
      }
      for (std::int64_t t = 0; t < a.frames; ++t)
        q.times.push_back(static_cast<double>(t) / opt.fps);
      q.poses.assign(a.poses.begin(), a.poses.end());
      c.sequences.push_back(std::move(q));
    }
  }
  return c;
}

RawSkeletonCollection read_skeleton_h5(const std::string& path) {
  const io::SkeletonFile f = io::read_skeleton_file(path);
  if (f.dims != 3) throw InvalidInput("2-D skeleton files are not supported here", path);
  RawSkeletonCollection c;
  c.joint_names = f.joint_names;
  c.parents = f.parents;
  c.frame_rate = f.frame_rate;
  const std::vector<float> raw = f.raw_poses();
  for (std::size_t s = 0; s < f.sequences(); ++s) {
    RawSkeletonSequence q;
    q.name = f.sequence_names[s].empty() ? fmt::format("sequence_{}", s) : f.sequence_names[s];
    q.label = f.class_names.at(static_cast<std::size_t>(f.labels[s]));
    q.subject = f.subjects.empty() ? 0 : f.subjects[s];
    for (auto t = f.offsets[s]; t < f.offsets[s + 1]; ++t) {
      q.times.push_back(static_cast<double>(t - f.offsets[s]) / f.frame_rate);
      const auto* p = raw.data() + static_cast<std::size_t>(t) * f.frame_size();
      q.poses.insert(q.poses.end(), p, p + f.frame_size());
    }
    c.sequences.push_back(std::move(q));
  }
  return c;
}

}  // namespace df::convert
