#include "io/skeleton_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "io/schema.h"

namespace df::io {

namespace {

// Mixture weights: none negative and every row summing to 1 (to rounding); the schema has checked
// shape and finiteness.
std::vector<float> read_label_weights(const h5::File& f, std::size_t sequences,
                                      std::size_t classes) {
  std::vector<float> w = f.read<float>("/sequences/label_weights").data;
  for (std::size_t s = 0; s < sequences; ++s) {
    double sum = 0;
    for (std::size_t c = 0; c < classes; ++c) {
      if (w[s * classes + c] < 0)
        throw InvalidInput(fmt::format("a negative weight in row {}", s),
                           f.where("/sequences/label_weights"));
      sum += w[s * classes + c];
    }
    if (std::abs(sum - 1) > 1e-4)
      throw InvalidInput(fmt::format("row {} sums to {:g}, not 1", s, sum),
                         f.where("/sequences/label_weights"));
  }
  return w;
}

}  // namespace

void SkeletonFile::joint(std::size_t t, std::size_t j, double out[3]) const {
  const float* p = poses.data() + (t * joints + j) * static_cast<std::size_t>(dims);
  out[0] = p[0];
  out[1] = p[1];
  out[2] = dims == 3 ? p[2] : 0.0;
}

bool SkeletonFile::is_mixture(std::size_t s) const {
  if (label_weights.empty()) return false;
  const float* w = label_weights.data() + s * class_names.size();
  return std::count_if(w, w + class_names.size(), [](float x) { return x > 0; }) > 1;
}

std::string SkeletonFile::label_text(std::size_t s) const {
  const auto label = static_cast<std::size_t>(labels[s]);
  if (!is_mixture(s)) return label < class_names.size() ? class_names[label] : "?";
  std::string text;
  for (std::size_t c = 0; c < class_names.size(); ++c)
    if (const float w = label_weights[s * class_names.size() + c]; w > 0)
      text += fmt::format("{}{} {:.2f}", text.empty() ? "" : " + ", class_names[c], w);
  return text;
}

SkeletonFile read_skeleton_file(const std::string& path) {
  Dimensions d;
  h5::File f = open_input(path, "skeleton", &d);
  SkeletonFile s;
  s.frames = d.at("T");
  s.joints = d.at("J");
  s.dims = static_cast<int>(d.at("D"));
  s.poses = f.read<float>("/poses").data;
  check_finite_rows(s.poses.data(), 0, s.frames, s.joints * static_cast<std::size_t>(s.dims),
                    f.where("/poses"));
  s.offsets = f.read<std::int64_t>("/sequences/offsets").data;
  s.sequence_names = f.exists("/sequences/names") ? f.read_strings("/sequences/names")
                                                  : std::vector<std::string>(s.sequences());
  s.labels = f.read<std::int32_t>("/sequences/labels").data;
  read_classes_and_skeleton(f, s.class_names, s.parents, s.joint_names);
  s.frame_rate = f.attr_double("/", "frame_rate");
  if (f.exists("/sequences/subjects"))
    s.subjects = f.read<std::int32_t>("/sequences/subjects").data;
  if (f.exists("/sequences/test")) s.test = f.read<std::int32_t>("/sequences/test").data;
  if (f.exists("/sequences/label_weights"))
    s.label_weights = read_label_weights(f, s.sequences(), s.class_names.size());
  s.normalization = read_pose_normalization(f);
  return s;
}

void write_skeleton_data(h5::File& f, const SkeletonFile& s) {
  f.set_attr("/", "frame_rate", s.frame_rate);
  f.write<float>("/poses", s.poses, {s.frames, s.joints, static_cast<std::size_t>(s.dims)});
  f.write<std::int64_t>("/sequences/offsets", s.offsets, {s.offsets.size()});
  f.write<std::int32_t>("/sequences/labels", s.labels, {s.labels.size()});
  if (!s.sequence_names.empty()) f.write_strings("/sequences/names", s.sequence_names);
  write_classes_and_skeleton(f, s.class_names, s.parents, s.joint_names);
  if (!s.subjects.empty())
    f.write<std::int32_t>("/sequences/subjects", s.subjects, {s.subjects.size()});
  if (!s.test.empty()) f.write<std::int32_t>("/sequences/test", s.test, {s.test.size()});
  if (!s.label_weights.empty())
    f.write<float>("/sequences/label_weights", s.label_weights,
                   {s.sequences(), s.class_names.size()});
  write_pose_normalization(f, s.normalization, s.dims);
}

void write_classes_and_skeleton(h5::File& f, const std::vector<std::string>& class_names,
                                const std::vector<std::int32_t>& parents,
                                const std::vector<std::string>& joint_names) {
  f.write_strings("/classes/names", class_names);
  f.write<std::int32_t>("/skeleton/parents", parents, {parents.size()});
  f.write_strings("/skeleton/joint_names", joint_names);
}

void read_classes_and_skeleton(const h5::File& f, std::vector<std::string>& class_names,
                               std::vector<std::int32_t>& parents,
                               std::vector<std::string>& joint_names) {
  class_names = f.read_strings("/classes/names");
  parents = f.read<std::int32_t>("/skeleton/parents").data;
  joint_names = f.read_strings("/skeleton/joint_names");
}

void write_pose_normalization(h5::File& f, const SkeletonNormalization& n, int dims) {
  if (!n.present()) return;
  const std::vector<std::size_t> shape{n.mean.size() / static_cast<std::size_t>(dims),
                                       static_cast<std::size_t>(dims)};
  f.write<double>("/normalization/mean", n.mean, shape);
  f.write<double>("/normalization/std", n.std, shape);
  f.set_attr("/normalization", "root_joint", n.root_joint);
  f.set_attr("/normalization", "scale", n.scale);
}

SkeletonNormalization read_pose_normalization(const h5::File& f) {
  SkeletonNormalization n;
  if (!f.exists("/normalization")) return n;
  n.root_joint = static_cast<int>(f.attr_int("/normalization", "root_joint"));
  n.scale = f.attr_double("/normalization", "scale");
  n.mean = f.read<double>("/normalization/mean").data;
  n.std = f.read<double>("/normalization/std").data;
  return n;
}

std::vector<float> SkeletonFile::raw_poses() const {
  if (!normalization.present()) return poses;
  std::vector<float> raw(poses.size());
  const std::size_t fs = frame_size();
  for (std::size_t t = 0; t < frames; ++t)
    for (std::size_t k = 0; k < fs; ++k)
      raw[t * fs + k] = static_cast<float>(
          (poses[t * fs + k] * normalization.std[k] + normalization.mean[k]) * normalization.scale);
  return raw;  // root-centred: the root's trajectory is not kept
}

std::vector<float> poses_normalized_as(const SkeletonFile& s, const SkeletonNormalization& b) {
  const auto& a = s.normalization;
  const bool same = a.present() == b.present() &&
                    (!a.present() || (a.root_joint == b.root_joint && a.scale == b.scale &&
                                      a.mean == b.mean && a.std == b.std));
  if (same) return s.poses;
  std::vector<float> raw = s.raw_poses();
  if (!b.present()) return raw;
  const std::size_t fs = s.frame_size(), dims = static_cast<std::size_t>(s.dims);
  const auto root = static_cast<std::size_t>(b.root_joint) * dims;
  for (std::size_t t = 0; t < s.frames; ++t) {
    float* p = raw.data() + t * fs;
    std::vector<float> r(p + root, p + root + dims);
    for (std::size_t k = 0; k < fs; ++k)
      p[k] = static_cast<float>(((p[k] - r[k % dims]) / b.scale - b.mean[k]) / b.std[k]);
  }
  return raw;
}

const std::vector<std::string>& kinect_joint_names() {
  static const std::vector<std::string> names{
      "hip_center",  "spine",      "shoulder_center", "head",           "shoulder_left",
      "elbow_left",  "wrist_left", "hand_left",       "shoulder_right", "elbow_right",
      "wrist_right", "hand_right", "hip_left",        "knee_left",      "ankle_left",
      "foot_left",   "hip_right",  "knee_right",      "ankle_right",    "foot_right"};
  return names;
}

const std::vector<std::int32_t>& kinect_joint_parents() {
  static const std::vector<std::int32_t> parents{-1, 0,  1, 2,  2,  4,  5, 6,  2,  8,
                                                 9,  10, 0, 12, 13, 14, 0, 16, 17, 18};
  return parents;
}

}  // namespace df::io
