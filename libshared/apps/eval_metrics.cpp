#include "apps/eval_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "apps/component_metrics.h"
#include "convert/frame_set.h"
#include "core/atomic_output.h"
#include "core/error.h"
#include "core/log.h"
#include "eval/mesh_metrics.h"
#include "eval/recognition_metrics.h"
#include "eval/sequence_measures.h"
#include "eval/skeleton_metrics.h"
#include "io/h5.h"
#include "io/schema.h"
#include "models/actgan/generate.h"

namespace df::apps {
using namespace df::eval;
namespace {

// The recogniser's view of the compared clips (the sequences skeleton_metrics pairs, each read
// for the frames it compares): FID, diversity, multimodality and accuracy, and each class's
// accuracy of PRED's and of TRUTH's clips.
struct Recognition {
  RecognitionMetrics metrics;
  std::vector<std::string> classes;
  std::vector<double> accuracy_generated, accuracy_real;
};

Recognition recognition_of(const io::SkeletonFile& pred, const io::SkeletonFile& truth,
                           const SkeletonSelection& select, const std::string& model_path) {
  const models::ActganModel m = models::load_actgan_model(model_path);
  if (!m.config.classifier)
    throw InvalidInput(
        "the recogniser has no classifier (trained with --no-classifier); train one with "
        "train-actgan --classifier-only",
        model_path);
  const SkeletonPairing pairs = pair_skeleton_classes(pred, truth, select);
  Recognition out;
  std::vector<std::size_t> gen, real;
  std::vector<int> gen_labels, real_labels, class_labels;
  for (const auto& k : pairs.classes) {
    const auto it = std::find(m.class_names.begin(), m.class_names.end(), k.name);
    if (it == m.class_names.end())
      throw InvalidInput(fmt::format("the recogniser does not know class '{}' (it knows: {})",
                                     k.name, fmt::join(m.class_names, ", ")),
                         model_path);
    const int label = static_cast<int>(it - m.class_names.begin());
    out.classes.push_back(k.name);
    class_labels.push_back(label);
    gen.insert(gen.end(), k.pred.begin(), k.pred.end());
    gen_labels.insert(gen_labels.end(), k.pred.size(), label);
    real.insert(real.end(), k.truth.begin(), k.truth.end());
    real_labels.insert(real_labels.end(), k.truth.size(), label);
  }
  const auto clips_of = [&](const io::SkeletonFile& file, const std::vector<std::size_t>& seqs,
                            const std::vector<int>& labels) {
    const models::Recognised r = models::recognise(m, file, seqs, pairs.frames);
    RecognisedClips c;
    c.features = r.features.cast<double>();
    c.labels = labels;
    for (Eigen::Index i = 0; i < r.prob.rows(); ++i) {
      Eigen::Index best = 0;
      r.prob.row(i).maxCoeff(&best);
      c.predicted.push_back(static_cast<int>(best));
    }
    return c;
  };
  const RecognisedClips g = clips_of(pred, gen, gen_labels), t = clips_of(truth, real, real_labels);
  out.metrics = recognition_metrics(g, t);
  const auto class_accuracy = [](const RecognisedClips& c, int label) {
    RecognisedClips one;
    for (std::size_t i = 0; i < c.labels.size(); ++i)
      if (c.labels[i] == label)
        one.labels.push_back(label), one.predicted.push_back(c.predicted[i]);
    return accuracy(one);
  };
  for (const int label : class_labels) {
    out.accuracy_generated.push_back(class_accuracy(g, label));
    out.accuracy_real.push_back(class_accuracy(t, label));
  }
  return out;
}

nlohmann::ordered_json recognition_json(const Recognition& r, const std::string& model_path) {
  const auto scores = [](const RecognitionScores& s) {
    return nlohmann::ordered_json{{"fid", s.fid},
                                  {"diversity", s.diversity},
                                  {"multimodality", s.multimodality},
                                  {"accuracy", s.accuracy}};
  };
  nlohmann::ordered_json js{{"recogniser", model_path},
                            {"features", r.metrics.features},
                            {"generated", scores(r.metrics.generated)},
                            {"real", scores(r.metrics.real)}};
  for (std::size_t c = 0; c < r.classes.size(); ++c)
    js["classes"][r.classes[c]] = {{"accuracy_generated", r.accuracy_generated[c]},
                                   {"accuracy_real", r.accuracy_real[c]}};
  return js;
}

void print_recognition(const Recognition& r, const std::string& model_path) {
  fmt::print(
      "\nrecogniser {} ({} features): FID of Gaussians fitted to the features, diversity (200\n"
      "random pairs), multimodality (20 pairs per class), accuracy of the most probable class\n",
      model_path, r.metrics.features);
  fmt::print("{:<28} {:>10} {:>10} {:>14} {:>9}\n", "", "FID", "diversity", "multimodality",
             "accuracy");
  const auto row = [](const char* what, const RecognitionScores& s) {
    fmt::print("{:<28} {:>10.4g} {:>10.4g} {:>14.4g} {:>9.3f}\n", what, s.fid, s.diversity,
               s.multimodality, s.accuracy);
  };
  row("generated (PRED)", r.metrics.generated);
  row("real (TRUTH; FID of halves)", r.metrics.real);
}

// eval-metrics on skeleton files: the table (or JSON) of skeleton_metrics, and with a
// recogniser the measures in its feature space.
void eval_skeletons(const EvalOptions& opt, bool force) {
  const std::string &pred_path = opt.pred, &truth_path = opt.truth, &json = opt.json;
  const SkeletonSelection& select = opt.skeletons;
  if (truth_path.empty())
    throw UsageError("skeleton files are measured against TRUTH (real sequences)");
  const io::SkeletonFile pred = io::read_skeleton_file(pred_path);
  const io::SkeletonFile truth = io::read_skeleton_file(truth_path);
  const SkeletonMetrics r = skeleton_metrics(pred, truth, select);
  std::optional<Recognition> recognition;
  if (!opt.recogniser.empty()) recognition = recognition_of(pred, truth, select, opt.recogniser);
  nlohmann::ordered_json js;
  js["pred"] = pred_path;
  js["truth"] = truth_path;
  js["frames"] = r.frames;
  js["mmd_avg"] = r.mmd_avg;
  js["mmd_seq"] = r.mmd_seq;
  js["mmd_motion_avg"] = r.mmd_motion_avg;
  js["mmd_motion_seq"] = r.mmd_motion_seq;
  js["pairwise_ratio"] = r.pairwise_ratio;
  js["pace_ratio"] = r.pace_ratio;
  for (const auto& m : r.classes)
    js["classes"][m.name] = {{"generated", m.generated},
                             {"real", m.real},
                             {"mmd_avg", m.mmd_avg},
                             {"mmd_seq", m.mmd_seq},
                             {"mmd_motion_avg", m.mmd_motion_avg},
                             {"mmd_motion_seq", m.mmd_motion_seq},
                             {"spread_mean", m.spread_mean},
                             {"spread_sd", m.spread_sd},
                             {"pairwise_generated", m.pairwise_generated},
                             {"pairwise_real", m.pairwise_real},
                             {"halves_generated", m.halves_generated},
                             {"halves_real", m.halves_real},
                             {"motion_generated", m.motion_generated},
                             {"motion_real", m.motion_real}};
  if (recognition) js["recognition"] = recognition_json(*recognition, opt.recogniser);
  if (json != "-") {
    fmt::print("{} vs {} ({} frames per sequence; MMD_u^2 max over bandwidths 1e-4..1e9)\n",
               pred_path, truth_path, r.frames);
    fmt::print("{:<16} {:>9} {:>6} {:>11} {:>11} {:>11} {:>11} {:>12} {:>10}\n", "class",
               "generated", "real", "MMD_avg", "MMD_seq", "motion_avg", "motion_seq", "spread mean",
               "spread sd");
    for (const auto& m : r.classes)
      fmt::print("{:<16} {:>9} {:>6} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g} {:>12.5g} {:>10.5g}\n",
                 m.name, m.generated, m.real, m.mmd_avg, m.mmd_seq, m.mmd_motion_avg,
                 m.mmd_motion_seq, m.spread_mean, m.spread_sd);
    fmt::print("{:<16} {:>9} {:>6} {:>11.5g} {:>11.5g} {:>11.5g} {:>11.5g}\n", "mean", "", "",
               r.mmd_avg, r.mmd_seq, r.mmd_motion_avg, r.mmd_motion_seq);
    fmt::print(
        "\n"
        "variety: mean distance between two sequences, and MMD_u^2 of one half of a set against "
        "the other\n"
        "(at the bandwidth of the class's MMD_seq: its sampling noise)\n");
    fmt::print("{:<16} {:>14} {:>14} {:>8} {:>14} {:>14} {:>10}\n", "class", "dist generated",
               "dist real", "ratio", "halves gen.", "halves real", "pace");
    for (const auto& m : r.classes)
      fmt::print("{:<16} {:>14.5g} {:>14.5g} {:>8.3f} {:>14.5g} {:>14.5g} {:>10.3f}\n", m.name,
                 m.pairwise_generated, m.pairwise_real, m.pairwise_generated / m.pairwise_real,
                 m.halves_generated, m.halves_real, m.motion_generated / m.motion_real);
    fmt::print("{:<16} {:>14} {:>14} {:>8.3f} {:>14} {:>14} {:>10.3f}\n", "mean", "", "",
               r.pairwise_ratio, "", "", r.pace_ratio);
    fmt::print(
        "pace: the mean distance a pose moves per frame, generated over real (1: the data's "
        "pace)\n");
    if (recognition) print_recognition(*recognition, opt.recogniser);
  }
  if (json.empty()) return;
  if (json == "-") {
    fmt::print("{}\n", js.dump(2));
    return;
  }
  write_text_output(json, js.dump(2) + "\n", force, {pred_path, truth_path});
}

using convert::FrameSet;
using convert::read_frame_set;

void check_options(const EvalOptions& opt) {
  if (opt.sted_rings < 1) throw UsageError("--sted-rings must be at least 1");
  if (!(opt.sted_dt > 0)) throw UsageError("--sted-dt must be positive");
  if (opt.change_span < 1) throw UsageError("--change-span must be at least 1");
  if (opt.align != "translation" && opt.align != "rigid")
    throw UsageError("--align must be translation or rigid");
}

// Everything measured on one file pair (or on PRED alone), as the JSON, the TSV and the table
// show it.
struct MeshMeasures {
  bool has_truth = false;
  std::vector<PaceCase> pace;
  FramePairs pairs;
  PairMeasures pm;
  Totals totals;
  SamplesVsTruth samples;
  FeatureChange change;
  double spread = 0;
  std::size_t spread_n = 0, spread_cases = 0;
  double spread_diag = 0;
};

// The vertex error: its mean, per step after the given frames (gen-bdlstm's predictions; else
// per_frame says it all) and per frame pair.
nlohmann::ordered_json vertex_error_json(const MeshMeasures& m, const FrameSet& pred, double np,
                                         double diag) {
  const auto& t = m.totals;
  nlohmann::ordered_json js = {{"mean", t.err / np}, {"mean_relative", t.err / np / diag}};
  if (!pred.step.empty()) {
    nlohmann::ordered_json steps = nlohmann::ordered_json::array();
    for (const auto& [s, v] : t.by_step)
      steps.push_back({{"step", s},
                       {"frames", v.second},
                       {"mean", v.first / v.second},
                       {"relative", v.first / v.second / diag}});
    js["per_step"] = steps;
  }
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < m.pm.results.size(); ++k)
    frames.push_back({{"pred", m.pairs[k].first},
                      {"truth", m.pairs[k].second},
                      {"error", m.pm.results[k].error},
                      {"sted_spatial", m.pm.results[k].sted_s}});
  js["per_frame"] = frames;
  return js;
}

// The pace over the first kPaceSteps predicted frames: in all and per case.
nlohmann::ordered_json pace_json(const std::vector<eval::PaceCase>& pace, double diag) {
  double predicted = 0, truth = 0;
  for (const auto& c : pace) predicted += c.predicted, truth += c.truth;
  const double n = static_cast<double>(pace.size() * kPaceSteps);
  nlohmann::ordered_json js = {{"steps", kPaceSteps},
                               {"cases", pace.size()},
                               {"predicted_per_frame", predicted / n},
                               {"true_per_frame", truth / n},
                               {"predicted_per_frame_relative", predicted / n / diag},
                               {"true_per_frame_relative", truth / n / diag},
                               {"ratio", truth > 0 ? predicted / truth : 0.0}};
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const auto& c : pace)
    cases.push_back({{"case", c.name},
                     {"predicted_relative", c.predicted / kPaceSteps / diag},
                     {"true_relative", c.truth / kPaceSteps / diag}});
  js["per_case"] = cases;
  return js;
}

