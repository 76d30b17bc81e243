#include "models/msae/recon.h"

#include <fmt/format.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/file_header.h"
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

  AtomicOutput dest(opt.output, AtomicOutput::Kind::file, common.force, {opt.model, opt.data});
  {
    h5::File f(dest.temp_path(), h5::File::Mode::create, opt.output);
    io::write_header(f, "acap",
                     {m.history == shapes.history ? m.history : m.history + "\n" + shapes.history});
    f.write_matrix("/template/vertices", m.tmpl.vertices);
    f.write_matrix("/template/faces", m.tmpl.faces);
    geometry::write_normalization(f, m.normalization);
    // One sequence per data sequence that has frames in the part, in file order.
    std::vector<std::string> seqs;
    std::vector<std::int64_t> offsets{0};
    for (std::size_t k = 0; k < shapes.sequence.size(); ++k) {
      if (seqs.empty() || seqs.back() != shapes.sequence[k]) {
        if (!seqs.empty()) offsets.push_back(static_cast<std::int64_t>(k));
        seqs.push_back(shapes.sequence[k]);
      }
    }
    offsets.push_back(static_cast<std::int64_t>(shapes.sequence.size()));
    const auto n = static_cast<std::size_t>(recon.rows()),
               V = static_cast<std::size_t>(m.tmpl.vertices.rows());
    f.write_strings("/frames/names", shapes.names);
    f.write<std::int64_t>("/frames/source", shapes.frames, {n});
    f.set_attr("/frames/source", "data", opt.data);
    f.write<std::int64_t>("/sequences/offsets", offsets, {offsets.size()});
    f.write_strings("/sequences/names", seqs);
    f.write<float>("/features/normalized", std::span<const float>(recon.data(), n * V * 9),
                   {n, V, 9});
    f.set_attr("/features/normalized", "levels", levels);
    f.close();
  }
  dest.commit();
  log::info("wrote {} shapes ({} part, {} of {} levels) to {}", recon.rows(), opt.part, levels,
            m.config.levels(), opt.output);
}

}  // namespace df::models
