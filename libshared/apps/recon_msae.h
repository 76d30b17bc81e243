// recon-msae: shapes encoded and decoded by a trained MSAE through its first 1..L levels, written
// as an acap file (normalized features; /frames/source pairs each frame with the data frame it
// reconstructs) for acap2obj, render-mesh and eval-metrics (E_rms, STED, eq. 8). With fit_codes
// the codes are least-squares fits through the decoders (the protocol PCA and SPLOCS are measured
// under) and the feature error of both kinds of code is printed.
#pragma once

#include <string>

#include "core/common_options.h"
#include "models/common/frame_part.h"

namespace df::apps {
using models::FramePart;

struct MsaeReconOptions {
  std::string model, data, output;
  FramePart part = FramePart::test;  ///< train | validation | test | all
  int levels = 0;                    ///< 0 = every level of the model
  /// > 0: the codes are fitted to each shape through the decoders (MsaeNet::fit_codes) in this
  /// many Adam steps, starting from the encoder's, instead of taken from the encoder
  int fit_codes = 0;
  double fit_lr = 0.05;  ///< fit_codes' initial rate
};

void recon_msae(const MsaeReconOptions& opt, const CommonOptions& common);

}  // namespace df::apps
