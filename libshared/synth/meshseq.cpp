#include "synth/meshseq.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "core/rng.h"
#include "io/acap_file.h"

namespace fs = std::filesystem;

namespace df::synth {
namespace {
constexpr double kPi = std::numbers::pi;

// Triangulated (nx+1) x (ny+1) grid over [x0,x1] x [y0,y1] at z = 0.
Mesh grid(int nx, int ny, double x0, double x1, double y0, double y1) {
  Mesh m;
  m.vertices.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.vertices.row(j * (nx + 1) + i) << x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny, 0.0;
  m.faces.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      m.faces.row(f++) << a, b, d;
      m.faces.row(f++) << a, d, c;
    }
  return m;
}

}  // namespace

MeshSeqKind mesh_seq_kind_from_name(const std::string& name) {
  if (name == "finger") return MeshSeqKind::finger;
  if (name == "flag") return MeshSeqKind::flag;
  if (name == "bumps") return MeshSeqKind::bumps;
  throw UsageError("unknown sequence kind '" + name + "' (finger, flag, bumps)");
}

const char* mesh_seq_kind_name(MeshSeqKind k) {
  switch (k) {
    case MeshSeqKind::finger:
      return "finger";
    case MeshSeqKind::flag:
      return "flag";
    default:
      return "bumps";
  }
}

MeshSequenceGenerator::MeshSequenceGenerator(const MeshSeqParams& p) : params_(p) {
  if (p.frames < 1) throw UsageError("--frames must be at least 1");
  if (p.sequences < 1) throw UsageError("--sequences must be at least 1");
  if (p.resolution < 3) throw UsageError("--resolution must be at least 3");
  if (p.fine_regions < 0 || p.fine_regions > kMaxFineRegions)
    throw UsageError(
        fmt::format("--fine-regions must be from 0 to {} (more do not fit the surface apart)",
                    kMaxFineRegions));
  if (!std::isfinite(p.amplitude) || !std::isfinite(p.twist_degrees) || !std::isfinite(p.periods))
    throw UsageError("--amplitude, --twist and --periods must be finite numbers");
  for (int k = 0; k < p.sequences; ++k) {
    Rng rng(p.seed, static_cast<std::uint64_t>(k));
    seq_scale_.push_back(k == 0 ? 1.0 : rng.uniform(0.7, 1.3));
  }

  if (p.kind == MeshSeqKind::finger) {
    build_finger();
  } else if (p.kind == MeshSeqKind::flag) {
    rest_ = grid(3 * p.resolution / 2, p.resolution, 0.0, 3.0, 0.0, 2.0);
  } else {
    rest_ = grid(p.resolution, p.resolution, -1.0, 1.0, -1.0, 1.0);
    plant_regions();
  }
}

// The finger: a capped cylinder along z, `resolution` around and 4 × as many rings.
void MeshSequenceGenerator::build_finger() {
  const int seg = params_.resolution, rings = 4 * params_.resolution;
  const double radius = 0.5;
  const int nv = seg * (rings + 1) + 2;
  rest_.vertices.resize(nv, 3);
  for (int r = 0; r <= rings; ++r)
    for (int k = 0; k < seg; ++k) {
      double a = 2 * kPi * k / seg;
      int v = r * seg + k;
      s_.push_back(length_ * r / rings);
      x_.push_back(radius * std::cos(a));
      y_.push_back(radius * std::sin(a));
      rest_.vertices.row(v) << x_.back(), y_.back(), s_.back();
    }
  const int bottom = seg * (rings + 1), top = bottom + 1;
  for (double s : {0.0, length_}) {
    s_.push_back(s);
    x_.push_back(0);
    y_.push_back(0);
  }
  rest_.vertices.row(bottom) << 0, 0, 0;
  rest_.vertices.row(top) << 0, 0, length_;
  rest_.faces.resize(2 * seg * rings + 2 * seg, 3);
  int f = 0;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < seg; ++k) {
      int a = r * seg + k, b = r * seg + (k + 1) % seg, c = a + seg, d = b + seg;
      rest_.faces.row(f++) << a, b, d;
      rest_.faces.row(f++) << a, d, c;
    }
  for (int k = 0; k < seg; ++k) {
    rest_.faces.row(f++) << bottom, (k + 1) % seg, k;
    rest_.faces.row(f++) << top, rings * seg + k, rings * seg + (k + 1) % seg;
  }
}

