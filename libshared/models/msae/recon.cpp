#include "models/msae/recon.h"

#include <fmt/format.h>

#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "models/msae/data.h"

namespace df::models {

void recon_msae(const MsaeReconOptions& opt, const CommonOptions& common) {
  const MsaeModel m = load_msae_model(opt.model);
  const int levels = opt.levels == 0 ? m.config.levels() : opt.levels;
  if (levels < 1 || levels > m.config.levels())
    throw UsageError(
        fmt::format("--levels must be in 1..{} (the model's levels)", m.config.levels()));
  const MsaeShapes shapes = read_msae_shapes(m, opt.data, opt.part);
  if (shapes.x.rows() == 0)
    throw InvalidInput(fmt::format("the model's {} part is empty", opt.part), opt.model);

  // Reconstruct in chunks (a block's activations are ~10 matrices of chunk × 9V floats).
  nn::Matrix<float> recon(shapes.x.rows(), shapes.x.cols());
  Progress progress("reconstructing", static_cast<std::size_t>(shapes.x.rows()));
  for (Eigen::Index r = 0; r < shapes.x.rows(); r += 64) {
    const Eigen::Index n = std::min<Eigen::Index>(64, shapes.x.rows() - r);
    recon.middleRows(r, n) = m.net->reconstruct(shapes.x.middleRows(r, n), levels);
    progress.advance(static_cast<std::size_t>(n));
  }
  progress.finish();

  write_shapes(opt.output, m, shapes, &recon, nullptr, opt.data, {opt.model, opt.data},
               common.force, fmt::format("recon-msae: {} of {} levels", levels, m.config.levels()));
  log::info("wrote {} shapes ({} part, {} of {} levels) to {}", recon.rows(), opt.part, levels,
            m.config.levels(), opt.output);
}

}  // namespace df::models
