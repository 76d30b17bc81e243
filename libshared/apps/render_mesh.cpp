#include "apps/render_mesh.h"

#include <fmt/args.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <span>

#include "apps/edit_shape.h"
#include "apps/sequence_choice.h"
#include "convert/acap2obj.h"
#include "convert/frame_set.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "eval/mesh_metrics.h"
#include "geometry/mesh_topology.h"
#include "io/acap_file.h"
#include "io/components_file.h"
#include "io/h5.h"
#include "io/schema.h"
#include "io/skeleton_file.h"
#include "render/canvas.h"
#include "render/rasterizer.h"
#include "render/sheet.h"
#include "render/stick_figure.h"

namespace fs = std::filesystem;

namespace df::apps {
using namespace df::render;
namespace {

constexpr int kMaxColumns = 64, kMaxPanels = 1024;
constexpr int kBatchColumns = 16;  // per-frame outputs: columns rasterised at once

// One row of the sheet: frames of one input (or of one of its sequences).
struct Row {
  std::size_t input = 0;
  std::string label;
  std::vector<std::size_t> frames;          // indices into the input's frames
  std::vector<std::string> captions;        // default column caption of each frame
  bool truth = false;                       // the ground-truth row of --show-truth
  std::vector<Vertices> shown;              // meshes: positions drawn, per frame
  std::vector<std::vector<double>> scalar;  // meshes: per-vertex value per frame (empty: plain)
};

enum class Kind { mesh, skeleton };

Kind input_kind(const std::string& path) {
  if (!io::is_hdf5_path(path)) return Kind::mesh;
  if (!fs::exists(path)) throw IOError("no such file", path);
  h5::File f(path, h5::File::Mode::read);
  const std::string kind = io::declared_kind(f);
  if (kind == "acap") return Kind::mesh;
  if (kind == "skeleton") return Kind::skeleton;
  throw InvalidInput("is a " + kind + " file; render-mesh draws acap, skeleton and mesh files",
                     path);
}

std::string stem(const std::string& path) {
  fs::path p(path);
  if (p.filename().empty()) p = p.parent_path();
  return io::is_hdf5_path(path) ? p.stem().string() : p.filename().string();
}

// Sequence indices chosen by --sequence (names, or indices when no name matches).
std::vector<std::size_t> chosen_sequences(const std::vector<std::string>& wanted,
                                          const std::vector<std::string>& names,
                                          const std::string& path) {
  std::vector<std::size_t> out;
  for (const auto& w : wanted) out.push_back(sequence_index(w, names, path));
  return out;
}

// Whether --frames names frames (L0.0.3 of a components file, stand01 of an MD2 model) rather
// than giving indices and ranges.
bool frames_by_name(const std::string& spec) {
  return spec.find_first_not_of("0123456789-,") != std::string::npos;
}

// The frames of [begin, end) that --steps, --frames and --every select, in order. `names`: the
// file's frame names (none for skeleton files), for --frames by name.
std::vector<std::size_t> select_frames(std::size_t begin, std::size_t end,
                                       const std::vector<std::int32_t>& step,
                                       const RenderOptions& opt, const std::string& where,
                                       const std::vector<std::string>& names = {}) {
  std::vector<std::size_t> cand;
  for (std::size_t i = begin; i < end; ++i) cand.push_back(i);
  if (!opt.steps.empty()) {
    if (step.empty())
      throw UsageError("--steps needs generated frames with /frames/step (gen-bdlstm output): " +
                       where);
    std::erase_if(cand, [&](std::size_t i) {
      return std::find(opt.steps.begin(), opt.steps.end(), step[i]) == opt.steps.end();
    });
  }
  if (cand.empty()) throw UsageError("no frames selected in " + where);
  std::vector<std::size_t> out;
  if (frames_by_name(opt.frames)) {
    if (names.empty()) throw UsageError("--frames by name: " + where + " has no frame names");
    std::vector<std::string> wanted;
    for (std::size_t a = 0; a <= opt.frames.size();) {
      const std::size_t b = std::min(opt.frames.find(',', a), opt.frames.size());
      wanted.push_back(opt.frames.substr(a, b - a));
      a = b + 1;
    }
    for (std::size_t i : cand)
      if (std::find(wanted.begin(), wanted.end(), names[i]) != wanted.end()) out.push_back(i);
    if (out.empty())
      throw UsageError(fmt::format("--frames: no frame of {} is named {}", where, opt.frames));
  } else {
    for (std::size_t k : convert::parse_frame_selection(opt.frames, cand.size()))
      out.push_back(cand[k]);
  }
  if (opt.every > 1) {
    std::vector<std::size_t> thinned;
    for (std::size_t k = 0; k < out.size(); k += static_cast<std::size_t>(opt.every))
      thinned.push_back(out[k]);
    out = std::move(thinned);
  }
  return out;
}

// --- meshes ----------------------------------------------------------------------------------

// A column's caption, true of every row drawn in it (a --show-truth row shows the data frame
// paired with it): a generated frame's step after the given ones; the data frame a given frame,
// a reconstruction (recon-msae, fit-baseline) or a fitted edit stands for; a component's name;
// else the frame's number in its sequence.
std::string caption(const convert::FrameSet& s, std::size_t i, std::size_t begin, bool components) {
  if (!s.step.empty() && s.step[i] > 0) return fmt::format("future frame {}", s.step[i]);
  if (!s.source.empty() && s.source[i] >= 0)  // a given frame, a reconstructed or fitted shape
    return fmt::format("{}data frame {}", s.step.empty() ? "" : "given: ", s.source[i]);
  if (components) return fmt::format("component {}", s.names[i]);
  return fmt::format("frame {}", i - begin);
}

std::vector<Row> mesh_rows(const std::vector<convert::FrameSet>& sets, const RenderOptions& opt) {
  std::vector<Row> rows;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    const auto& s = sets[k];
    if (s.tmpl.faces.rows() == 0) throw InvalidInput("has no triangles to draw", s.path);
    const bool components = io::names_components(s.sequences, s.names, s.offsets);
    auto add = [&](std::size_t begin, std::size_t end, const std::string& label) {
      Row r;
      r.input = k;
      r.label = label;
      r.frames = select_frames(begin, end, s.step, opt, label, s.names);
      for (std::size_t i : r.frames) r.captions.push_back(caption(s, i, begin, components));
      rows.push_back(std::move(r));
    };
    if (opt.sequences.empty()) {
      add(0, s.size(), stem(s.path));
    } else {
      for (std::size_t q : chosen_sequences(opt.sequences, s.sequences, s.path))
        add(static_cast<std::size_t>(s.offsets[q]), static_cast<std::size_t>(s.offsets[q + 1]),
            fmt::format("{} / {}", stem(s.path), s.sequences[q]));
    }
  }
  return rows;
}

// The truth frame paired with frame i of `s`: gen-bdlstm's /frames/source, else the same index.
std::size_t truth_frame(const convert::FrameSet& s, std::size_t i, const convert::FrameSet& truth) {
  std::int64_t j = s.source.empty() ? static_cast<std::int64_t>(i) : s.source[i];
  if (j < 0)
    throw InvalidInput(
        fmt::format("frame {} has no ground-truth frame (it lies past the data's end)", i), s.path);
  if (static_cast<std::size_t>(j) >= truth.size())
    throw InvalidInput(
        fmt::format("frame {} pairs with frame {} of the ground truth, which has {} frames", i, j,
                    truth.size()),
        s.path);
  return static_cast<std::size_t>(j);
}

// What --color asks for: the per-vertex quantity, its units for the colour bar, the dataset.
struct Coloring {
  std::string mode;  // none | error | deformation | displacement | dataset
  std::string units;
  std::string dataset;
};

Coloring coloring(const RenderOptions& opt) {
  Coloring c;
  c.mode = opt.color == "auto" ? (opt.error_vs.empty() ? "none" : "error") : opt.color;
  if (!c.mode.empty() && c.mode[0] == '/') c.dataset = c.mode, c.mode = "dataset";
  if (c.mode == "error") {
    if (opt.error_vs.empty()) throw UsageError("--color error needs --error-vs GROUND_TRUTH");
    c.units = "vertex error (x bbox diagonal)";
  } else if (c.mode == "deformation") {
    c.units = "||X - X_r|| per vertex (ACAP features)";
  } else if (c.mode == "displacement") {
    c.units = "|p - p_template| (x bbox diagonal)";
  } else if (c.mode == "dataset") {
    c.units = c.dataset;
  } else if (c.mode != "none") {
    throw UsageError(
        "--color must be none, error, deformation, displacement or a /dataset path, not '" +
        opt.color + "'");
  }
  return c;
}

// Per-vertex values of dataset `path` of an input for its frames: [N, V] or [V] (same for all).
std::vector<std::vector<double>> dataset_values(const convert::FrameSet& s, const std::string& path,
                                                std::string& units) {
  if (!io::is_hdf5_path(s.path))
    throw UsageError("--color " + path + " needs .h5 inputs: " + s.path);
  h5::File f(s.path, h5::File::Mode::read);
  if (!f.is_dataset(path)) throw InvalidInput("has no dataset " + path + " to colour by", s.path);
  auto a = f.read<double>(path);
  const std::size_t nv = s.vertices();
  if (f.has_attr(path, "units")) units = path + " (" + f.attr_string(path, "units") + ")";
  std::vector<std::vector<double>> out(s.size());
  if (a.dims.size() == 1 && a.dims[0] == nv) {
    for (auto& v : out) v = a.data;
  } else if (a.dims.size() == 2 && a.dims[0] == s.size() && a.dims[1] == nv) {
    for (std::size_t i = 0; i < s.size(); ++i)
      out[i].assign(a.data.begin() + static_cast<std::ptrdiff_t>(i * nv),
                    a.data.begin() + static_cast<std::ptrdiff_t>((i + 1) * nv));
  } else {
    throw InvalidInput(fmt::format("{} must have shape [V] or [N, V] = [{}, {}] to colour vertices",
                                   path, s.size(), nv),
                       s.path);
  }
  return out;
}

// Fills each row's shown positions and scalars; returns the data range of the scalars.
std::pair<double, double> prepare_meshes(std::vector<Row>& rows,
                                         std::vector<convert::FrameSet>& sets,
                                         convert::FrameSet* truth, Coloring& col) {
  for (auto& s : sets) {
    std::vector<std::size_t> need;
    for (const auto& r : rows)
      if (!r.truth && &sets[r.input] == &s)
        need.insert(need.end(), r.frames.begin(), r.frames.end());
    convert::reconstruct(s, &need);
  }
  // What a colouring needs per input, computed once for all its rows.
  const std::size_t n_inputs = sets.size();
  std::vector<std::vector<std::vector<double>>> datasets(n_inputs);
  std::vector<eval::MeshParts> parts(n_inputs);
  std::vector<Eigen::VectorXd> identity(n_inputs);
  for (std::size_t k = 0; k < n_inputs; ++k) {
    const auto& s = sets[k];
    if (col.mode == "dataset") datasets[k] = dataset_values(s, col.dataset, col.units);
    if (col.mode == "error")
      parts[k] = eval::mesh_parts(s.tmpl.faces, static_cast<Eigen::Index>(s.vertices()));
    if (col.mode == "deformation") {
      if (s.raw.rows() == 0)
        throw InvalidInput("has no ACAP features for --color deformation", s.path);
      const auto id = geometry::identity_features(s.normalization ? &*s.normalization : nullptr);
      identity[k].resize(s.raw.cols());
      for (Eigen::Index j = 0; j < identity[k].size(); ++j)
        identity[k][j] = id[static_cast<std::size_t>(j % geometry::kFeatureDims)];
    }
  }
  const double truth_diag = truth ? truth->diagonal() : 0.0;
  double lo = 1e300, hi = -1e300;
  for (auto& r : rows) {
    const auto& s = r.truth ? *truth : sets[r.input];
    const double diag = s.diagonal();
    for (std::size_t i : r.frames) {
      Vertices p = s.positions[i];
      std::vector<double> v;
      if (r.truth || col.mode == "none") {
        // drawn in the plain mesh colour
      } else if (col.mode == "error") {
        const Vertices& gt = truth->positions[truth_frame(s, i, *truth)];
        p = eval::align_parts(p, gt, parts[r.input]);
        v.resize(s.vertices());
        for (Eigen::Index k = 0; k < p.rows(); ++k)
          v[static_cast<std::size_t>(k)] = (p.row(k) - gt.row(k)).norm() / truth_diag;
      } else if (col.mode == "deformation") {
        const Eigen::VectorXd x =
            convert::normalized_features(s, i, s.normalization) - identity[r.input];
        v.resize(s.vertices());
        for (std::size_t k = 0; k < v.size(); ++k)
          v[k] = x.segment(static_cast<Eigen::Index>(k * geometry::kFeatureDims),
                           geometry::kFeatureDims)
                     .norm();
      } else if (col.mode == "displacement") {
        v.resize(s.vertices());
        for (Eigen::Index k = 0; k < p.rows(); ++k)
          v[static_cast<std::size_t>(k)] = (p.row(k) - s.tmpl.vertices.row(k)).norm() / diag;
      } else {
        v = datasets[r.input][i];
      }
      for (double x : v)
        if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
      r.shown.push_back(std::move(p));
      r.scalar.push_back(std::move(v));
    }
  }
  return {lo, hi};
}

// The first row of --show-truth: the truth frames paired with the first row's frames.
Row truth_row(const Row& first, const convert::FrameSet& s, const convert::FrameSet& truth) {
  Row r;
  r.truth = true;
  r.label = "ground truth";
  for (std::size_t i : first.frames) r.frames.push_back(truth_frame(s, i, truth));
  r.captions = first.captions;
  return r;
}

// --- skeletons -------------------------------------------------------------------------------

std::vector<Row> skeleton_rows(const std::vector<io::SkeletonFile>& files,
                               const std::vector<std::string>& paths, const RenderOptions& opt) {
  std::vector<Row> rows;
  for (std::size_t k = 0; k < files.size(); ++k) {
    const auto& s = files[k];
    std::vector<std::string> names = s.sequence_names;
    for (std::size_t q = 0; q < names.size(); ++q)
      if (names[q].empty()) names[q] = std::to_string(q);
    std::vector<std::size_t> seqs = chosen_sequences(opt.sequences, names, paths[k]);
    if (opt.sequences.empty())
      for (std::size_t q = 0; q < s.sequences(); ++q) seqs.push_back(q);
    for (std::size_t q : seqs) {
      Row r;
      r.input = k;
      r.label = fmt::format("{}{} ({})", files.size() > 1 ? stem(paths[k]) + " / " : "", names[q],
                            s.label_text(q));
      const auto begin = static_cast<std::size_t>(s.offsets[q]);
      r.frames = select_frames(begin, static_cast<std::size_t>(s.offsets[q + 1]), {}, opt, r.label);
      for (std::size_t i : r.frames) r.captions.push_back(fmt::format("frame {}", i - begin));
      rows.push_back(std::move(r));
    }
  }
  return rows;
}

// --- the pictures --------------------------------------------------------------------------

// Output names: one file, or one per column from the pattern.
std::vector<std::string> output_names(const RenderOptions& opt, const std::vector<Row>& rows,
                                      std::size_t cols) {
  if (io::lower_extension(opt.output) != ".png")
    throw UsageError("-o must name a .png file (or a NAME{index}.png pattern)");
  if (opt.output.find('{') == std::string::npos) return {opt.output};
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (std::size_t c = 0; c < cols; ++c) {
    std::string name;
    try {
      const std::size_t frame = c < rows.front().frames.size() ? rows.front().frames[c] : 0;
      name = fmt::format(fmt::runtime(opt.output), fmt::arg("index", c), fmt::arg("frame", frame));
    } catch (const fmt::format_error& e) {
      throw UsageError(fmt::format("bad -o pattern '{}': {}", opt.output, e.what()));
    }
    if (!seen.insert(name).second)
      throw UsageError("two frames get the file name " + name + "; use {index} in -o");
    out.push_back(name);
  }
  return out;
}

std::vector<std::string> labels_or(const std::vector<std::string>& given,
                                   std::vector<std::string> fallback, const char* option) {
  if (given.empty()) return fallback;
  if (given.size() != fallback.size())
    throw UsageError(
        fmt::format("{} gives {} labels for {}", option, given.size(), fallback.size()));
  return given;
}

// Everything a picture shows: the inputs, their rows, the colour bar, the camera fitted to it all.
struct Scene {
  bool skeleton = false;
  std::vector<std::vector<int>> points;  // per input, the vertices marked with dots (--points)
  std::vector<convert::FrameSet> sets;
  std::vector<io::SkeletonFile> skels;
  std::unique_ptr<convert::FrameSet> truth;
  std::vector<Row> rows;
  std::optional<ColorBar> bar;
  Camera camera{View{}};
  std::size_t columns() const {
    std::size_t c = 0;
    for (const auto& r : rows) c = std::max(c, r.frames.size());
    return c;
  }
};

// The rows the camera is fitted to (--fit).
std::span<const Row> fitted_rows(const std::vector<Row>& rows, const RenderOptions& opt) {
  return opt.fit == "first" ? std::span<const Row>(rows.data(), 1) : std::span<const Row>(rows);
}

void check_options(const RenderOptions& opt) {
  if (opt.inputs.empty()) throw UsageError("no inputs");
  if (opt.width < 16 || opt.height < 16 || opt.width > 4096 || opt.height > 4096)
    throw UsageError("--size must be between 16 and 4096 pixels per side");
  if (opt.supersample < 1 || opt.supersample > 8) throw UsageError("--supersample must be 1 to 8");
  if (opt.every < 0) throw UsageError("--every must be positive");
  if (!opt.range.empty() && (opt.range.size() != 2 || !(opt.range[0] < opt.range[1])))
    throw UsageError("--range needs LO,HI with LO < HI");
  if (opt.shading != "smooth" && opt.shading != "flat")
    throw UsageError("--shading must be smooth or flat");
  if (opt.fit != "all" && opt.fit != "first") throw UsageError("--fit must be all or first");
  if (opt.show_truth && opt.error_vs.empty())
    throw UsageError("--show-truth needs --error-vs GROUND_TRUTH");
}

Scene load_skeletons(const RenderOptions& opt, const Coloring& col) {
  if (col.mode != "none" || !opt.error_vs.empty())
    throw UsageError("skeleton files are drawn without --color / --error-vs");
  Scene sc;
  sc.skeleton = true;
  sc.camera = Camera(parse_view(opt.view, opt.up));
  for (const auto& p : opt.inputs) {  // drawn in raw (root-centred) coordinates
    io::SkeletonFile skel = io::read_skeleton_file(p);
    skel.poses = skel.raw_poses();
    sc.skels.push_back(std::move(skel));
  }
  sc.rows = skeleton_rows(sc.skels, opt.inputs, opt);
  for (const auto& r : fitted_rows(sc.rows, opt))
    for (std::size_t t : r.frames)
      for (std::size_t j = 0; j < sc.skels[r.input].joints; ++j) {
        double q[3];
        sc.skels[r.input].joint(t, j, q);
        sc.camera.include_point({q[0], q[1], q[2]});
      }
  return sc;
}

Scene load_meshes(const RenderOptions& opt, Coloring& col) {
  Scene sc;
  sc.camera = Camera(parse_view(opt.view, opt.up));
  for (const auto& p : opt.inputs) sc.sets.push_back(convert::read_frame_set(p));
  sc.rows = mesh_rows(sc.sets, opt);
  if (!opt.error_vs.empty()) {  // the truth: its frames paired with every row's
    sc.truth = std::make_unique<convert::FrameSet>(convert::read_frame_set(opt.error_vs));
    auto& truth = *sc.truth;
    for (const auto& in : sc.sets)
      if (truth.vertices() != in.vertices())
        throw InvalidInput(fmt::format("the error reference has {} vertices, {} has {}",
                                       truth.vertices(), in.path, in.vertices()),
                           opt.error_vs);
    if (opt.show_truth)
      sc.rows.insert(sc.rows.begin(),
                     truth_row(sc.rows.front(), sc.sets[sc.rows.front().input], truth));
    std::vector<std::size_t> need;
    for (const auto& r : sc.rows)
      for (std::size_t i : r.frames)
        need.push_back(r.truth ? i : truth_frame(sc.sets[r.input], i, truth));
    convert::reconstruct(truth, &need);
  }
  auto [lo, hi] = prepare_meshes(sc.rows, sc.sets, sc.truth.get(), col);
  if (col.mode != "none") {
    if (!opt.range.empty())
      lo = opt.range[0], hi = opt.range[1];
    else if (!(lo <= hi))  // nothing finite
      lo = 0, hi = 1;
    else
      lo = std::min(lo, 0.0), hi = hi > lo ? hi : lo + 1;
    sc.bar = ColorBar{parse_colormap(opt.colormap), lo, hi, col.units};
  }
  for (const auto& r : fitted_rows(sc.rows, opt))
    for (const auto& p : r.shown) sc.camera.include(p);
  return sc;
}

// The PNG files to write, checked before any drawing (each is then written atomically).
struct Outputs {
  std::vector<std::string> names;
  bool per_frame = false;
  std::vector<fs::path> inputs;  // never overwritten
};

Outputs check_outputs(const RenderOptions& opt, const Scene& sc, const CommonOptions& common) {
  Outputs out;
  const std::size_t cols = sc.columns();
  out.names = output_names(opt, sc.rows, cols);
  out.per_frame = opt.output.find('{') != std::string::npos;
  if (!out.per_frame && cols > static_cast<std::size_t>(kMaxColumns))
    throw UsageError(fmt::format(
        "{} frames selected; a sheet shows at most {}: choose with --frames/--every/--steps, or "
        "write one PNG per frame with -o 'DIR/{{index:04d}}.png'",
        cols, kMaxColumns));
  if (sc.rows.size() * (out.per_frame ? 1 : cols) > static_cast<std::size_t>(kMaxPanels))
    throw UsageError(fmt::format("{} rows x {} columns is too many panels for one picture",
                                 sc.rows.size(), cols));
  out.inputs.assign(opt.inputs.begin(), opt.inputs.end());
  if (!opt.error_vs.empty()) out.inputs.emplace_back(opt.error_vs);
  for (const auto& name : out.names) {
    const fs::path dir = fs::path(name).parent_path();
    if (out.per_frame && !dir.empty()) fs::create_directories(dir);
    AtomicOutput check(name, AtomicOutput::Kind::file, common.force, out.inputs);
  }
  return out;
}

// Title, captions and colour bar of the sheets (one sheet, or one per column).
SheetSpec sheet_spec(const RenderOptions& opt, const Scene& sc) {
  SheetSpec spec;
  spec.rows = static_cast<int>(sc.rows.size());
  spec.cols = static_cast<int>(sc.columns());
  spec.panel_width = opt.width, spec.panel_height = opt.height;
  spec.title = opt.title;
  for (const auto& r : sc.rows) spec.row_labels.push_back(r.label);
  spec.row_labels = labels_or(opt.row_labels, spec.row_labels, "--row-labels");
  const Row& first = sc.rows.front().truth && sc.rows.size() > 1 ? sc.rows[1] : sc.rows.front();
  for (std::size_t c = 0; c < sc.columns(); ++c)
    spec.column_labels.push_back(c < first.captions.size() ? first.captions[c] : "");
  spec.column_labels = labels_or(opt.column_labels, spec.column_labels, "--column-labels");
  log::debug("rows: {}; columns: {}", fmt::join(spec.row_labels, " | "),
             fmt::join(spec.column_labels, " | "));
  spec.bar = sc.bar;
  spec.background = parse_color(opt.background);
  return spec;
}

// Mesh panels of columns [c0, c1) of every row, rasterised in parallel (one panel per task, so
// the pixels do not depend on the thread count); row-major.
std::vector<Panel> mesh_panels(const Scene& sc, const RenderOptions& opt, std::size_t c0,
                               std::size_t c1, Progress& progress) {
  Shading shading;
  shading.smooth = opt.shading == "smooth";
  shading.background = parse_color(opt.background);
  shading.supersample = opt.supersample;
  const Rgb base = parse_color(opt.base_color);
  std::vector<Panel> panels(sc.rows.size() * (c1 - c0));
  tbb::parallel_for(std::size_t{0}, panels.size(), [&](std::size_t k) {
    const Row& r = sc.rows[k / (c1 - c0)];
    const std::size_t c = c0 + k % (c1 - c0);
    if (c >= r.frames.size()) return;
    std::vector<Rgb> colors;
    if (sc.bar && !r.scalar[c].empty())
      for (double v : r.scalar[c])
        colors.push_back(map_color(sc.bar->map, (v - sc.bar->lo) / (sc.bar->hi - sc.bar->lo)));
    const auto& faces = (r.truth ? *sc.truth : sc.sets[r.input]).tmpl.faces;
    panels[k] =
        rasterize_mesh(r.shown[c], faces, colors, base, sc.camera, opt.width, opt.height, shading);
    progress.advance();
  });
  return panels;
}

const std::vector<int> kNoPoints;

// --points: per input, a handle file's vertices, or the handles of its /edit record (none
// without one).
std::vector<std::vector<int>> marked_points(const RenderOptions& opt, const Scene& sc) {
  if (opt.points.empty()) return {};
  if (sc.skeleton) throw UsageError("--points marks mesh vertices; these inputs are skeletons");
  const int V = static_cast<int>(sc.sets.front().tmpl.vertices.rows());
  if (opt.points != "edit")
    return std::vector<std::vector<int>>(opt.inputs.size(), read_handles(opt.points, V).vertices);
  std::vector<std::vector<int>> points;
  bool any = false;
  for (const auto& p : opt.inputs) {
    points.emplace_back();
    if (io::is_hdf5_path(p)) {  // (mesh inputs: an .h5 is an acap file, input_kind checked)
      const io::AcapReader r(p);
      if (!r.has_edit()) continue;
      const auto h = r.read_edit().handles;
      points.back().assign(h.begin(), h.end());
      any = true;
    }
  }
  if (!any) throw UsageError("--points edit: no input has an /edit record (an edit-shape output)");
  return points;
}

// Draws and writes the pictures: one sheet, or one per column (in batches of columns, so a long
// sequence never holds all its panels in memory).
void draw_pictures(const Scene& sc, const RenderOptions& opt, const CommonOptions& common,
                   const Outputs& out) {
  const std::size_t cols = sc.columns();
  const SheetSpec all = sheet_spec(opt, sc);
  Progress progress("rendering", sc.rows.size() * cols);
  const std::size_t batch = out.per_frame ? kBatchColumns : cols;
  for (std::size_t c0 = 0; c0 < cols; c0 += batch) {
    const std::size_t c1 = std::min(cols, c0 + batch);
    const std::vector<Panel> panels =
        sc.skeleton ? std::vector<Panel>{} : mesh_panels(sc, opt, c0, c1, progress);
    for (std::size_t o = 0; o < (out.per_frame ? c1 - c0 : 1); ++o) {
      SheetSpec spec = all;
      if (out.per_frame) spec.cols = 1, spec.column_labels = {all.column_labels[c0 + o]};
      const SheetLayout L = layout_sheet(spec);
      Canvas canvas(L.width, L.height, spec.background);
      for (std::size_t ri = 0; ri < sc.rows.size(); ++ri)
        for (std::size_t c = out.per_frame ? c0 + o : c0; c < (out.per_frame ? c0 + o + 1 : c1);
             ++c) {
          if (c >= sc.rows[ri].frames.size()) continue;
          const int x = L.panel_x(static_cast<int>(out.per_frame ? 0 : c), spec),
                    y = L.panel_y(static_cast<int>(ri), spec);
          if (sc.skeleton) {
            draw_stick_figure(canvas, sc.skels[sc.rows[ri].input], sc.rows[ri].frames[c], sc.camera,
                              x, y, opt.width, opt.height);
            progress.advance();
          } else {
            canvas.blit(panels[ri * (c1 - c0) + (c - c0)], x, y);
            const auto& shown = sc.rows[ri].shown[c];
            const auto input = sc.rows[ri].truth ? 0 : sc.rows[ri].input;
            for (int v : sc.points.empty() ? kNoPoints : sc.points[input]) {
              if (v >= shown.rows()) continue;
              const Eigen::Vector3d q =
                  sc.camera.to_panel(shown.row(v).transpose(), opt.width, opt.height);
              canvas.disc(x + q.x(), y + q.y(), 4.5, Rgb{1, 1, 1});
              canvas.disc(x + q.x(), y + q.y(), 3.2, Rgb{0.86, 0.1, 0.1});
            }
          }
        }
      draw_sheet_frame(canvas, spec, L);
      AtomicOutput file(out.names[out.per_frame ? c0 + o : 0], AtomicOutput::Kind::file,
                        common.force, out.inputs);
      canvas.write_png(file.temp_path(), file.final_path().string());
      file.commit();
    }
  }
  progress.finish();
}

}  // namespace

void render_mesh(const RenderOptions& opt, const CommonOptions& common) {
  check_options(opt);
  parse_colormap(opt.colormap), parse_color(opt.background),
      parse_color(opt.base_color);  // usage errors first
  Coloring col = coloring(opt);
  std::vector<Kind> kinds;
  for (const auto& p : opt.inputs) kinds.push_back(input_kind(p));
  if (std::any_of(kinds.begin(), kinds.end(), [&](Kind k) { return k != kinds.front(); }))
    throw UsageError("cannot draw skeleton files and meshes in one picture");
  Scene scene = kinds.front() == Kind::skeleton ? load_skeletons(opt, col) : load_meshes(opt, col);
  scene.points = marked_points(opt, scene);
  const Outputs out = check_outputs(opt, scene, common);
  draw_pictures(scene, opt, common, out);
  log::info("wrote {} ({} rows x {} frames{})",
            out.per_frame ? fmt::format("{} PNG files", out.names.size()) : opt.output,
            scene.rows.size(), scene.columns(),
            scene.bar ? fmt::format(", colour {} .. {:.3g} {}", scene.bar->lo, scene.bar->hi,
                                    scene.bar->units)
                      : "");
}

}  // namespace df::apps
