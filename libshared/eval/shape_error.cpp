#include "eval/shape_error.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "convert/frame_set.h"
#include "core/error.h"
#include "eval/mesh_metrics.h"

namespace df::eval {

ShapeErms::ShapeErms(const std::string& data, const std::vector<std::int64_t>& frames,
                     const geometry::Normalization& nz)
    : nz_(nz) {
  convert::FrameSet fs = convert::read_frame_set(data);
  std::vector<std::size_t> wanted;
  for (auto f : frames) {
    if (f < 0 || static_cast<std::size_t>(f) >= fs.size())
      throw InvalidInput(fmt::format("has no frame {}", f), data);
    wanted.push_back(static_cast<std::size_t>(f));
  }
  convert::reconstruct(fs, &wanted);
  for (auto f : wanted) truth_.push_back(fs.positions[f]);
  solver_ = std::make_unique<geometry::Reconstructor>(fs.tmpl.vertices, fs.tmpl.faces, 0,
                                                      geometry::ReconstructionSolver::gradients);
  parts_ = {solver_->component_of(), solver_->components()};
}

ShapeErms::~ShapeErms() = default;

double ShapeErms::operator()(
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& normalized) const {
  if (static_cast<std::size_t>(normalized.rows()) != truth_.size())
    throw Error(fmt::format("internal: {} shapes to measure against {} true ones",
                            normalized.rows(), truth_.size()));
  if (truth_.empty()) return 0;
  const Eigen::Index nv = truth_[0].rows();
  std::vector<double> squared(truth_.size());
  tbb::parallel_for(std::size_t{0}, truth_.size(), [&](std::size_t k) {
    std::vector<double> raw(static_cast<std::size_t>(normalized.cols()));
    for (Eigen::Index c = 0; c < normalized.cols(); ++c)
      raw[static_cast<std::size_t>(c)] =
          nz_.denormalize(static_cast<int>(c % geometry::kFeatureDims),
                          static_cast<double>(normalized(static_cast<Eigen::Index>(k), c)));
    const Vertices p = solver_->solve(raw.data());
    squared[k] = erms_share(p, truth_[k], parts_);
  });
  double sum = 0;
  for (double s : squared) sum += s;
  return erms_from_sum(sum, static_cast<double>(truth_.size()), static_cast<double>(nv));
}

}  // namespace df::eval
