#include "apps/gen_actgan.h"

#include <sstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "io/file_header.h"
#include "io/skeleton_file.h"

namespace df::apps {
using namespace df::models;
namespace {

void write_latents(const std::string& path, const std::vector<std::string>& names,
                   const std::vector<float>& latents, int length, int z, bool force,
                   const std::string& model) {
  std::ostringstream f;
  f << "# sequence\tframe";
  for (int k = 0; k < z; ++k) f << "\th" << k + 1;
  f << "\n";
  for (std::size_t s = 0; s < names.size(); ++s) {
    for (int t = 0; t < length; ++t) {
      f << names[s] << '\t' << t;
      for (int k = 0; k < z; ++k)
        f << '\t'
          << latents[(s * static_cast<std::size_t>(length) + static_cast<std::size_t>(t)) *
                         static_cast<std::size_t>(z) +
                     static_cast<std::size_t>(k)];
      f << "\n";
    }
    f << "\n";  // a blank line between sequences (gnuplot: separate curves)
  }
  write_text_output(path, f.str(), force, {model});
}

}  // namespace

void gen_actgan(const ActganGenerateOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.output, opt.latents}, common.force, {opt.model});
  const ActganModel m = load_actgan_model(opt.model);
  const int length = opt.length > 0 ? opt.length : m.length;
  if (length < 1) throw UsageError("--length must be positive");
  if (!opt.latents.empty() && m.config.generator == Generator::pose)
    throw UsageError("the direct-pose baseline has no latent trajectories (--latents)");
  AtomicOutput out(opt.output, AtomicOutput::Kind::file, common.force, {opt.model});
  std::vector<std::string> names;
  const auto y = label_rows(m, opt, names);
  Rng rng(common.seed, 0);
  io::SkeletonFile s;
  std::vector<float> latents;
  generate_actions(m, y, length, rng, s.poses, latents);
  s.joints = m.joint_names.size();
  s.dims = 3;
  s.frames = names.size() * static_cast<std::size_t>(length);
  for (std::size_t k = 0; k <= names.size(); ++k)
    s.offsets.push_back(static_cast<std::int64_t>(k) * length);
  for (Eigen::Index r = 0; r < y.rows(); ++r)
    s.labels.push_back(static_cast<std::int32_t>(most_probable(y, r)));
  if (!opt.mix.empty()) {  // stored, so that pictures and the classifier say what was asked for
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> w = y;
    s.label_weights.assign(w.data(), w.data() + w.size());
  }
  s.sequence_names = names;
  s.class_names = m.class_names;
  s.parents = m.parents;
  s.joint_names = m.joint_names;
  s.frame_rate = m.frame_rate;
  s.normalization = m.normalization;
  {
    h5::File f(out.temp_path(), h5::File::Mode::create, opt.output);
    io::write_header(f, "skeleton", {m.history});
    io::write_skeleton_data(f, s);
  }
  if (!opt.latents.empty())
    write_latents(opt.latents, names, latents, length, m.config.latent, common.force, opt.model);
  out.commit();
  log::info("wrote {}: {} sequences of {} frames", opt.output, names.size(), length);
}

}  // namespace df::apps
