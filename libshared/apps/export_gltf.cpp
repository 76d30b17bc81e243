#include "apps/export_gltf.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "convert/frame_set.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/vertex_normals.h"
#include "io/gltf_file.h"

namespace df::apps {
namespace {

// The frames to export: one sequence's (by name) or all, every K-th.
std::vector<std::size_t> chosen_frames(const convert::FrameSet& fs, const ExportGltfOptions& opt) {
  std::size_t first = 0, last = fs.size();
  if (!opt.sequence.empty()) {
    const auto it = std::find(fs.sequences.begin(), fs.sequences.end(), opt.sequence);
    if (it == fs.sequences.end())
      throw UsageError(fmt::format("--sequence: {} has no sequence '{}'", opt.input, opt.sequence));
    const auto s = static_cast<std::size_t>(it - fs.sequences.begin());
    first = static_cast<std::size_t>(fs.offsets[s]), last = static_cast<std::size_t>(fs.offsets[s + 1]);
  }
  std::vector<std::size_t> frames;
  for (std::size_t i = first; i < last; i += static_cast<std::size_t>(opt.every)) frames.push_back(i);
  return frames;
}

}  // namespace

void export_gltf(const ExportGltfOptions& opt, const CommonOptions& common) {
  if (!(opt.fps > 0)) throw UsageError("--fps must be positive");
  if (opt.every < 1) throw UsageError("--every must be at least 1");
  convert::FrameSet fs = convert::read_frame_set(opt.input);
  const auto frames = chosen_frames(fs, opt);
  if (frames.empty()) throw InvalidInput("no frames to export", opt.input);
  convert::reconstruct(fs, &frames);
  io::GltfSequence seq;
  seq.faces = fs.tmpl.faces;
  seq.fps = opt.fps;
  seq.name = opt.sequence.empty() ? "deformflow" : opt.sequence;
  for (auto i : frames) seq.frames.push_back(fs.positions[i]);
  seq.normals.resize(frames.size());
  tbb::parallel_for(std::size_t{0}, frames.size(),
                    [&](std::size_t k) { seq.normals[k] = geometry::vertex_normals(seq.frames[k], seq.faces); });
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force, {opt.input});
  io::write_gltf_sequence(out.temp_path().string(), seq);
  out.commit();
  log::info("wrote {}: {} frames of {} vertices as morph targets, {:.3g} s at {:g} fps", opt.output, frames.size(),
            fs.vertices(), static_cast<double>(frames.size() - 1) / opt.fps, opt.fps);
}

}  // namespace df::apps