nlohmann::ordered_json to_json(const MeshMeasures& m, const FrameSet& pred,
                               const EvalOptions& opt) {
  nlohmann::ordered_json js;
  js["pred"] = opt.pred;
  const auto& t = m.totals;
  const double np = static_cast<double>(t.counted), diag = m.pm.diag;
  const std::size_t nv = static_cast<std::size_t>(pred.tmpl.vertices.rows());
  if (m.has_truth) {
    js["truth"] = opt.truth;
    js["frame_pairs"] = m.pm.results.size();
    if (opt.align != "translation") js["align"] = opt.align;
    js["frames_measured"] = t.counted;
    js["diagonal"] = diag;
    js["vertex_error"] = vertex_error_json(m, pred, np, diag);
    js["erms"] = erms_from_sum(t.ub, np, static_cast<double>(nv));
    const double st = m.pm.sted_t_n ? m.pm.sted_t / static_cast<double>(m.pm.sted_t_n) : 0.0;
    js["sted"] = {{"spatial", t.sted_s / np}, {"rings", opt.sted_rings}};
    if (m.pm.sted_t_n) {
      js["sted"]["temporal"] = st;
      js["sted"]["combined"] =
          std::sqrt(std::pow(t.sted_s / np, 2) + opt.sted_c * opt.sted_c * st * st);
      js["sted"]["dt"] = opt.sted_dt;
      js["sted"]["c"] = opt.sted_c;
    }
    if (t.rse_n)
      js["relative_squared_error"] = {{"max", t.rse_max},
                                      {"mean", t.rse_mean / static_cast<double>(t.rse_n)}};
    if (!m.pace.empty()) js["pace"] = pace_json(m.pace, diag);
    const auto& v = m.samples;
    if (v.cases)
      js["samples_vs_truth"] = {{"cases", v.cases},
                                {"mean_of_k", v.mean},
                                {"best_of_k", v.best},
                                {"worst_of_k", v.worst},
                                {"mean_of_k_relative", v.mean / diag},
                                {"best_of_k_relative", v.best / diag},
                                {"worst_of_k_relative", v.worst / diag}};
  }
  if (m.spread_n)
    js["sample_spread"] = {
        {"mean", m.spread / static_cast<double>(m.spread_n)},
        {"mean_relative", m.spread / static_cast<double>(m.spread_n) / m.spread_diag},
        {"cases", m.spread_cases}};
  const auto& c = m.change;
  if (c.n)
    js["feature_change"] = {{"span", opt.change_span},
                            {"mean", c.total / static_cast<double>(c.n)},
                            {"min", *std::min_element(c.by_index.begin(), c.by_index.end())},
                            {"max", *std::max_element(c.by_index.begin(), c.by_index.end())},
                            {"per_index", c.by_index}};
  return js;
}

