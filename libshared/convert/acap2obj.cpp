#include "convert/acap2obj.h"

#include <fmt/args.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <set>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "geometry/acap_features.h"
#include "geometry/reconstruction.h"
#include "io/acap_file.h"
#include "io/mesh_io.h"
#include "io/schema.h"

namespace fs = std::filesystem;

namespace df::convert {
namespace {
using geometry::kFeatureDims;

// Max and mean vertex distance after aligning each connected component's centroid.
struct FrameError {
  double max = 0, mean = 0;
};
FrameError frame_error(const Vertices& P, const Vertices& truth, const std::vector<int>& component,
                       int nc) {
  Eigen::MatrixXd shift = Eigen::MatrixXd::Zero(nc, 3);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(nc);
  for (Eigen::Index v = 0; v < P.rows(); ++v) {
    shift.row(component[v]) += truth.row(v) - P.row(v);
    count[component[v]] += 1;
  }
  FrameError e;
  for (Eigen::Index v = 0; v < P.rows(); ++v) {
    double d = (P.row(v) + shift.row(component[v]) / count[component[v]] - truth.row(v)).norm();
    e.max = std::max(e.max, d);
    e.mean += d / static_cast<double>(P.rows());
  }
  return e;
}

}  // namespace

std::vector<std::size_t> parse_frame_selection(const std::string& spec, std::size_t n) {
  std::set<std::size_t> out;
  if (spec.empty()) {
    for (std::size_t i = 0; i < n; ++i) out.insert(i);
    return {out.begin(), out.end()};
  }
  std::size_t pos = 0;
  auto number = [&](const std::string& s) -> std::size_t {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
      throw UsageError("bad --frames '" + spec + "' (expected e.g. 0-9,20,30-)");
    return std::stoul(s);
  };
  while (pos <= spec.size()) {
    std::size_t comma = spec.find(',', pos);
    std::string part =
        spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    std::size_t dash = part.find('-');
    std::size_t a, b;
    if (dash == std::string::npos) {
      a = b = number(part);
    } else {
      a = number(part.substr(0, dash));
      b = dash + 1 == part.size() ? n - 1 : number(part.substr(dash + 1));
    }
    if (a > b || b >= n)
      throw UsageError(fmt::format("--frames '{}': {} is outside 0-{}", spec, part, n - 1));
    for (std::size_t i = a; i <= b; ++i) out.insert(i);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return {out.begin(), out.end()};
}

namespace {

void check_options(const Acap2ObjOptions& opt) {
  if (opt.features != "raw" && opt.features != "normalized" && opt.features != "auto")
    throw UsageError("--features must be raw, normalized or auto");
  if (opt.anchor_positions != "auto" && opt.anchor_positions != "reference" &&
      opt.anchor_positions != "frames")
    throw UsageError("--anchor-positions must be auto, reference or frames");
  if (opt.solver != "gradients" && opt.solver != "edges")
    throw UsageError("--solver must be gradients or edges");
}

// Which features to reconstruct from (--features; auto: raw when the file has them) and, for the
// normalized ones, the numbers that undo the normalization.
struct FeatureSource {
  bool raw = false;
  geometry::Normalization nz;
};

FeatureSource feature_source(const io::AcapReader& in, const Acap2ObjOptions& opt) {
  const bool has_raw = in.has_raw(), has_norm = in.has_normalized();
  if (!has_raw && !has_norm)
    throw InvalidInput(
        "has no features (/features/raw or /features/normalized); run obj2acap first", opt.input);
  if (opt.features == "raw" && !has_raw) throw InvalidInput("has no /features/raw", opt.input);
  if (opt.features == "normalized" && !has_norm)
    throw InvalidInput("has no /features/normalized", opt.input);
  FeatureSource src;
  src.raw = opt.features == "raw" || (opt.features == "auto" && has_raw);
  if (!src.raw) src.nz = in.normalization();
  return src;
}

// The frames --frames and --sequence select, with every frame's sequence.
struct Selection {
  std::vector<std::string> names, seq_names;
  std::vector<std::size_t> seq_of;  ///< sequence of every frame of the file
  std::vector<std::size_t> frames;  ///< the selected ones, in order
};

Selection select_frames(const io::AcapReader& in, const Acap2ObjOptions& opt) {
  Selection sel{in.frame_names(), in.sequence_names(), std::vector<std::size_t>(in.frames()), {}};
  const auto offsets = in.offsets();
  for (std::size_t s = 0; s + 1 < offsets.size(); ++s)
    for (auto f = offsets[s]; f < offsets[s + 1]; ++f) sel.seq_of[static_cast<std::size_t>(f)] = s;
  sel.frames = parse_frame_selection(opt.frames, in.frames());
  if (!opt.sequences.empty()) {
    for (const auto& s : opt.sequences)
      if (std::find(sel.seq_names.begin(), sel.seq_names.end(), s) == sel.seq_names.end())
        throw UsageError(fmt::format("no sequence '{}' in {} (it has: {})", s, opt.input,
                                     fmt::join(sel.seq_names, ", ")));
    std::erase_if(sel.frames, [&](std::size_t i) {
      return std::find(opt.sequences.begin(), opt.sequences.end(), sel.seq_names[sel.seq_of[i]]) ==
             opt.sequences.end();
    });
  }
  if (sel.frames.empty()) throw UsageError("the selection holds no frames");
  return sel;
}

// The mesh files' names (--name; by default the frame names, with the sequence when two frames
// share a name), checked to be plain, distinct mesh file names.
std::vector<std::string> mesh_file_names(const Selection& sel, const std::string& name_pattern) {
  std::string pattern = name_pattern;
  if (pattern.empty()) {
    std::set<std::string> unique;
    for (auto i : sel.frames) unique.insert(sel.names[i]);
    pattern = unique.size() == sel.frames.size() ? "{name}.obj" : "{sequence}-{name}.obj";
  }
  std::vector<std::string> file_names;
  std::set<std::string> seen;
  for (auto i : sel.frames) {
    std::string name;
    try {
      name = fmt::format(fmt::runtime(pattern), fmt::arg("name", sel.names[i]),
                         fmt::arg("index", i), fmt::arg("sequence", sel.seq_names[sel.seq_of[i]]));
    } catch (const fmt::format_error& e) {
      throw UsageError(fmt::format("bad --name pattern '{}': {}", pattern, e.what()));
    }
    if (name.find('/') != std::string::npos || name.empty())
      throw UsageError("--name must give plain file names: " + name);
    if (!io::is_mesh_file(name)) throw UsageError("--name must end in .obj, .ply or .off: " + name);
    if (!seen.insert(name).second)
      throw UsageError("two frames get the file name " + name + "; use --name with {index}");
    file_names.push_back(name);
  }
  return file_names;
}

// An acap output: the template, the selected frames' names, sequences and labels, and room for
// their positions.
std::unique_ptr<io::AcapWriter> acap_output(const std::filesystem::path& temp,
                                            const std::string& output, const io::AcapReader& in,
                                            const Mesh& tmpl, const Selection& sel) {
  auto f = std::make_unique<io::AcapWriter>(temp, output, std::vector<std::string>{in.history()});
  f->write_template(tmpl);
  std::vector<std::string> sel_names, sel_seqs;
  std::vector<std::int64_t> sel_offsets{0};
  std::vector<std::int32_t> sel_labels;
  const bool labelled = in.labelled();
  const auto labels = labelled ? in.labels() : std::vector<std::int32_t>{};
  const auto& frames = sel.frames;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::size_t s = sel.seq_of[frames[k]];
    if (k == 0 || sel.seq_of[frames[k - 1]] != s) {
      if (k) sel_offsets.push_back(static_cast<std::int64_t>(k));
      sel_seqs.push_back(sel.seq_names[s]);
      if (labelled) sel_labels.push_back(labels[s]);
    }
    sel_names.push_back(sel.names[frames[k]]);
  }
  sel_offsets.push_back(static_cast<std::int64_t>(frames.size()));
  f->write_frame_names(sel_names);
  f->write_sequences(sel_offsets, sel_seqs);
  if (labelled) f->write_labels(sel_labels, in.class_names());
  f->create_positions(frames.size(), static_cast<std::size_t>(tmpl.vertices.rows()));
  return f;
}

// Every selected frame solved and written (to `f`, or as a mesh file in `dir`); the round-trip
// error per frame against the stored positions when the file has them. Frames in blocks:
// contiguous runs are read with one call (parallel chunk decompression), solved in parallel,
// written in order. Buffers are reused across blocks.
std::vector<FrameError> reconstruct_frames(const io::AcapReader& in, const FeatureSource& src,
                                           const Selection& sel, const geometry::Reconstructor& rec,
                                           bool pin_to_frames, const Mesh& tmpl, io::AcapWriter* f,
                                           const std::filesystem::path& dir,
                                           const std::vector<std::string>& file_names) {
  const std::size_t nv = in.vertices();
  const bool has_positions = in.has_positions();
  const auto& frames = sel.frames;
  io::MeshWriter writer(tmpl.faces, nv);
  Progress progress("reconstructing frames", frames.size());
  const std::size_t block = 64;
  const std::size_t row = nv * kFeatureDims;
  std::vector<double> feat(block * row);
  std::vector<float> featf, pos_in, pos_out(block * nv * 3);
  std::vector<Vertices> truth(block), result(block);
  std::vector<FrameError> errors(frames.size());
  auto read_run = [&](std::size_t k0, std::size_t len) {  // frames[k0..k0+len) are consecutive
    const std::size_t i = frames[k0], b = k0 % block;
    if (src.raw) {
      in.read_raw(i, len, feat.data() + b * row);
    } else {
      featf.resize(len * row);
      in.read_normalized(i, len, featf.data());
      for (std::size_t k = 0; k < featf.size(); ++k)
        feat[b * row + k] = src.nz.denormalize(static_cast<int>(k % kFeatureDims), featf[k]);
    }
    if (has_positions) {
      pos_in.resize(len * nv * 3);
      in.read_positions(i, len, pos_in.data());
      for (std::size_t q = 0; q < len; ++q)
        truth[b + q] = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                           pos_in.data() + q * nv * 3, static_cast<Eigen::Index>(nv), 3)
                           .cast<double>();
    }
  };
  for (std::size_t first = 0; first < frames.size(); first += block) {
    const std::size_t count = std::min(block, frames.size() - first);
    for (std::size_t k = first; k < first + count;) {  // HDF5 reads: one thread
      std::size_t len = 1;
      while (k + len < first + count && frames[k + len] == frames[k] + len) ++len;
      read_run(k, len);
      k += len;
    }
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t b) {
      result[b] = rec.solve(feat.data() + b * row, pin_to_frames ? &truth[b] : nullptr);
      if (has_positions)
        errors[first + b] = frame_error(result[b], truth[b], rec.component_of(), rec.components());
      if (f)
        for (std::size_t k = 0; k < nv * 3; ++k)
          pos_out[b * nv * 3 + k] = static_cast<float>(result[b].data()[k]);
      else
        writer.write((dir / file_names[first + b]).string(), result[b]);
      progress.advance();
    });
    if (f) f->write_positions_rows(first, count, pos_out.data());
  }
  progress.finish();
  if (!has_positions) errors.clear();
  return errors;
}

