// What eval-metrics measures of mesh sequences (the predicted file PRED, alone or against the
// data TRUTH): the frame pairs, each pair's errors and STED, the totals that leave given frames
// out, the spread of diverse samples and each sample against the truth, the feature change of a
// sequence and the pace of a prediction. The tool (apps/eval_metrics) reads the files and writes
// the JSON, TSV and table from these.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "convert/frame_set.h"
#include "eval/mesh_metrics.h"
#include "geometry/mesh_topology.h"

namespace df::eval {

/// The template's topology and parts, which every measure of one file pair shares.
struct SequenceShape {
  geometry::MeshTopology topo;
  MeshParts parts;
};
SequenceShape shape_of(const convert::FrameSet& pred);

/// Feature change between frames `span` apart in each PRED sequence, by index in the sequence
/// (index t: frames t and t + span); nothing when PRED has no features.
struct FeatureChange {
  std::vector<double> by_index;
  double total = 0;
  std::size_t n = 0;
};
FeatureChange feature_change_of(const convert::FrameSet& pred, int change_span);

/// (PRED frame, TRUTH frame) pairs.
using FramePairs = std::vector<std::pair<std::size_t, std::size_t>>;
/// Which PRED frame is measured against which TRUTH frame: /frames/source (frames without a
/// source, -1, left out), else frame by frame. InvalidInput, naming the file at fault, when the
/// templates differ, a source is past TRUTH's end, the frame counts differ without sources, or
/// no pair is left.
FramePairs pair_frames(const convert::FrameSet& pred, const convert::FrameSet& truth);

/// One pair's errors: mean vertex distance and unit-ball squared error after alignment, STED's
/// spatial part, and the relative squared feature error (-1: a file without features).
struct PairResult {
  double error = 0, unit_ball = 0, sted_s = 0, rse = -1;
};
struct PairOptions {
  int sted_rings = 1;
  double sted_dt = 1;
  Alignment align = Alignment::translation;
};
/// Every pair's errors (positions aligned per part) and STED's temporal part over consecutive
/// PRED frames of one sequence that both have truth; diag is TRUTH's template's bounding-box
/// diagonal. Reconstructs the positions of both files where they are not stored.
struct PairMeasures {
  std::vector<PairResult> results;
  double diag = 0, sted_t = 0;
  std::size_t sted_t_n = 0;
};
PairMeasures measure_pairs(convert::FrameSet& pred, convert::FrameSet& truth,
                           const SequenceShape& sh, const FramePairs& pairs,
                           const PairOptions& opt);

/// Diverse samples: sequences NAME~k, by NAME (sequence indices), only names with at least two.
using SampleGroups = std::map<std::string, std::vector<std::size_t>>;
SampleGroups sample_groups(const convert::FrameSet& pred);
/// Spread of diverse samples: samples of equal length compared frame by frame, every pair of
/// samples (aligned per part), given frames (step 0, identical in every sample) left out.
/// Returns the sum of the mean vertex distances and the count of compared pairs; InvalidInput
/// when one name's samples differ in length.
std::pair<double, std::size_t> sample_spread(convert::FrameSet& pred, const SampleGroups& groups,
                                             const SequenceShape& sh);

/// The pairs' totals. Given frames (step 0 of generated files) are copies of the truth: the
/// totals leave them out (skip_given, when any frame has a step above 0); the per-step sums
/// (step, or PRED's frame index without steps) keep them.
struct Totals {
  double err = 0, ub = 0, sted_s = 0, rse_max = 0, rse_mean = 0;
  std::size_t rse_n = 0, counted = 0;
  bool skip_given = false;
  std::map<int, std::pair<double, int>> by_step;  ///< step -> (error sum, frames)
};
Totals totals_of(const convert::FrameSet& pred, const FramePairs& pairs,
                 const std::vector<PairResult>& results);

/// Diverse samples against the truth, each sample on its own: the mean error of each sample's
/// generated frames, then per case the best, the mean and the worst of its K samples, averaged
/// over the cases (a fair comparison with a single deterministic answer is the mean of K; best
/// of K is what a user who picks gets).
struct SamplesVsTruth {
  double best = 0, mean = 0, worst = 0;
  std::size_t cases = 0;
};
SamplesVsTruth samples_vs_truth(const convert::FrameSet& pred, const SampleGroups& groups,
                                const FramePairs& pairs, const std::vector<PairResult>& results,
                                bool skip_given);

/// The pace of a prediction: over the first kPaceSteps frames after the given ones, how far each
/// frame moves from the one before (motion_between), the prediction's against the data's at the
/// same times, per case (sequence). Their ratio summed over the cases: 1 is the data's pace, near
/// 0 frozen, above 1 moving where the data stands still.
constexpr int kPaceSteps = 5;
struct PaceCase {
  std::string name;                 ///< PRED's sequence
  double predicted = 0, truth = 0;  ///< motion summed over the kPaceSteps frames
};
/// The mean vertex distance between two frames, each one's centroid removed.
double motion_between(const Vertices& a, const Vertices& b);
/// The cases whose first kPaceSteps predicted frames (and the given frame before them) all have
/// a TRUTH frame (/frames/source); none without steps or sources.
std::vector<PaceCase> pace_of(const convert::FrameSet& pred, const convert::FrameSet& truth);

}  // namespace df::eval