// Two data blocks that gnuplot selects by name: index 'step', index 'feature_change'.
void write_tsv(const MeshMeasures& m, const FrameSet& pred, const EvalOptions& opt, bool force) {
  std::ostringstream out;
  if (!pred.step.empty()) {
    out << "# step: frames error relative_error\n";
    for (const auto& [st, v] : m.totals.by_step)
      out << fmt::format("{} {} {:.9g} {:.9g}\n", st, v.second, v.first / v.second,
                         v.first / v.second / m.pm.diag);
  } else {
    out << "# frame: pred_frame truth_frame error relative_error\n";
    for (std::size_t k = 0; k < m.pm.results.size(); ++k)
      out << fmt::format("{} {} {:.9g} {:.9g}\n", m.pairs[k].first, m.pairs[k].second,
                         m.pm.results[k].error, m.pm.results[k].error / m.pm.diag);
  }
  out << fmt::format("\n\n# feature_change: index change (frames index and index + {})\n",
                     opt.change_span);
  for (std::size_t k = 0; k < m.change.by_index.size(); ++k)
    out << fmt::format("{} {:.9g}\n", k, m.change.by_index[k]);
  write_text_output(opt.tsv, out.str(), force, {opt.pred, opt.truth});
}

// The human table.
std::string table(const MeshMeasures& m, const nlohmann::ordered_json& js, const FrameSet& pred,
                  const EvalOptions& opt) {
  const auto& tt = m.totals;
  const double np = static_cast<double>(tt.counted), diag = m.pm.diag;
  std::string t = fmt::format(
      "{}{}\n", opt.pred,
      m.has_truth
          ? fmt::format(
                " vs {} ({} frame pairs{}{})", opt.truth, m.pm.results.size(),
                tt.skip_given ? fmt::format("; totals over the {} generated frames", tt.counted)
                              : "",
                opt.align == "rigid" ? "; each part aligned by a rotation and translation" : "")
          : "");
  if (m.has_truth) {
    t += fmt::format("  {:<28} {:.6g}  ({:.4g} x bbox diagonal {:.4g})\n",
                     "per-vertex position error", tt.err / np, tt.err / np / diag, diag);
    t += fmt::format("  {:<28} {:.6g}\n", "E_rms x 1000 (unit ball)", js["erms"].get<double>());
    t += fmt::format("  {:<28} spatial {:.6g}", "STED", js["sted"]["spatial"].get<double>());
    if (m.pm.sted_t_n)
      t += fmt::format("  temporal {:.6g}  combined {:.6g}", js["sted"]["temporal"].get<double>(),
                       js["sted"]["combined"].get<double>());
    t += "\n";
    if (tt.rse_n)
      t += fmt::format("  {:<28} max {:.6g}  mean {:.6g}\n", "relative squared error", tt.rse_max,
                       tt.rse_mean / static_cast<double>(tt.rse_n));
  }
  if (m.change.n)
    t += fmt::format("  {:<28} mean {:.6g}  min {:.6g}  max {:.6g} (over time indices)\n",
                     opt.change_span == 1 ? std::string("feature change")
                                          : fmt::format("feature change, span {}", opt.change_span),
                     js["feature_change"]["mean"].get<double>(),
                     js["feature_change"]["min"].get<double>(),
                     js["feature_change"]["max"].get<double>());
  if (m.spread_n)
    t += fmt::format("  {:<28} {:.6g}  ({:.4g} x bbox diagonal; {} cases)\n", "spread of samples",
                     js["sample_spread"]["mean"].get<double>(),
                     js["sample_spread"]["mean_relative"].get<double>(), m.spread_cases);
  if (js.contains("pace"))
    t += fmt::format(
        "  {:<28} {:.4g} per frame, the data {:.4g} (x bbox diagonal), over the first {} predicted "
        "frames of {} cases: ratio {:.3f}\n",
        "pace", js["pace"]["predicted_per_frame_relative"].get<double>(),
        js["pace"]["true_per_frame_relative"].get<double>(), kPaceSteps, m.pace.size(),
        js["pace"]["ratio"].get<double>());
  const auto& v = m.samples;
  if (v.cases)
    t += fmt::format(
        "  {:<28} mean of K {:.6g}  best of K {:.6g}  worst of K {:.6g}  (x bbox diagonal {:.4g} / "
        "{:.4g} / {:.4g}; {} cases)\n",
        "error per sample", v.mean, v.best, v.worst, v.mean / diag, v.best / diag, v.worst / diag,
        v.cases);
  const auto shown = [&](std::size_t n, int key) {
    return opt.steps.empty()
               ? n <= 40 || key % 5 == 0
               : std::find(opt.steps.begin(), opt.steps.end(), key) != opt.steps.end();
  };
  if (m.has_truth && !pred.step.empty() && tt.by_step.size() > 1) {
    t += fmt::format("  {:>6} {:>7} {:>14} {:>14}\n", "step", "frames", "error", "x diagonal");
    for (const auto& [s, val] : tt.by_step)
      if (shown(tt.by_step.size(), s))
        t += fmt::format("  {:>6} {:>7} {:>14.6g} {:>14.6g}\n", s, val.second,
                         val.first / val.second, val.first / val.second / diag);
  } else if (m.has_truth && pred.step.empty() && m.pm.results.size() > 1) {
    // Frames without steps (a reconstruction, a file of meshes): each pair's own row, numbered
    // in each file (the truth's frame is the data frame).
    t += fmt::format("  {:>10} {:>11} {:>14} {:>14}\n", "pred frame", "truth frame", "error",
                     "x diagonal");
    for (std::size_t k = 0; k < m.pm.results.size(); ++k)
      if (shown(m.pm.results.size(), static_cast<int>(m.pairs[k].first)))
        t += fmt::format("  {:>10} {:>11} {:>14.6g} {:>14.6g}\n", m.pairs[k].first,
                         m.pairs[k].second, m.pm.results[k].error, m.pm.results[k].error / diag);
  }
  return t;
}

