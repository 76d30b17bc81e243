#include "convert/skel2h5.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <regex>

#include "convert/bone_lengths.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/natural_sort.h"
#include "core/rng.h"
#include "io/file_header.h"

namespace fs = std::filesystem;

namespace df::convert {
namespace {

std::string lower_extension(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return e;
}

// The UTKinect label file in directory `dir` (or its joints/ folder), "" when there is none.
std::string utkinect_labels_in(const fs::path& dir) {
  for (const auto& d : std::array<fs::path, 2>{dir, dir / "joints"})
    if (fs::exists(d / "actionLabel.txt")) return (d / "actionLabel.txt").string();
  return {};
}

// The format a file's name says, "" when it says none.
std::string format_of_file(const std::string& path) {
  const std::string base = fs::path(path).filename().string();
  if (base.rfind("actionLabel", 0) == 0) return "utkinect";
  if (is_msr_action3d_name(path)) return "msr";
  const std::string ext = lower_extension(path);
  if (ext == ".bvh") return "bvh";
  if (ext == ".npy" || ext == ".npz") return "npy";
  if (ext == ".h5" || ext == ".hdf5") return "skeleton";
  return {};
}

struct ResolvedInputs {
  std::string format;
  std::vector<std::string> files;
};

// The inputs as files of one format. A directory is recognised by what it holds: a UTKinect label
// file, else its files whose names say one format (natural order), or when it holds only
// folders (one per class), theirs. A file named on the command
// line is taken by its name under --format auto, as it is under an explicit --format (but for
// MSR-Action3D, whose files are always told by their names: the dataset ships other .txt files
// beside them). Files of no recognised kind beside recognised ones are left out with a warning;
// two kinds at once are an error.
ResolvedInputs resolve_inputs(const Skel2h5Options& opt) {
  struct Input {
    std::string path;
    bool listed;  ///< named on the command line, not found in a directory
  };
  std::vector<Input> files;
  for (const auto& in : opt.inputs) {
    if (!fs::is_directory(in)) {
      files.push_back({in, true});
      continue;
    }
    if (const std::string labels = utkinect_labels_in(in);
        !labels.empty() && (opt.format == "auto" || opt.format == "utkinect")) {
      files.push_back({labels, true});
      continue;
    }
    std::vector<std::string> inside;
    for (const auto& e : fs::directory_iterator(in))
      if (e.is_regular_file()) inside.push_back(e.path().string());
    if (inside.empty())  // a directory of class folders: their files
      for (const auto& d : fs::directory_iterator(in))
        if (d.is_directory())
          for (const auto& e : fs::directory_iterator(d.path()))
            if (e.is_regular_file()) inside.push_back(e.path().string());
    if (inside.empty()) throw InvalidInput("an empty directory", in);
    natural_sort(inside);
    for (auto& f : inside) files.push_back({std::move(f), false});
  }
  const auto kind = [&](const Input& f) {
    const std::string named = format_of_file(f.path);
    if (opt.format == "auto") return named;
    if (opt.format == "msr") return is_msr_action3d_name(f.path) ? opt.format : std::string();
    return f.listed || named == opt.format ? opt.format : std::string();
  };
  ResolvedInputs r;
  std::vector<std::string> kinds, ignored;  // the recognised kinds, in order of appearance
  for (const auto& f : files) {
    const std::string k = kind(f);
    if (k.empty()) {
      ignored.push_back(f.path);
      continue;
    }
    if (std::find(kinds.begin(), kinds.end(), k) == kinds.end()) kinds.push_back(k);
    r.files.push_back(f.path);
  }
  if (kinds.empty())
    throw InvalidInput(
        opt.format == "auto"
            ? "cannot tell the format (a UTKinect directory or actionLabel.txt, "
              "aXX_sYY_eZZ_skeleton3D.txt files or a directory of them, .bvh, .npy or "
              ".npz joint arrays, or a skeleton .h5); use --format"
            : fmt::format("no input file of --format {}", opt.format),
        files.front().path);
  if (kinds.size() > 1)
    throw InvalidInput(fmt::format("inputs of more than one format ({}): give one kind at a time",
                                   fmt::join(kinds, ", ")),
                       opt.inputs.front());
  r.format = kinds.front();
  if (!ignored.empty())
    log::warn("{} input file(s) not of format {} left out: {}{}", ignored.size(), r.format,
              fmt::join(ignored.begin(),
                        ignored.begin() + std::min<std::ptrdiff_t>(3, std::ssize(ignored)), ", "),
              ignored.size() > 3 ? ", ..." : "");
  return r;
}

RawSkeletonCollection read_inputs(const Skel2h5Options& opt) {
  const ResolvedInputs in = resolve_inputs(opt);
  const auto one = [&](const char* what) {
    if (in.files.size() != 1)
      throw UsageError(
          fmt::format("--format {} reads one input ({} given)", what, in.files.size()));
    return in.files.front();
  };
  if (in.format == "utkinect") return read_utkinect(one("utkinect"));
  if (in.format == "msr") return read_msr_action3d(in.files);
  if (in.format == "bvh") return read_bvh(in.files, opt.label);
  if (in.format == "npy") return read_joint_arrays(in.files, opt.label, opt.arrays);
  if (in.format == "skeleton") return read_skeleton_h5(one("skeleton"));
  throw UsageError("--format must be auto, utkinect, msr, bvh, npy or skeleton");
}

}  // namespace

void resample(RawSkeletonCollection& c, double fps) {
  const std::size_t fs = c.joints() * 3;
  for (auto& s : c.sequences) {
    const double t0 = s.times.front(), t1 = s.times.back();
    const auto n = static_cast<std::size_t>(std::floor((t1 - t0) * fps + 1e-9)) + 1;
    std::vector<float> poses(n * fs);
    std::vector<double> times(n);
    std::size_t k = 0;  // source interval [times[k], times[k+1]]
    for (std::size_t i = 0; i < n; ++i) {
      const double t = t0 + static_cast<double>(i) / fps;
      while (k + 2 < s.times.size() && s.times[k + 1] < t) ++k;
      const double span = s.times[k + 1] - s.times[k];
      const double w = std::clamp(span > 0 ? (t - s.times[k]) / span : 0.0, 0.0, 1.0);
      for (std::size_t d = 0; d < fs; ++d)
        poses[i * fs + d] =
            static_cast<float>((1 - w) * s.poses[k * fs + d] + w * s.poses[(k + 1) * fs + d]);
      times[i] = t;
    }
    s.poses = std::move(poses);
    s.times = std::move(times);
  }
  c.frame_rate = fps;
}

std::vector<std::int32_t> assign_test_split(const RawSkeletonCollection& c,
                                            const Skel2h5Options& opt, std::uint64_t seed) {
  std::vector<std::int32_t> test(c.sequences.size(), 0);
  if (!opt.test_subjects.empty()) {
    for (std::size_t s = 0; s < test.size(); ++s)
      test[s] = std::count(opt.test_subjects.begin(), opt.test_subjects.end(),
                           c.sequences[s].subject) > 0;
    return test;
  }
  if (opt.test_fraction <= 0) return test;
  std::vector<std::string> labels;
  for (const auto& s : c.sequences)
    if (std::find(labels.begin(), labels.end(), s.label) == labels.end()) labels.push_back(s.label);
  Rng rng(seed, 0);
  for (const auto& label : labels) {
    std::vector<std::size_t> members;
    for (std::size_t s = 0; s < test.size(); ++s)
      if (c.sequences[s].label == label) members.push_back(s);
    for (std::size_t k = members.size(); k > 1; --k)
      std::swap(members[k - 1], members[rng.below(k)]);
    const auto held = static_cast<std::size_t>(
        std::lround(opt.test_fraction * static_cast<double>(members.size())));
    for (std::size_t k = 0; k < held; ++k) test[members[k]] = 1;
  }
  return test;
}

void normalize_skeletons(io::SkeletonFile& s, int root_joint, double sd_floor) {
  const std::size_t J = s.joints, fs = s.frame_size();
  std::vector<char> train(s.frames, 0);
  for (std::size_t q = 0; q < s.sequences(); ++q)
    if (s.test.empty() || s.test[q] == 0)
      std::fill(train.begin() + s.offsets[q], train.begin() + s.offsets[q + 1], 1);
  const auto training_frames = static_cast<double>(std::count(train.begin(), train.end(), 1));
  if (training_frames == 0) throw InvalidInput("no training sequence to fit the normalization on");
  for (std::size_t t = 0; t < s.frames; ++t) {  // root-centre
    float* p = s.poses.data() + t * fs;
    const std::array<float, 3> root{p[root_joint * 3], p[root_joint * 3 + 1],
                                    p[root_joint * 3 + 2]};
    for (std::size_t j = 0; j < J; ++j)
      for (int d = 0; d < 3; ++d)
        p[j * 3 + static_cast<std::size_t>(d)] -= root[static_cast<std::size_t>(d)];
  }
  double distance = 0;
  for (std::size_t t = 0; t < s.frames; ++t)
    if (train[t])
      for (std::size_t j = 0; j < J; ++j) {
        const float* p = s.poses.data() + t * fs + j * 3;
        distance += std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
      }
  auto& n = s.normalization;
  n.root_joint = root_joint;
  n.scale = distance / (training_frames * static_cast<double>(J));
  if (!(n.scale > 0)) throw InvalidInput("every joint sits on the root joint: nothing to scale");
  n.mean.assign(fs, 0.0);
  n.std.assign(fs, 0.0);
  for (std::size_t t = 0; t < s.frames; ++t)
    if (train[t])
      for (std::size_t k = 0; k < fs; ++k) n.mean[k] += s.poses[t * fs + k] / n.scale;
  for (auto& m : n.mean) m /= training_frames;
  for (std::size_t t = 0; t < s.frames; ++t)
    if (train[t])
      for (std::size_t k = 0; k < fs; ++k) {
        const double d = s.poses[t * fs + k] / n.scale - n.mean[k];
        n.std[k] += d * d;
      }
  for (auto& v : n.std) {
    v = std::sqrt(v / training_frames);
    if (v < 1e-6)
      v = 1;  // the root joint (always 0), or a joint that never moves
    else
      v = std::max(v, sd_floor);
  }
  for (std::size_t t = 0; t < s.frames; ++t)
    for (std::size_t k = 0; k < fs; ++k)
      s.poses[t * fs + k] =
          static_cast<float>((s.poses[t * fs + k] / n.scale - n.mean[k]) / n.std[k]);
}

io::SkeletonFile build_skeleton_file(const RawSkeletonCollection& c,
                                     const std::vector<std::int32_t>& test,
                                     const Skel2h5Options& opt) {
  io::SkeletonFile s;
  s.joints = c.joints();
  s.dims = 3;
  s.joint_names = c.joint_names;
  s.parents = c.parents;
  s.frame_rate = c.frame_rate;
  s.offsets.push_back(0);
  const std::size_t fs = s.frame_size();
  std::size_t too_short = 0;
  for (std::size_t q = 0; q < c.sequences.size(); ++q) {
    const auto& src = c.sequences[q];
    auto it = std::find(s.class_names.begin(), s.class_names.end(), src.label);
    if (it == s.class_names.end()) it = s.class_names.insert(s.class_names.end(), src.label);
    const auto label = static_cast<std::int32_t>(it - s.class_names.begin());
    const std::size_t n = src.times.size();
    const std::size_t length = opt.length > 0 ? static_cast<std::size_t>(opt.length) : n;
    const std::size_t stride =
        opt.clip_stride > 0 ? static_cast<std::size_t>(opt.clip_stride) : length;
    if (n < length) {
      ++too_short;
      continue;
    }
    for (std::size_t start = 0, clip = 0; start + length <= n; start += stride, ++clip) {
      s.poses.insert(s.poses.end(), src.poses.begin() + static_cast<std::ptrdiff_t>(start * fs),
                     src.poses.begin() + static_cast<std::ptrdiff_t>((start + length) * fs));
      s.offsets.push_back(s.offsets.back() + static_cast<std::int64_t>(length));
      s.labels.push_back(label);
      s.subjects.push_back(src.subject);
      s.test.push_back(test[q]);
      s.sequence_names.push_back(opt.length > 0 ? fmt::format("{}#{}", src.name, clip) : src.name);
      if (opt.length == 0) break;
    }
  }
  if (too_short)
    log::warn("{} of {} sequences are shorter than --length {} frames and were left out", too_short,
              c.sequences.size(), opt.length);
  if (s.labels.empty())
    throw InvalidInput(fmt::format("no sequence has --length {} frames", opt.length));
  s.frames = s.poses.size() / fs;
  if (opt.normalize) normalize_skeletons(s, opt.root_joint, opt.sd_floor);
  return s;
}

void skel2h5(const Skel2h5Options& opt, const CommonOptions& common) {
  if (opt.length < 0 || opt.clip_stride < 0 || opt.fps < 0 || opt.test_fraction < 0 ||
      opt.test_fraction >= 1)
    throw UsageError(
        "--length, --clip-stride and --fps must not be negative, --test-fraction in [0, 1)");
  if (!opt.test_subjects.empty() && opt.test_fraction > 0)
    throw UsageError("--test-subjects and --test-fraction exclude each other");
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force,
                   {opt.inputs.begin(), opt.inputs.end()});
  if (!(opt.bone_tolerance > 0)) throw UsageError("--bone-tolerance must be positive");
  if (!opt.normalize && opt.sd_floor > 0)
    throw UsageError("--sd-floor bounds the z-score's s.d.: --raw keeps raw coordinates");
  RawSkeletonCollection c = read_inputs(opt);
  check_bone_lengths(c, opt.bone_tolerance, opt.strict, opt.inputs.front());
  if (opt.root_joint < 0 || static_cast<std::size_t>(opt.root_joint) >= c.joints())
    throw UsageError(
        fmt::format("--root-joint {} is not one of the {} joints", opt.root_joint, c.joints()));
  resample(c, opt.fps > 0 ? opt.fps : c.frame_rate);
  const auto test = assign_test_split(c, opt, common.seed);
  io::SkeletonFile s = build_skeleton_file(c, test, opt);
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, opt.output);
    io::write_header(f, "skeleton");
    io::write_skeleton_data(f, s);
  }
  out.commit();
  const auto held = std::count(s.test.begin(), s.test.end(), 1);
  log::info(
      "wrote {}: {} sequences ({} training, {} test) of {} classes, {} frames at {} fps, {} joints",
      opt.output, s.sequences(), static_cast<std::int64_t>(s.sequences()) - held, held,
      s.class_names.size(), s.frames, s.frame_rate, s.joints);
}

}  // namespace df::convert
