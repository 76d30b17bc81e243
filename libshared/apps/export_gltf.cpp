#include "apps/export_gltf.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>

#include "apps/sequence_choice.h"
#include "convert/frame_set.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/vertex_normals.h"
#include "io/gltf_file.h"
#include "io/h5.h"
#include "io/schema.h"
#include "io/skeleton_file.h"

namespace df::apps {
namespace {

// The frames to export: one sequence's (by name or index) or all, every K-th.
std::vector<std::size_t> chosen_frames(const convert::FrameSet& fs, const ExportGltfOptions& opt) {
  std::size_t first = 0, last = fs.size();
  if (!opt.sequence.empty()) {
    const std::size_t s = sequence_index(opt.sequence, fs.sequences, opt.input);
    first = static_cast<std::size_t>(fs.offsets[s]),
    last = static_cast<std::size_t>(fs.offsets[s + 1]);
  }
  std::vector<std::size_t> frames;
  for (std::size_t i = first; i < last; i += static_cast<std::size_t>(opt.every))
    frames.push_back(i);
  return frames;
}

// One sequence of a skeleton file (by name or index; the first by default), every K-th frame, its
// normalization undone, as animated joints.
void export_skeleton(const ExportGltfOptions& opt, const CommonOptions& common) {
  const io::SkeletonFile s = io::read_skeleton_file(opt.input);
  std::size_t seq = 0;
  if (!opt.sequence.empty()) {
    seq = sequence_index(opt.sequence, s.sequence_names, opt.input);
  } else if (s.sequences() > 1) {
    log::info("{} holds {} sequences: exporting the first ('{}'; --sequence chooses)", opt.input,
              s.sequences(), s.sequence_names.front());
  }
  if (s.dims != 3) throw InvalidInput("has 2-D poses: glTF joints need 3-D ones", opt.input);
  const std::vector<float> raw = s.raw_poses();
  io::GltfSkeleton g;
  g.parents = s.parents;
  g.joint_names = s.joint_names;
  g.fps = (opt.fps > 0 ? opt.fps : s.frame_rate) / opt.every;
  g.name = s.sequence_names[seq].empty() ? "sequence" + std::to_string(seq) : s.sequence_names[seq];
  const std::size_t fs = s.frame_size();
  for (auto t = static_cast<std::size_t>(s.offsets[seq]);
       t < static_cast<std::size_t>(s.offsets[seq + 1]); t += static_cast<std::size_t>(opt.every))
    g.positions.insert(g.positions.end(), raw.begin() + static_cast<std::ptrdiff_t>(t * fs),
                       raw.begin() + static_cast<std::ptrdiff_t>((t + 1) * fs));
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force, {opt.input});
  io::write_gltf_skeleton(out.temp_path().string(), g);
  out.commit();
  log::info("wrote {}: sequence '{}', {} frames of {} joints at {:g} fps", opt.output, g.name,
            g.positions.size() / fs, s.joints, g.fps);
}

}  // namespace

void export_gltf(const ExportGltfOptions& opt, const CommonOptions& common) {
  if (opt.fps < 0) throw UsageError("--fps must be positive");
  if (opt.every < 1) throw UsageError("--every must be at least 1");
  const OutputClaim claim = claim_output(opt.output, common.force, {opt.input});
  if (io::is_hdf5_path(opt.input) && std::filesystem::exists(opt.input) &&
      io::declared_kind(h5::File(opt.input, h5::File::Mode::read)) == "skeleton")
    return export_skeleton(opt, common);
  convert::FrameSet fs = convert::read_frame_set(opt.input);
  const auto frames = chosen_frames(fs, opt);
  if (frames.empty()) throw InvalidInput("no frames to export", opt.input);
  convert::reconstruct(fs, &frames);
  io::GltfSequence seq;
  seq.faces = fs.tmpl.faces;
  seq.fps = (opt.fps > 0 ? opt.fps : 30.0) / opt.every;  // every K-th frame at the same speed
  seq.name = opt.sequence.empty() ? "deformflow" : opt.sequence;
  for (auto i : frames) seq.frames.push_back(fs.positions[i]);
  seq.normals.resize(frames.size());
  tbb::parallel_for(std::size_t{0}, frames.size(), [&](std::size_t k) {
    seq.normals[k] = geometry::vertex_normals(seq.frames[k], seq.faces);
  });
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force, {opt.input});
  io::write_gltf_sequence(out.temp_path().string(), seq);
  out.commit();
  log::info(
      "wrote {}: {} frames of {} vertices as morph targets at {:g} fps (the animation plays {:.3g} "
      "s)",
      opt.output, frames.size(), fs.vertices(), seq.fps,
      static_cast<double>(frames.size() - 1) / seq.fps);
}

}  // namespace df::apps