// eval-metrics on mesh files: PRED alone (feature change, samples' spread) or against TRUTH.
void eval_meshes(const EvalOptions& opt, bool force) {
  FrameSet pred = read_frame_set(opt.pred);
  const SequenceShape sh = shape_of(pred);
  MeshMeasures m;
  m.change = feature_change_of(pred, opt.change_span);
  std::optional<FrameSet> truth;
  if (!opt.truth.empty()) {
    truth = read_frame_set(opt.truth);
    m.has_truth = true;
    m.pairs = pair_frames(pred, *truth);
    m.pm = measure_pairs(pred, *truth, sh, m.pairs,
                         {opt.sted_rings, opt.sted_dt,
                          opt.align == "rigid" ? Alignment::rigid : Alignment::translation});
  }
  const SampleGroups groups = sample_groups(pred);
  std::tie(m.spread, m.spread_n) = sample_spread(pred, groups, sh);
  m.spread_cases = groups.size();
  const auto& T = truth ? truth->tmpl.vertices : pred.tmpl.vertices;
  m.spread_diag = (T.colwise().maxCoeff() - T.colwise().minCoeff()).norm();
  m.totals = totals_of(pred, m.pairs, m.pm.results);
  if (truth && m.totals.counted == 0)
    throw InvalidInput("no generated frame has a ground-truth frame to compare with", opt.pred);
  if (truth) m.samples = samples_vs_truth(pred, groups, m.pairs, m.pm.results, m.totals.skip_given);
  if (truth) m.pace = pace_of(pred, *truth);

  const nlohmann::ordered_json js = to_json(m, pred, opt);
  if (!opt.json.empty() && opt.json != "-")
    write_text_output(opt.json, js.dump(2) + "\n", force, {opt.pred, opt.truth});
  if (!opt.tsv.empty()) write_tsv(m, pred, opt, force);
  if (opt.json == "-")
    std::cout << js.dump(2) << "\n";
  else
    std::cout << table(m, js, pred, opt) << std::flush;
}

}  // namespace

void eval_metrics(const EvalOptions& opt, const CommonOptions& common) {
  check_options(opt);
  const auto claims = claim_outputs({opt.json, opt.tsv}, common.force, {opt.pred, opt.truth});
  const std::string kind =
      io::is_hdf5_path(opt.pred)
          ? io::declared_kind(h5::File(opt.pred, h5::File::Mode::read, opt.pred))
          : std::string();
  if (kind == "skeleton") return eval_skeletons(opt, common.force);
  if (!opt.recogniser.empty())
    throw UsageError("--recogniser measures skeleton files (generated actions against real ones)");
  if (kind == "components") {
    if (opt.truth.empty())
      throw UsageError("a components file is measured against TRUTH's planted regions");
    return eval_components(opt.pred, opt.truth, opt.json, opt.support_threshold, common.force);
  }
  eval_meshes(opt, common.force);
}

}  // namespace df::apps
