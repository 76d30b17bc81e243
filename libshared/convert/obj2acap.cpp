#include "convert/obj2acap.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <filesystem>

#include "convert/frame_reader.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/acap_file.h"

namespace fs = std::filesystem;

namespace df::convert {
namespace {
using geometry::kFeatureDims;

std::vector<fs::path> as_paths(const std::vector<std::string>& v) {
  return {v.begin(), v.end()};
}

// Class names in order of first appearance and each sequence's class index; no labels at all
// gives empty results, some but not all labels is an error.
void labels_of(const std::vector<SequenceInfo>& seqs, std::vector<std::string>& classes,
               std::vector<std::int32_t>& index) {
  std::size_t labelled =
      std::count_if(seqs.begin(), seqs.end(), [](const auto& s) { return !s.label.empty(); });
  if (labelled == 0) return;
  for (const auto& s : seqs) {
    if (s.label.empty())
      throw UsageError("sequence '" + s.name +
                       "' has no label while others have; give --labels for every sequence");
    auto it = std::find(classes.begin(), classes.end(), s.label);
    if (it == classes.end()) {
      classes.push_back(s.label);
      it = classes.end() - 1;
    }
    index.push_back(static_cast<std::int32_t>(it - classes.begin()));
  }
}

}  // namespace

namespace {

// The reader's sequences with --labels given to them (one per sequence), and the classes.
struct Labelled {
  std::vector<SequenceInfo> sequences;
  std::vector<std::string> classes;
  std::vector<std::int32_t> label_index;
};

Labelled labelled_sequences(const FrameReader& reader, const std::vector<std::string>& labels) {
  Labelled l{reader.sequences(), {}, {}};
  if (!labels.empty()) {
    if (labels.size() != l.sequences.size())
      throw UsageError(fmt::format("--labels gives {} labels for {} sequences", labels.size(),
                                   l.sequences.size()));
    for (std::size_t s = 0; s < l.sequences.size(); ++s) l.sequences[s].label = labels[s];
  }
  labels_of(l.sequences, l.classes, l.label_index);
  return l;
}

// The template: --reference, or the first frame.
Mesh read_reference(FrameReader& reader, const std::string& reference) {
  if (reference.empty()) return reader.read(0);
  io::MeshReadReport rep;
  Mesh mesh = io::read_mesh(reference, &rep);
  io::warn_about(rep, reference);
  return mesh;
}

// Template, frame names, sequences and labels, and the three datasets the frames fill.
std::vector<std::string> write_layout(io::AcapWriter& f, const FrameReader& reader,
                                      const Labelled& l, const Mesh& reference) {
  const std::size_t n = reader.size(), nv = static_cast<std::size_t>(reference.vertices.rows());
  f.write_template(reference);
  std::vector<std::string> frame_names, seq_names;
  std::vector<std::int64_t> offsets{0};
  for (std::size_t i = 0; i < n; ++i) frame_names.push_back(reader.frame_name(i));
  for (const auto& s : l.sequences) {
    seq_names.push_back(s.name);
    offsets.push_back(static_cast<std::int64_t>(s.first + s.count));
  }
  f.write_frame_names(frame_names);
  f.write_sequences(offsets, seq_names);
  if (!l.classes.empty()) f.write_labels(l.label_index, l.classes);
  f.create_positions(n, nv);
  f.create_raw(n, nv);
  f.create_normalized(n, nv);
  return frame_names;
}

// A block of frames: read, then decomposed by the parallel stage; written by the in-order one.
struct Block {
  std::size_t first = 0, count = 0;
  std::vector<Vertices> positions;
  std::vector<geometry::FrameDecomposition> dec;
  std::exception_ptr error;  // the block's first bad frame, thrown by the in-order stage
};

// The parallel stage: each frame of the block read (frame 0 is the template when no --reference
// names another) and decomposed T = RS, log R; the first bad frame kept for the in-order stage.
void decompose_block(Block& b, FrameReader& reader, const Mesh& reference,
                     const std::string& reference_name, const Obj2AcapOptions& opt,
                     const geometry::AcapFeatureExtractor& extractor) {
  b.positions.resize(b.count);
  b.dec.resize(b.count);
  std::vector<std::exception_ptr> errors(b.count);
  tbb::parallel_for(std::size_t{0}, b.count, [&](std::size_t k) {
    const std::size_t i = b.first + k;
    try {
      b.positions[k] = (i == 0 && opt.reference.empty())
                           ? reference.vertices
                           : reader.read_positions(i, reference, reference_name);
      extractor.decompose(b.positions[k], b.dec[k]);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  });
  for (auto& e : errors)
    if (e && !b.error) b.error = e;
}

// Every frame's positions and raw features, written in order; returns their normalization.
// A pipeline over blocks of frames: read + decompose T = RS, log R (parallel) -> consistency in
// time order (the first frame of each sequence without a temporal prior), pack, write (in order).
// The in-order stage of one block overlaps with the parallel stage of the next. A bad frame is
// reported deterministically: the first one.
geometry::Normalization extract_features(FrameReader& reader, const Labelled& l,
                                         const Mesh& reference, const std::string& reference_name,
                                         const std::vector<std::string>& frame_names,
                                         const Obj2AcapOptions& opt, io::AcapWriter& f) {
  const std::size_t n = reader.size(), nv = static_cast<std::size_t>(reference.vertices.rows());
  geometry::AcapFeatureExtractor extractor(reference.vertices, reference.faces,
                                           opt.consistency_options);
  log::debug("template: {} edges", extractor.topology().edges.size());
  std::vector<char> starts(n, 0);
  for (const auto& s : l.sequences)
    if (s.count) starts[s.first] = 1;
  geometry::NormalizationBuilder norm(opt.normalize);
  Progress progress("computing features", n);
  const std::size_t block = std::max<std::size_t>(1, opt.block_frames);
  geometry::FeatureSequence sequence(extractor, opt.consistency);
  std::vector<double> raw;
  std::vector<float> pos;
  double axis_gain = 0, angle_gain = 0, axis_before = 0, angle_before = 0;
  std::size_t next_first = 0;
  // The blocks live here, not in the pipeline's items: oneTBB does not destroy the items in
  // flight when a stage throws (a bad frame), so owning pointers leaked (found by the ASan
  // build). A finished block frees its frames.
  std::deque<Block> blocks;
  tbb::parallel_pipeline(
      4, tbb::make_filter<
             void, Block*>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) -> Block* {
           if (next_first >= n) {
             fc.stop();
             return nullptr;
           }
           Block* b = &blocks.emplace_back();
           b->first = next_first;
           b->count = std::min(block, n - next_first);
           next_first += b->count;
           return b;
         }) & tbb::make_filter<Block*, Block*>(tbb::filter_mode::parallel, [&](Block* b) {
           decompose_block(*b, reader, reference, reference_name, opt, extractor);
           return b;
         }) & tbb::make_filter<Block*, void>(tbb::filter_mode::serial_in_order, [&](Block* b) {
           if (b->error) std::rethrow_exception(b->error);
           const std::size_t first = b->first, count = b->count;
           raw.resize(count * nv * kFeatureDims);  // fully overwritten below
           pos.resize(count * nv * 3);
           for (std::size_t k = 0; k < count; ++k) {  // consistency: in time order
             const std::size_t i = first + k;
             const auto rep =
                 sequence.add(b->dec[k], starts[i] != 0, raw.data() + k * nv * kFeatureDims);
             if (!opt.consistency) continue;
             axis_before += rep.axis_before;
             angle_before += rep.angle_before;
             axis_gain += rep.axis_after - rep.axis_before;
             angle_gain += rep.angle_before - rep.angle_after;
             log::debug(
                 "frame {} ({}): axis agreement {} -> {}, angle spread {:.6g} -> {:.6g}, {} sweeps",
                 i, frame_names[i], rep.axis_before, rep.axis_after, rep.angle_before,
                 rep.angle_after, rep.sweeps);
           }
           for (std::size_t k = 0; k < count; ++k) {
             const double* p = b->positions[k].data();
             for (std::size_t c = 0; c < nv * 3; ++c)
               pos[k * nv * 3 + c] = static_cast<float>(p[c]);
           }
           norm.add(raw.data(), count * nv);
           f.write_positions_rows(first, count, pos.data());
           f.write_raw_rows(first, count, raw.data());
           progress.advance(count);
           *b = Block{};  // its frames are written
         }));
  progress.finish();
  if (opt.consistency)
    log::debug("consistency totals: axis agreement {} (+{}), angle spread {:.6g} (-{:.6g})",
               axis_before, axis_gain, angle_before, angle_gain);
  return norm.finish();
}

// The normalization over all frames, then the normalized copy, block by block.
void write_normalized(io::AcapWriter& f, const geometry::Normalization& nz, std::size_t n,
                      std::size_t nv, std::size_t block) {
  f.write_normalization(nz);
  std::vector<double> raw;
  std::vector<float> normalized;
  for (std::size_t first = 0; first < n; first += block) {
    const std::size_t count = std::min(block, n - first);
    raw.resize(count * nv * kFeatureDims);
    f.read_raw_rows(first, count, raw.data());
    normalized.resize(raw.size());
    for (std::size_t k = 0; k < raw.size(); ++k)
      normalized[k] = static_cast<float>(nz.normalize(static_cast<int>(k % kFeatureDims), raw[k]));
    f.write_normalized_rows(first, count, normalized.data());
  }
}

}  // namespace

