#include "models/common/model_data.h"

#include <fmt/format.h>

#include <numeric>

#include "core/error.h"

namespace df::models {

ModelData::ModelData(const std::string& path, const Mesh& tmpl) : file_(path) {
  file_.require_template(tmpl, "the model");
}

nn::Matrix<float> ModelData::features(const std::vector<std::int64_t>& frames,
                                      const FeatureNormalization& nz) const {
  const std::size_t row = file_.vertices() * kAcapFeatureDims;
  nn::Matrix<float> x(static_cast<Eigen::Index>(frames.size()), static_cast<Eigen::Index>(row));
  // Where the rows come from: the stored normalized features as they are (the same numbers), the
  // raw ones normalized, or the stored ones renormalized through the file's own numbers.
  enum class From { stored, raw, renormalized };
  const bool normalized = file_.has_normalized();
  const FeatureNormalization own = file_.has_normalization() ? file_.normalization() : nz;
  const From from = normalized && file_.has_normalization() && own.same_numbers(nz) ? From::stored
                    : file_.has_raw()                                               ? From::raw
                    : normalized ? From::renormalized
                                 : throw InvalidInput(
                                       "has no features (/features/raw or /features/normalized); "
                                       "run obj2acap on the meshes first",
                                       file_.path());
  std::vector<double> raw;
  // Runs of consecutive frames are read in one call (a chunk is decompressed once per run).
  for (std::size_t k = 0; k < frames.size();) {
    std::size_t run = 1;
    while (k + run < frames.size() && frames[k + run] == frames[k] + static_cast<std::int64_t>(run))
      ++run;
    const auto first = static_cast<std::size_t>(frames[k]);
    float* out = x.row(static_cast<Eigen::Index>(k)).data();
    if (from == From::raw) {
      raw.resize(run * row);
      file_.read_raw(first, run, raw.data());
      for (std::size_t j = 0; j < run * row; ++j)
        out[j] = static_cast<float>(nz.normalize(static_cast<int>(j % kAcapFeatureDims), raw[j]));
    } else {
      file_.read_normalized(first, run, out);
      if (from == From::renormalized)
        for (std::size_t j = 0; j < run * row; ++j) {
          const int d = static_cast<int>(j % kAcapFeatureDims);
          out[j] = static_cast<float>(nz.normalize(d, own.denormalize(d, out[j])));
        }
    }
    k += run;
  }
  return x;
}

nn::Matrix<float> training_features(const io::AcapReader& in, const std::string& path) {
  if (!in.has_normalized())
    throw InvalidInput("has no /features/normalized; run obj2acap on the meshes first", path);
  nn::Matrix<float> x(static_cast<Eigen::Index>(in.frames()),
                      static_cast<Eigen::Index>(in.vertices() * kAcapFeatureDims));
  in.read_normalized(0, in.frames(), x.data());
  return x;
}

nn::Matrix<float> ModelData::all_features(const FeatureNormalization& nz) const {
  std::vector<std::int64_t> all(frames());
  std::iota(all.begin(), all.end(), std::int64_t{0});
  return features(all, nz);
}

}  // namespace df::models
