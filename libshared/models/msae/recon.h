// recon-msae: shapes encoded and decoded by a trained MSAE through its first 1..L levels, written
// as an acap file (normalized features; /frames/source pairs each frame with the data frame it
// reconstructs) for acap2obj, render-mesh and eval-metrics (E_rms, STED, eq. 8).
#pragma once

#include <string>

#include "core/tool.h"

namespace df::models {

struct MsaeReconOptions {
  std::string model, data, output;
  std::string part = "test";  ///< train | validation | test | all
  int levels = 0;             ///< 0 = every level of the model
};

void recon_msae(const MsaeReconOptions& opt, const CommonOptions& common);

}  // namespace df::models