void obj2acap(const Obj2AcapOptions& opt, const CommonOptions& common) {
  const auto t_start = std::chrono::steady_clock::now();
  const OutputClaim claim = claim_output(opt.output, common.force, as_paths(opt.inputs));
  FrameReader reader(opt.inputs);
  const Labelled labelled = labelled_sequences(reader, opt.labels);
  const std::size_t n = reader.size();
  if (n == 0) throw InvalidInput("the inputs hold no frames");
  const std::string reference_name = opt.reference.empty() ? reader.frame_origin(0) : opt.reference;
  const Mesh reference = read_reference(reader, opt.reference);
  const auto nv = static_cast<std::size_t>(reference.vertices.rows());

  auto inputs = as_paths(reader.input_paths());
  if (!opt.reference.empty()) inputs.emplace_back(opt.reference);
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force, inputs);
  log::info("{} frames in {} sequences, {} vertices, {} triangles; reference {}", n,
            labelled.sequences.size(), nv, reference.faces.rows(), reference_name);
  io::AcapWriter f(out.temp_path(), opt.output, reader.histories());
  const auto frame_names = write_layout(f, reader, labelled, reference);
  const geometry::Normalization nz =
      extract_features(reader, labelled, reference, reference_name, frame_names, opt, f);
  write_normalized(f, nz, n, nv, std::max<std::size_t>(1, opt.block_frames));
  f.close();
  out.commit();
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  log::info("wrote {}: {} frames x {} vertices in {:.2f} s ({:.3g} vertex-frames/s)", opt.output, n,
            nv, secs, static_cast<double>(n * nv) / secs);
}

}  // namespace df::convert