void MeshSequenceGenerator::plant_regions() {
  // Planted regions: 2 coarse (radius 0.45), --fine-regions fine (radius 0.15), centres apart.
  // Each region's draws follow the previous ones', so adding fine regions leaves the first
  // ones (and their weights in every frame) as they were.
  Rng rng(params_.seed, 1000003);
  struct C {
    double x, y, r;
    int scale;
  };
  std::vector<C> centers;
  for (auto [count, radius, scale] :
       {std::tuple{2, 0.45, 0}, std::tuple{params_.fine_regions, 0.15, 1}}) {
    for (int n = 0; n < count; ++n) {
      for (int attempt = 0;; ++attempt) {
        if (attempt == 100000)
          throw UsageError(fmt::format(
              "--fine-regions {}: no room for region {} of {} apart from the "
              "others (seed {}); ask for fewer or try another seed",
              params_.fine_regions, centers.size() + 1, 2 + params_.fine_regions, params_.seed));
        C c{rng.uniform(-1 + radius, 1 - radius), rng.uniform(-1 + radius, 1 - radius), radius,
            scale};
        bool ok = true;
        for (const auto& o : centers)  // a little apart first, then touching at most
          ok = ok && std::hypot(c.x - o.x, c.y - o.y) > (c.r + o.r) * (attempt < 1000 ? 1.05 : 1.0);
        if (ok) {
          centers.push_back(c);
          break;
        }
      }
    }
  }
  const auto nv = rest_.vertices.rows();
  for (const auto& c : centers) {
    Region reg;
    reg.scale = c.scale;
    reg.radius = c.r;
    reg.height = c.scale == 0 ? 0.35 : 0.12;
    reg.mask.assign(static_cast<std::size_t>(nv), 0);
    double best = 1e300;
    for (Eigen::Index v = 0; v < nv; ++v) {
      double d = std::hypot(rest_.vertices(v, 0) - c.x, rest_.vertices(v, 1) - c.y);
      if (d < c.r) reg.mask[static_cast<std::size_t>(v)] = 1;
      if (d < best) {
        best = d;
        reg.center = static_cast<int>(v);
      }
    }
    regions_.push_back(std::move(reg));
  }
}

Vertices MeshSequenceGenerator::finger(int seq, double phase) const {
  const double lift = 0.5 - 0.5 * std::cos(phase);  // 0 at rest, 1 at the peak
  const double bend = params_.amplitude * seq_scale_[seq] * 0.5 * kPi * lift;
  const double twist = params_.twist_degrees * seq_scale_[seq] * kPi / 180.0 * lift;
  Vertices V(rest_.vertices.rows(), 3);
  const double kappa = bend / length_;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    double s = s_[v], t = twist * s / length_;
    double x = x_[v] * std::cos(t) - y_[v] * std::sin(t);
    double y = x_[v] * std::sin(t) + y_[v] * std::cos(t);
    // Centreline bent with constant curvature in the xz plane.
    double cx, cz, nx, nz;
    if (std::abs(kappa) < 1e-12) {
      cx = 0, cz = s, nx = 1, nz = 0;
    } else {
      cx = (1 - std::cos(kappa * s)) / kappa;
      cz = std::sin(kappa * s) / kappa;
      nx = std::cos(kappa * s);
      nz = -std::sin(kappa * s);
    }
    V.row(v) << cx + x * nx, y, cz + x * nz;
  }
  return V;
}

Vertices MeshSequenceGenerator::flag(int seq, double phase) const {
  Vertices V = rest_.vertices;
  const double a = 0.25 * params_.amplitude * seq_scale_[seq];
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    double x = rest_.vertices(v, 0), y = rest_.vertices(v, 1);
    double reach = x / 3.0;  // pinned at x = 0
    double w1 = std::sin(2 * kPi * x / 2.0 - phase);
    double w2 = std::sin(2 * kPi * (0.6 * x + 0.4 * y) / 1.5 - 1.7 * phase);
    V(v, 2) = a * reach * (w1 + 0.35 * w2);
    V(v, 1) = y - 0.15 * a * reach * reach * (1 + std::cos(phase));
  }
  return V;
}

std::vector<double> MeshSequenceGenerator::region_weights(int t) const {
  std::vector<double> w;
  if (params_.kind != MeshSeqKind::bumps) return w;
  Rng rng(params_.seed, static_cast<std::uint64_t>(t) + 1);
  for (std::size_t r = 0; r < regions_.size(); ++r) w.push_back(rng.uniform(-1.0, 1.0));
  if (t == 0) std::fill(w.begin(), w.end(), 0.0);  // first frame at rest: the natural reference
  return w;
}

Vertices MeshSequenceGenerator::bumps(int t) const {
  Vertices V = rest_.vertices;
  auto w = region_weights(t);
  for (std::size_t r = 0; r < regions_.size(); ++r) {
    const Region& reg = regions_[r];
    double cx = rest_.vertices(reg.center, 0), cy = rest_.vertices(reg.center, 1);
    double h = params_.amplitude * reg.height * w[r];
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (!reg.mask[static_cast<std::size_t>(v)]) continue;
      double d = std::hypot(rest_.vertices(v, 0) - cx, rest_.vertices(v, 1) - cy) / reg.radius;
      if (d < 1) V(v, 2) += h * (1 - d * d) * (1 - d * d);
    }
  }
  return V;
}

