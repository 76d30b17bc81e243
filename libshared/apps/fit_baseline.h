// fit-baseline's job: the baselines of models/baselines (PCA, SPLOCS on positions, SPLOCS on ACAP
// features) fitted on an MSAE model's training shapes, the held-out shapes reconstructed and
// written like recon-msae's, the basis optionally as a components file.
#pragma once

#include <span>
#include <string>

#include "core/choice.h"
#include "core/common_options.h"
#include "models/common/frame_part.h"
#include "models/common/splocs.h"

namespace df::apps {
using models::FramePart;
using models::SplocsOptions;

/// fit-baseline's methods (names as core/choice.h).
enum class BaselineMethod { pca, splocs, splocs_acap };
inline constexpr Named<BaselineMethod> kBaselineMethodNames[] = {
    {"pca", BaselineMethod::pca},
    {"splocs", BaselineMethod::splocs},
    {"splocs-acap", BaselineMethod::splocs_acap}};
constexpr std::span<const Named<BaselineMethod>> names_of(BaselineMethod) {
  return kBaselineMethodNames;
}

struct BaselineOptions {
  std::string model, data, output;
  BaselineMethod method = BaselineMethod::pca;
  int components = 0;  ///< 0 = as many as the MSAE model has
  FramePart part = FramePart::test;
  /// Also write the fitted basis as a components file (pca and splocs-acap, whose components are
  /// ACAP features): prune-components, render-mesh and eval-metrics then take them as MSAE's
  std::string components_out;
  SplocsOptions splocs;
};
/// fit-baseline: fits on the model's training shapes, writes the reconstructions of `part` as
/// an acap file (pca: normalized features; splocs: positions), paired with DATA like recon-msae.
void fit_baseline(const BaselineOptions& opt, const CommonOptions& common);

}  // namespace df::apps
