#include "models/actgan/generate.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "core/error.h"
#include "nn/ops.h"

namespace df::models {
namespace {

constexpr Eigen::Index kBatch = 64;  // sequences per forward pass

int class_index(const ActganModel& m, const std::string& name) {
  const auto it = std::find(m.class_names.begin(), m.class_names.end(), name);
  if (it == m.class_names.end())
    throw UsageError(fmt::format("unknown class '{}' (the model knows: {})", name,
                                 fmt::join(m.class_names, ", ")));
  return static_cast<int>(it - m.class_names.begin());
}

// "walk:0.5,wave:0.5" -> weights per class, normalized to sum 1.
std::vector<float> parse_mix(const ActganModel& m, const std::string& mix, std::string& name) {
  std::vector<float> w(m.class_names.size(), 0.0f);
  std::stringstream in(mix);
  for (std::string part; std::getline(in, part, ',');) {
    const auto colon = part.find(':');
    if (colon == std::string::npos)
      throw UsageError(fmt::format("--mix part '{}' is not CLASS:WEIGHT", part));
    const std::string cls = part.substr(0, colon);
    double weight = 0;
    try {
      weight = std::stod(part.substr(colon + 1));
    } catch (const std::exception&) {
      throw UsageError(fmt::format("--mix part '{}': the weight is not a number", part));
    }
    if (!(weight >= 0))
      throw UsageError(fmt::format("--mix part '{}': weights must not be negative", part));
    w[static_cast<std::size_t>(class_index(m, cls))] += static_cast<float>(weight);
    name += (name.empty() ? "" : "+") + cls;
  }
  float sum = 0;
  for (float x : w) sum += x;
  if (!(sum > 0)) throw UsageError("--mix weights sum to 0");
  for (float& x : w) x /= sum;
  return w;
}

}  // namespace

Eigen::Index most_probable(const nn::Matrix<float>& p, Eigen::Index r) {
  Eigen::Index best = 0;
  p.row(r).maxCoeff(&best);
  return best;
}

nn::Matrix<float> label_rows(const ActganModel& m, const ActganGenerateOptions& opt,
                             std::vector<std::string>& names) {
  if (opt.count < 1) throw UsageError("--count must be positive");
  std::vector<std::vector<float>> rows;
  if (!opt.mix.empty()) {
    if (!opt.classes.empty()) throw UsageError("--class and --mix exclude each other");
    std::string name;
    const auto w = parse_mix(m, opt.mix, name);
    for (int k = 0; k < opt.count; ++k) {
      rows.push_back(w);
      names.push_back(fmt::format("{}~{}", name, k));
    }
  } else {
    const auto classes = opt.classes.empty() ? m.class_names : opt.classes;
    for (const auto& cls : classes) {
      const int c = class_index(m, cls);
      for (int k = 0; k < opt.count; ++k) {
        std::vector<float> w(m.class_names.size(), 0.0f);
        w[static_cast<std::size_t>(c)] = 1;
        rows.push_back(w);
        names.push_back(fmt::format("{}~{}", cls, k));
      }
    }
  }
  nn::Matrix<float> y(static_cast<Eigen::Index>(rows.size()),
                      static_cast<Eigen::Index>(m.class_names.size()));
  for (std::size_t r = 0; r < rows.size(); ++r)
    y.row(static_cast<Eigen::Index>(r)) =
        Eigen::Map<const Eigen::RowVectorXf>(rows[r].data(), y.cols());
  return y;
}

void generate_actions(const ActganModel& m, const nn::Matrix<float>& y, int length, Rng& rng,
                      std::vector<float>& poses, std::vector<float>& latents) {
  const auto P = static_cast<std::size_t>(m.config.pose),
             Z = static_cast<std::size_t>(m.config.latent);
  const auto L = static_cast<std::size_t>(length);
  poses.assign(static_cast<std::size_t>(y.rows()) * L * P, 0.0f);
  latents.assign(static_cast<std::size_t>(y.rows()) * L * Z, 0.0f);
  nn::Tape<float> tape;
  for (Eigen::Index r0 = 0; r0 < y.rows(); r0 += kBatch) {
    const Eigen::Index n = std::min(kBatch, y.rows() - r0);
    const auto noise = draw_generator_noise<float>(m.config, n, length, rng);
    tape.clear();
    const auto g = generate_from_noise(*m.gen, m.gen->store().bind_constant(tape), tape,
                                       nn::Matrix<float>(y.middleRows(r0, n)), noise);
    for (Eigen::Index i = 0; i < n; ++i)
      for (std::size_t t = 0; t < L; ++t) {
        const auto s = static_cast<std::size_t>(r0 + i);
        for (std::size_t k = 0; k < P; ++k)
          poses[(s * L + t) * P + k] = g.frames[t].value()(i, static_cast<Eigen::Index>(k));
        if (!g.latents.empty())
          for (std::size_t k = 0; k < Z; ++k)
            latents[(s * L + t) * Z + k] = g.latents[t].value()(i, static_cast<Eigen::Index>(k));
      }
  }
}

Recognised recognise(const ActganModel& m, const io::SkeletonFile& s,
                     const std::vector<std::size_t>& seqs, std::size_t length) {
  if (!m.config.classifier) throw Error("internal: recognise() with a model without a classifier");
  if (s.joints * 3 != static_cast<std::size_t>(m.config.pose) || s.dims != 3)
    throw InvalidInput(fmt::format("{} joints x {}: the model was trained on {} values per pose",
                                   s.joints, s.dims, m.config.pose));
  const std::vector<float> poses = io::poses_normalized_as(s, m.normalization);
  const std::size_t P = s.frame_size();
  Recognised out;
  out.prob.resize(static_cast<Eigen::Index>(seqs.size()), m.config.classes);
  out.features.resize(static_cast<Eigen::Index>(seqs.size()), m.config.fc);
  nn::Tape<float> tape;
  for (std::size_t r0 = 0; r0 < seqs.size(); r0 += kBatch) {
    const std::size_t n = std::min<std::size_t>(kBatch, seqs.size() - r0);
    std::size_t frames = length ? length : s.length(seqs[r0]);
    for (std::size_t i = 0; i < n; ++i) {
      if (length && s.length(seqs[r0 + i]) < length)
        throw Error(
            fmt::format("internal: sequence {} is shorter than {} frames", seqs[r0 + i], length));
      if (!length) frames = std::min(frames, s.length(seqs[r0 + i]));
    }
    tape.clear();
    std::vector<nn::Var<float>> x;
    for (std::size_t t = 0; t < frames; ++t) {
      nn::Matrix<float> xt(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(P));
      for (std::size_t i = 0; i < n; ++i)
        xt.row(static_cast<Eigen::Index>(i)) = Eigen::Map<const Eigen::RowVectorXf>(
            poses.data() + (static_cast<std::size_t>(s.offsets[seqs[r0 + i]]) + t) * P,
            static_cast<Eigen::Index>(P));
      x.push_back(tape.constant(xt));
    }
    const auto p = m.cls->store().bind_constant(tape);
    const auto rows = [&](nn::Matrix<float>& M) {
      return M.middleRows(static_cast<Eigen::Index>(r0), static_cast<Eigen::Index>(n));
    };
    const nn::Var<float> f = m.cls->features(p, x);  // the BiLSTM once, for both
    rows(out.features) = f.value();
    rows(out.prob) = nn::softmax<float>(m.cls->output(p, f).value());
  }
  return out;
}

}  // namespace df::models
