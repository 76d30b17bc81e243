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
FrameError frame_error(const io::Vertices& P, const io::Vertices& truth, const std::vector<int>& component, int nc) {
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
    std::string part = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
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

void acap2obj(const Acap2ObjOptions& opt, const CommonOptions& common) {
  auto t0 = std::chrono::steady_clock::now();
  const io::AcapReader in(opt.input);
  const bool has_raw = in.has_raw(), has_norm = in.has_normalized();
  if (!has_raw && !has_norm)
    throw InvalidInput("has no features (/features/raw or /features/normalized); run obj2acap first", opt.input);
  bool use_raw = opt.features == "raw" || (opt.features == "auto" && has_raw);
  if (opt.features == "raw" && !has_raw) throw InvalidInput("has no /features/raw", opt.input);
  if (opt.features == "normalized" && !has_norm) throw InvalidInput("has no /features/normalized", opt.input);
  if (opt.features != "raw" && opt.features != "normalized" && opt.features != "auto")
    throw UsageError("--features must be raw, normalized or auto");
  geometry::Normalization nz;
  if (!use_raw) nz = in.normalization();

  const io::Mesh tmpl = in.read_template();
  const std::size_t nv = in.vertices(), n_all = in.frames();
  const bool has_positions = in.has_positions();
  if (opt.anchor_positions != "auto" && opt.anchor_positions != "reference" && opt.anchor_positions != "frames")
    throw UsageError("--anchor-positions must be auto, reference or frames");
  if (opt.anchor_positions == "frames" && !has_positions)
    throw InvalidInput("--anchor-positions frames needs /frames/positions", opt.input);
  const bool pin_to_frames = has_positions && opt.anchor_positions != "reference";

  // Frame selection: --frames and --sequence.
  const auto names = in.frame_names();
  const auto seq_names = in.sequence_names();
  const auto offsets = in.offsets();
  std::vector<std::size_t> seq_of(n_all);
  for (std::size_t s = 0; s + 1 < offsets.size(); ++s)
    for (auto f = offsets[s]; f < offsets[s + 1]; ++f) seq_of[static_cast<std::size_t>(f)] = s;
  std::vector<std::size_t> frames = parse_frame_selection(opt.frames, n_all);
  if (!opt.sequences.empty()) {
    for (const auto& s : opt.sequences)
      if (std::find(seq_names.begin(), seq_names.end(), s) == seq_names.end())
        throw UsageError(fmt::format("no sequence '{}' in {} (it has: {})", s, opt.input, fmt::join(seq_names, ", ")));
    std::erase_if(frames, [&](std::size_t i) {
      return std::find(opt.sequences.begin(), opt.sequences.end(), seq_names[seq_of[i]]) == opt.sequences.end();
    });
  }
  if (frames.empty()) throw UsageError("the selection holds no frames");

  if (opt.solver != "gradients" && opt.solver != "edges") throw UsageError("--solver must be gradients or edges");
  const auto solver = opt.solver == "gradients" ? geometry::ReconstructionSolver::gradients
                                                : geometry::ReconstructionSolver::edges;
  geometry::Reconstructor rec(tmpl.vertices, tmpl.faces, opt.anchor, solver);
  log::info("template {} vertices, {} components; {} system factored in {:.3f} s", nv, rec.components(),
            opt.solver == "gradients" ? "gradient" : "edge", rec.factor_seconds());
  const double diag = (tmpl.vertices.colwise().maxCoeff() - tmpl.vertices.colwise().minCoeff()).norm();

  // Output: a directory of meshes, or an acap .h5.
  const bool h5out = io::is_hdf5_path(opt.output);
  AtomicOutput out(opt.output, h5out ? AtomicOutput::Kind::file : AtomicOutput::Kind::directory, common.force,
                   {opt.input});
  std::vector<std::string> file_names;
  if (!h5out) {
    std::string pattern = opt.name_pattern;
    if (pattern.empty()) {
      std::set<std::string> unique;
      for (auto i : frames) unique.insert(names[i]);
      pattern = unique.size() == frames.size() ? "{name}.obj" : "{sequence}-{name}.obj";
    }
    std::set<std::string> seen;
    for (auto i : frames) {
      std::string name;
      try {
        name = fmt::format(fmt::runtime(pattern), fmt::arg("name", names[i]), fmt::arg("index", i),
                           fmt::arg("sequence", seq_names[seq_of[i]]));
      } catch (const fmt::format_error& e) {
        throw UsageError(fmt::format("bad --name pattern '{}': {}", pattern, e.what()));
      }
      if (name.find('/') != std::string::npos || name.empty()) throw UsageError("--name must give plain file names: " + name);
      if (!io::is_mesh_file(name)) throw UsageError("--name must end in .obj, .ply or .off: " + name);
      if (!seen.insert(name).second) throw UsageError("two frames get the file name " + name + "; use --name with {index}");
      file_names.push_back(name);
    }
  }
  std::unique_ptr<io::AcapWriter> f;
  if (h5out) {
    f = std::make_unique<io::AcapWriter>(out.temp_path(), opt.output, std::vector<std::string>{in.history()});
    f->write_template(tmpl);
    std::vector<std::string> sel_names, sel_seqs;
    std::vector<std::int64_t> sel_offsets{0};
    std::vector<std::int32_t> sel_labels;
    const bool labelled = in.labelled();
    const auto labels = labelled ? in.labels() : std::vector<std::int32_t>{};
    for (std::size_t k = 0; k < frames.size(); ++k) {
      std::size_t s = seq_of[frames[k]];
      if (k == 0 || seq_of[frames[k - 1]] != s) {
        if (k) sel_offsets.push_back(static_cast<std::int64_t>(k));
        sel_seqs.push_back(seq_names[s]);
        if (labelled) sel_labels.push_back(labels[s]);
      }
      sel_names.push_back(names[frames[k]]);
    }
    sel_offsets.push_back(static_cast<std::int64_t>(frames.size()));
    f->write_frame_names(sel_names);
    f->write_sequences(sel_offsets, sel_seqs);
    if (labelled) f->write_labels(sel_labels, in.class_names());
    f->create_positions(frames.size(), nv);
  }

  io::MeshWriter writer(tmpl.faces, nv);
  Progress progress("reconstructing frames", frames.size());
  const std::size_t block = 64;
  // Frames in blocks: contiguous runs are read with one call (parallel chunk decompression),
  // solved in parallel, written in order. Buffers are reused across blocks.
  const std::size_t row = nv * kFeatureDims;
  std::vector<double> feat(block * row);
  std::vector<float> featf, pos_in, pos_out(block * nv * 3);
  std::vector<io::Vertices> truth(block), result(block);
  std::vector<FrameError> errors(frames.size());
  auto read_run = [&](std::size_t k0, std::size_t len) {  // frames[k0..k0+len) are consecutive
    const std::size_t i = frames[k0], b = k0 % block;
    if (use_raw) {
      in.read_raw(i, len, feat.data() + b * row);
    } else {
      featf.resize(len * row);
      in.read_normalized(i, len, featf.data());
      for (std::size_t k = 0; k < featf.size(); ++k)
        feat[b * row + k] = nz.denormalize(static_cast<int>(k % kFeatureDims), featf[k]);
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
      if (has_positions) errors[first + b] = frame_error(result[b], truth[b], rec.component_of(), rec.components());
      if (h5out)
        for (std::size_t k = 0; k < nv * 3; ++k) pos_out[b * nv * 3 + k] = static_cast<float>(result[b].data()[k]);
      else
        writer.write((out.temp_path() / file_names[first + b]).string(), result[b]);
      progress.advance();
    });
    if (h5out) f->write_positions_rows(first, count, pos_out.data());
  }
  progress.finish();
  if (f) f->close();
  out.commit();
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::info("wrote {} frames to {} in {:.2f} s", frames.size(), opt.output, secs);
  if (has_positions) {
    auto worst = std::max_element(errors.begin(), errors.end(), [](auto& a, auto& b) { return a.max < b.max; });
    double mean = 0;
    for (const auto& e : errors) mean += e.mean / static_cast<double>(errors.size());
    log::info("round-trip error vs stored positions (per-component translation removed): max {:.3g} x bbox "
              "diagonal (frame {} '{}'), mean {:.3g} x diagonal",
              worst->max / diag, frames[static_cast<std::size_t>(worst - errors.begin())],
              names[frames[static_cast<std::size_t>(worst - errors.begin())]], mean / diag);
  }
}

}  // namespace df::convert
