#include "io/skeleton_file.h"

#include "io/schema.h"

namespace df::io {

void SkeletonFile::joint(std::size_t t, std::size_t j, double out[3]) const {
  const float* p = poses.data() + (t * joints + j) * static_cast<std::size_t>(dims);
  out[0] = p[0];
  out[1] = p[1];
  out[2] = dims == 3 ? p[2] : 0.0;
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
  s.class_names = f.read_strings("/classes/names");
  s.parents = f.read<std::int32_t>("/skeleton/parents").data;
  s.joint_names = f.read_strings("/skeleton/joint_names");
  s.frame_rate = f.attr_double("/", "frame_rate");
  return s;
}

void write_skeleton_data(h5::File& f, const SkeletonFile& s) {
  f.set_attr("/", "frame_rate", s.frame_rate);
  f.write<float>("/poses", s.poses, {s.frames, s.joints, static_cast<std::size_t>(s.dims)});
  f.write<std::int64_t>("/sequences/offsets", s.offsets, {s.offsets.size()});
  f.write<std::int32_t>("/sequences/labels", s.labels, {s.labels.size()});
  if (!s.sequence_names.empty()) f.write_strings("/sequences/names", s.sequence_names);
  f.write_strings("/classes/names", s.class_names);
  f.write<std::int32_t>("/skeleton/parents", s.parents, {s.parents.size()});
  f.write_strings("/skeleton/joint_names", s.joint_names);
}

}  // namespace df::io