Vertices MeshSequenceGenerator::frame(int t) const {
  int seq = t / params_.frames, local = t % params_.frames;
  double phase = 2 * kPi * params_.periods * local / std::max(params_.frames, 1);
  switch (params_.kind) {
    case MeshSeqKind::finger:
      return finger(seq, phase);
    case MeshSeqKind::flag:
      return flag(seq, phase);
    default:
      return bumps(t);
  }
}

namespace {

void write_hdf5(const MeshSequenceGenerator& gen, const AtomicOutput& out) {
  const MeshSeqParams& p = gen.params();
  const int n = gen.total_frames();
  const auto nv = static_cast<std::size_t>(gen.rest().vertices.rows());
  io::AcapWriter f(out.temp_path(), out.final_path().string());
  f.write_template(gen.rest());

  std::vector<std::string> names, seq_names;
  std::vector<std::int64_t> offsets{0};
  for (int k = 0; k < p.sequences; ++k) {
    seq_names.push_back(p.sequences == 1 ? mesh_seq_kind_name(p.kind)
                                         : fmt::format("{}-{}", mesh_seq_kind_name(p.kind), k));
    offsets.push_back(static_cast<std::int64_t>(k + 1) * p.frames);
    for (int t = 0; t < p.frames; ++t)
      names.push_back(fmt::format("{}-{:04d}", seq_names.back(), t));
  }
  f.write_frame_names(names);
  f.write_sequences(offsets, seq_names);

  // Frames in parallel blocks, written in order.
  f.create_positions(static_cast<std::size_t>(n), nv);
  Progress progress("generating frames", static_cast<std::size_t>(n));
  const int block = 64;
  std::vector<float> buf;
  for (int first = 0; first < n; first += block) {
    int count = std::min(block, n - first);
    buf.assign(static_cast<std::size_t>(count) * nv * 3, 0.0f);
    tbb::parallel_for(0, count, [&](int i) {
      Vertices V = gen.frame(first + i);
      float* dst = buf.data() + static_cast<std::size_t>(i) * nv * 3;
      for (std::size_t k = 0; k < nv * 3; ++k) dst[k] = static_cast<float>(V.data()[k]);
      progress.advance();
    });
    f.write_positions_rows(static_cast<std::size_t>(first), static_cast<std::size_t>(count),
                           buf.data());
  }
  progress.finish();

  io::SyntheticTruth truth;
  truth.kind = mesh_seq_kind_name(p.kind);
  truth.amplitude = p.amplitude;
  truth.twist_degrees = p.twist_degrees;
  truth.periods = p.periods;
  truth.resolution = p.resolution;
  truth.seed = static_cast<std::int64_t>(p.seed);
  for (const auto& r : gen.regions()) {
    truth.regions.push_back(r.mask);
    truth.region_scale.push_back(r.scale);
    truth.region_center.push_back(r.center);
  }
  if (!truth.regions.empty())
    for (int t = 0; t < n; ++t)
      for (double w : gen.region_weights(t)) truth.weights.push_back(static_cast<float>(w));
  f.write_synthetic(truth);
  f.close();
}

void write_meshes(const MeshSequenceGenerator& gen, const AtomicOutput& out,
                  const std::string& format) {
  if (format != "obj" && format != "ply" && format != "off")
    throw UsageError("unknown mesh format '" + format + "' (obj, ply, off)");
  const int n = gen.total_frames();
  io::MeshWriter writer(gen.rest().faces, static_cast<std::size_t>(gen.rest().vertices.rows()));
  Progress progress("writing frames", static_cast<std::size_t>(n));
  const int frames = gen.params().frames;
  const bool many = gen.params().sequences > 1;
  tbb::parallel_for(0, n, [&](int t) {
    std::string name = many ? fmt::format("s{}-{:04d}.{}", t / frames, t % frames, format)
                            : fmt::format("{:04d}.{}", t, format);
    writer.write((out.temp_path() / name).string(), gen.frame(t));
    progress.advance();
  });
  progress.finish();
}

}  // namespace

void synth_meshseq(const MeshSeqParams& p, const std::string& output,
                   const std::string& mesh_format, const CommonOptions& common) {
  MeshSequenceGenerator gen(p);
  const bool h5out = io::is_hdf5_path(output);
  AtomicOutput out(output, h5out ? AtomicOutput::Kind::file : AtomicOutput::Kind::directory,
                   common.force);
  log::info("{} sequence: {} x {} frames, {} vertices, {} triangles", mesh_seq_kind_name(p.kind),
            p.sequences, p.frames, gen.rest().vertices.rows(), gen.rest().faces.rows());
  if (h5out)
    write_hdf5(gen, out);
  else
    write_meshes(gen, out, mesh_format);
  out.commit();
  log::info("wrote {}", output);
}

}  // namespace df::synth
