// obj2acap: mesh frames -> the acap file kind (template, positions, raw and normalized ACAP
// features, normalization numbers, sequences, labels). SPEC §4.
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"
#include "geometry/acap_consistency.h"
#include "geometry/acap_features.h"

namespace df::convert {

struct Obj2AcapOptions {
  std::vector<std::string> inputs;  ///< see FrameReader for how inputs become sequences
  std::string output;               ///< .h5 path
  std::string reference;            ///< mesh file; "" = the first frame
  NormalizationMode normalize = NormalizationMode::group;
  std::vector<std::string> labels;  ///< one per sequence ("" = keep the inputs' labels)
  bool consistency = true;          ///< false: principal per-vertex logs (for comparison only)
  geometry::ConsistencyOptions consistency_options;
  std::size_t block_frames = 16;  ///< frames per pipeline block
};

void obj2acap(const Obj2AcapOptions& opt, const CommonOptions& common);

}  // namespace df::convert
