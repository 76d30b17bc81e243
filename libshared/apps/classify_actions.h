// classify-actions' job: an ActGAN model's classifier (models::recognise) on a skeleton file's
// sequences — per class how many are recognised, as a table and as JSON.
#pragma once

#include <string>

#include "core/common_options.h"

namespace df::apps {

struct ClassifyOptions {
  std::string model, input;
  bool all = false;            ///< every sequence, not only the test part
  std::string json;            ///< "" or a file (or "-") with per-class accuracy and probabilities
  bool probabilities = false;  ///< print each sequence's class probabilities
};

void classify_actions(const ClassifyOptions& opt, const CommonOptions& common);

}  // namespace df::apps
