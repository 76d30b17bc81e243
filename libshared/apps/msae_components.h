// extract-components' and prune-components' jobs: a trained MSAE's components read out of its
// decoders (models/msae/components.h) and written as a components file (and as frames), with
// extract-components' --report; their strengths (eq. 7), the pruning, its table and JSON.
#pragma once

#include <string>

#include "core/common_options.h"

namespace df::apps {

struct ExtractOptions {
  std::string model, data, output, acap;
  /// "" = none; validation or test: print diagnose_msae's table for that held-out part
  std::string report;
};
void extract_components_tool(const ExtractOptions& opt, const CommonOptions& common);

struct PruneOptions {
  std::string input, output, acap, json;
  double eps1 = 1e-6, eps2 = 0.01;
};
void prune_components_tool(const PruneOptions& opt, const CommonOptions& common);

}  // namespace df::apps