void report_round_trip(const std::vector<FrameError>& errors, const Selection& sel, double diag) {
  if (errors.empty()) return;
  auto worst = std::max_element(errors.begin(), errors.end(),
                                [](auto& a, auto& b) { return a.max < b.max; });
  double mean = 0;
  for (const auto& e : errors) mean += e.mean / static_cast<double>(errors.size());
  const std::size_t frame = sel.frames[static_cast<std::size_t>(worst - errors.begin())];
  log::info(
      "round-trip error vs stored positions (per-component translation removed): max {:.3g} x bbox "
      "diagonal (frame {} '{}'), mean {:.3g} x diagonal",
      worst->max / diag, frame, sel.names[frame], mean / diag);
}

}  // namespace

void acap2obj(const Acap2ObjOptions& opt, const CommonOptions& common) {
  const auto t0 = std::chrono::steady_clock::now();
  check_options(opt);
  const bool h5out = io::is_hdf5_path(opt.output);
  const OutputClaim claim =
      claim_output(opt.output, common.force, {opt.input},
                   h5out ? AtomicOutput::Kind::file : AtomicOutput::Kind::directory);
  const io::AcapReader in(opt.input);
  const FeatureSource src = feature_source(in, opt);
  const Mesh tmpl = in.read_template();
  if (opt.anchor_positions == "frames" && !in.has_positions())
    throw InvalidInput("--anchor-positions frames needs /frames/positions", opt.input);
  const bool pin_to_frames = in.has_positions() && opt.anchor_positions != "reference";
  const Selection sel = select_frames(in, opt);

  const auto solver = opt.solver == "gradients" ? geometry::ReconstructionSolver::gradients
                                                : geometry::ReconstructionSolver::edges;
  geometry::Reconstructor rec(tmpl.vertices, tmpl.faces, opt.anchor, solver);
  log::info("template {} vertices, {} components; {} system factored in {:.3f} s", in.vertices(),
            rec.components(), opt.solver == "gradients" ? "gradient" : "edge",
            rec.factor_seconds());
  const auto& fs = rec.factor_stats();
  log::debug(
      "of which: assembly {:.3f} s, ordering and analysis {:.3f} s, numeric factorisation {:.3f} s "
      "({:.2f} GFLOP, {:.1f} M non-zeros in the factor), simplicial copy for the solves {:.3f} s",
      rec.assemble_seconds(), fs.analyse_seconds, fs.factor_seconds, fs.flops / 1e9,
      fs.factor_nonzeros / 1e6, fs.simplicial_seconds);
  const double diag =
      (tmpl.vertices.colwise().maxCoeff() - tmpl.vertices.colwise().minCoeff()).norm();

  // Output: a directory of meshes, or an acap .h5.
  AtomicOutput out(opt.output, h5out ? AtomicOutput::Kind::file : AtomicOutput::Kind::directory,
                   common.force, {opt.input});
  const std::vector<std::string> file_names =
      h5out ? std::vector<std::string>{} : mesh_file_names(sel, opt.name_pattern);
  const auto f = h5out ? acap_output(out.temp_path(), opt.output, in, tmpl, sel) : nullptr;
  const auto errors = reconstruct_frames(in, src, sel, rec, pin_to_frames, tmpl, f.get(),
                                         out.temp_path(), file_names);
  if (f) f->close();
  out.commit();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::info("wrote {} frames to {} in {:.2f} s", sel.frames.size(), opt.output, secs);
  report_round_trip(errors, sel, diag);
}

}  // namespace df::convert
