// A model's data: an ACAP file read as a trained model of one template and one normalization
// sees it — the template checked, the features normalized with the model's numbers — the one
// reader behind gen-bdlstm, recon-msae, extract-components and fit-baseline.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/acap_file.h"
#include "nn/tape.h"

namespace df::models {

class ModelData {
 public:
  /// Opens `path` (kind acap) and checks that its template is `tmpl` (vertex count and
  /// triangles): InvalidInput otherwise, saying model and data must share the template.
  ModelData(const std::string& path, const Mesh& tmpl);

  const io::AcapReader& file() const { return file_; }
  std::size_t frames() const { return file_.frames(); }

  /// The 9V features of the listed frames (rows in that order), normalized with `nz`: the
  /// stored normalized ones when the file's numbers are nz's, else the raw ones normalized,
  /// else the stored normalized ones renormalized; every value checked finite. InvalidInput
  /// when the file has no features.
  nn::Matrix<float> features(const std::vector<std::int64_t>& frames,
                             const FeatureNormalization& nz) const;
  /// The same of every frame.
  nn::Matrix<float> all_features(const FeatureNormalization& nz) const;

 private:
  io::AcapReader file_;
};

/// A trainer's data: every frame's stored normalized features, one row of 9V per frame.
/// InvalidInput when the file has none (obj2acap writes them).
nn::Matrix<float> training_features(const io::AcapReader& in, const std::string& path);

}  // namespace df::models
