#include "convert/frame_set.h"

#include <tbb/parallel_for.h>

#include "convert/frame_reader.h"
#include "core/error.h"
#include "core/progress.h"
#include "geometry/reconstruction.h"
#include "io/acap_file.h"

namespace df::convert {

using geometry::kFeatureDims;

double FrameSet::diagonal() const {
  const auto& T = tmpl.vertices;
  return T.rows() ? (T.colwise().maxCoeff() - T.colwise().minCoeff()).norm() : 0.0;
}

namespace {

FrameSet read_mesh_files(const std::string& path) {
  FrameSet fs;
  fs.path = path;
  FrameReader reader({path});
  fs.tmpl = reader.read(0);
  fs.offsets = {0};
  for (const auto& s : reader.sequences()) {
    fs.sequences.push_back(s.name);
    fs.offsets.push_back(static_cast<std::int64_t>(s.first + s.count));
  }
  fs.positions.resize(reader.size());
  for (std::size_t i = 0; i < reader.size(); ++i) fs.names.push_back(reader.frame_name(i));
  tbb::parallel_for(std::size_t{0}, reader.size(), [&](std::size_t i) {
    fs.positions[i] = reader.read_positions(i, fs.tmpl, reader.frame_name(0));
  });
  fs.positions_stored = true;
  return fs;
}

}  // namespace

FrameSet read_frame_set(const std::string& path) {
  if (!io::is_hdf5_path(path)) return read_mesh_files(path);
  FrameSet fs;
  fs.path = path;
  const io::AcapReader f(path);
  fs.tmpl = f.read_template();
  fs.offsets = f.offsets();
  fs.sequences = f.sequence_names();
  fs.names = f.frame_names();
  const std::size_t n = f.frames(), nv = f.vertices(), row = nv * kFeatureDims;
  if (f.has_normalization()) fs.normalization = f.normalization();
  if (f.has_raw() || f.has_normalized()) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(
        static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(row));
    f.read_features(0, n, m.data());
    fs.raw = m;
  }
  fs.positions.resize(n);
  if (f.has_positions()) {
    std::vector<float> p(n * nv * 3);
    f.read_positions(0, n, p.data());
    for (std::size_t i = 0; i < n; ++i)
      fs.positions[i] = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                            p.data() + i * nv * 3, static_cast<Eigen::Index>(nv), 3)
                            .cast<double>();
    fs.positions_stored = true;
  }
  if (f.has_source()) fs.source = f.source();
  if (f.has_steps()) fs.step = f.steps();
  return fs;
}

void reconstruct(FrameSet& fs, const std::vector<std::size_t>* frames) {
  std::vector<char> wanted(fs.size(), frames ? 0 : 1);
  if (frames)
    for (std::size_t i : *frames) wanted.at(i) = 1;
  std::vector<std::size_t> todo;  // wanted frames without positions
  for (std::size_t i = 0; i < fs.size(); ++i)
    if (wanted[i] && fs.positions[i].rows() == 0) todo.push_back(i);
  if (todo.empty()) return;
  if (fs.raw.rows() == 0) throw InvalidInput("has neither /frames/positions nor features", fs.path);
  geometry::Reconstructor rec(fs.tmpl.vertices, fs.tmpl.faces, 0,
                              geometry::ReconstructionSolver::gradients);
  Progress progress("reconstructing " + fs.path, todo.size());
  tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t k) {
    Eigen::Matrix<double, 1, Eigen::Dynamic> row = fs.raw.row(static_cast<Eigen::Index>(todo[k]));
    fs.positions[todo[k]] = rec.solve(row.data());
    progress.advance();
  });
  progress.finish();
}

Eigen::VectorXd normalized_features(const FrameSet& fs, std::size_t i,
                                    const std::optional<geometry::Normalization>& nz) {
  Eigen::VectorXd x = fs.raw.row(static_cast<Eigen::Index>(i)).transpose();
  if (nz)
    for (Eigen::Index k = 0; k < x.size(); ++k)
      x[k] = nz->normalize(static_cast<int>(k % kFeatureDims), x[k]);
  return x;
}

}  // namespace df::convert
