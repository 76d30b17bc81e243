// eval-metrics: compares predicted frames with ground truth (SPEC §9) and prints a table;
// --json writes every number (per frame, per future-frame step, per time index).
//   * inputs: acap files (positions are used when stored, else reconstructed from the features
//     with the exact solver) or mesh directories;
//   * frames are paired through PRED's /frames/source (gen-bdlstm) or by index;
//   * per-vertex position error after removing one translation per connected component (the
//     reconstruction's freedom), raw and / bounding-box diagonal of TRUTH's template, per frame
//     and per /frames/step; E_rms; STED spatial, temporal and combined; relative squared error
//     of normalized ACAP features; feature change between consecutive frames of each sequence;
//   * PRED a components file (extract-components / prune-components) and TRUTH with planted
//     regions (synth-meshseq --kind bumps): how well the kept components localize them
//     (component_metrics.h);
//   * PRED and TRUTH skeleton files (gen-actgan, skel2h5): MMD_avg, MMD_seq and the spread of
//     generated sequences per class (skeleton_metrics.h); with a recogniser (an ActGAN model's
//     classifier, train-actgan --classifier-only) FID, diversity, multimodality and accuracy in
//     its feature space (recognition_metrics.h);
//   * the spread of diverse samples (gen-bdlstm --samples: sequences NAME~k): mean per-vertex
//     distance between every two samples of a case at the same frame.
#pragma once

#include <string>
#include <vector>

#include "core/common_options.h"
#include "eval/skeleton_metrics.h"

namespace df::apps {

struct EvalOptions {
  std::string pred, truth;  ///< truth "" = only single-file measures (feature change)
  std::string json;         ///< "" = none; "-" = stdout (then no table)
  std::string tsv;  ///< "" = none; else per-step errors and feature change per index, for gnuplot
  std::vector<int> steps;  ///< steps shown in the table (empty = all when few)
  /// How PRED is aligned to TRUTH before measuring, per connected part: "translation" (the
  /// reconstruction's own freedom) or "rigid" (rotation too, Kabsch; the MSAE paper's protocol)
  std::string align = "translation";
  int sted_rings = 1;
  double sted_dt = 1.0;  ///< frame interval for STED's temporal part
  double sted_c = 1.0;   ///< STED = sqrt(STED_s² + c² STED_t²)
  /// Feature change between frames this far apart (1 = consecutive, the paper's Fig. 2). Wider
  /// spans tell sustained motion (grows with the span) from frame-to-frame jitter (does not).
  int change_span = 1;
  /// PRED a components file: a component's support is where its deformation reaches this
  /// fraction of its maximum (localization against TRUTH's planted regions)
  double support_threshold = 0.1;
  /// PRED and TRUTH skeleton files: which sequences are compared (all of TRUTH's, or some
  /// subjects' of either file)
  eval::SkeletonSelection skeletons;
  /// Skeleton files: an ActGAN model whose classifier recognises the clips ("" = none)
  std::string recogniser;
};

void eval_metrics(const EvalOptions& opt, const CommonOptions& common);

}  // namespace df::apps
