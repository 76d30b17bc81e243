// The numbers that normalize ACAP features to [−0.95, 0.95] for tanh networks (SPEC §4.7), at the
// bottom so that geometry computes them and the models use them without the file formats
// (io/acap_file.h writes and reads /normalization).
#pragma once

#include <array>

namespace df {

/// Numbers per vertex of an ACAP feature: the rotation's log (3) and the symmetric stretch's upper
/// triangle (6).
inline constexpr int kAcapFeatureDims = 9;

enum class NormalizationMode { group, per_dim };

struct FeatureNormalization {
  NormalizationMode mode = NormalizationMode::group;
  std::array<double, kAcapFeatureDims> min{}, max{};

  /// x_norm = −0.95 + 1.9 (x − min_d) / (max_d − min_d)
  double normalize(int d, double x) const { return -0.95 + 1.9 * (x - min[d]) / (max[d] - min[d]); }
  double denormalize(int d, double y) const {
    return min[d] + (y + 0.95) * (max[d] - min[d]) / 1.9;
  }
  bool same_numbers(const FeatureNormalization& o) const { return min == o.min && max == o.max; }
};

}  // namespace df
