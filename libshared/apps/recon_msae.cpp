#include "apps/recon_msae.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "models/msae/data.h"

namespace df::apps {
using namespace df::models;

void recon_msae(const MsaeReconOptions& opt, const CommonOptions& common) {
  const OutputClaim claim = claim_output(opt.output, common.force, {opt.model, opt.data});
  const MsaeModel m = load_msae_model(opt.model);
  const int levels = opt.levels == 0 ? m.config.levels() : opt.levels;
  if (levels < 1 || levels > m.config.levels())
    throw UsageError(
        fmt::format("--levels must be in 1..{} (the model's levels)", m.config.levels()));
  const MsaeShapes shapes = read_msae_shapes(m, opt.data, opt.part);
  if (shapes.x.rows() == 0)
    throw InvalidInput(fmt::format("the model's {} part is empty", opt.part), opt.model);

  // Reconstruct in chunks (a block's activations are ~10 matrices of chunk × 9V floats).
  if (opt.fit_codes < 0) throw UsageError("--fit-codes must not be negative");
  if (!(opt.fit_lr > 0)) throw UsageError("--fit-lr must be positive");
  nn::Matrix<float> recon(shapes.x.rows(), shapes.x.cols());
  double encoder_error = 0;
  Progress progress(opt.fit_codes ? "fitting codes" : "reconstructing",
                    static_cast<std::size_t>(shapes.x.rows()));
  for (Eigen::Index r = 0; r < shapes.x.rows(); r += 64) {
    const Eigen::Index n = std::min<Eigen::Index>(64, shapes.x.rows() - r);
    const nn::Matrix<float> x = shapes.x.middleRows(r, n);
    std::vector<nn::Matrix<float>> codes;
    recon.middleRows(r, n) = m.net->reconstruct(x, levels, &codes);
    if (opt.fit_codes > 0) {
      encoder_error += static_cast<double>((x - recon.middleRows(r, n)).squaredNorm());
      recon.middleRows(r, n) = m.net->fit_codes(x, levels, codes, opt.fit_codes, opt.fit_lr);
    }
    progress.advance(static_cast<std::size_t>(n));
  }
  progress.finish();
  if (opt.fit_codes > 0)
    log::info(
        "mean |X - X^|^2 per shape: encoder's codes {:.6g}, fitted codes {:.6g}",
        encoder_error / static_cast<double>(recon.rows()),
        static_cast<double>((shapes.x - recon).squaredNorm()) / static_cast<double>(recon.rows()));

  write_shapes(
      opt.output, m, shapes, &recon, nullptr, opt.data, {opt.model, opt.data}, common.force,
      fmt::format("recon-msae: {} of {} levels{}", levels, m.config.levels(),
                  opt.fit_codes ? fmt::format(", codes fitted ({} steps)", opt.fit_codes) : ""));
  log::info("wrote {} shapes ({} part, {} of {} levels) to {}", recon.rows(), opt.part, levels,
            m.config.levels(), opt.output);
}

}  // namespace df::apps
