#include "apps/inspect_actgan.h"

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/skeleton_file.h"

namespace df::apps {
using namespace df::models;

namespace {

nlohmann::ordered_json to_json(const PoseError& e) {
  return {{"rms", e.rms}, {"joint_distance", e.joint_distance}};
}

nlohmann::ordered_json reach_json(const DecoderReach& d, const ActganInspectOptions& opt) {
  nlohmann::ordered_json js;
  js["model"] = opt.model;
  js["input"] = opt.input;
  js["part"] = d.part;
  if (!opt.subjects.empty()) js["subjects"] = opt.subjects;
  js["poses"] = d.poses;
  js["reference_poses"] = d.training_poses;
  js["steps"] = opt.steps;
  js["decoder"] = {{"fitted", to_json(d.fitted)}, {"start", to_json(d.start)}};
  js["mean_pose"] = to_json(d.mean_pose);
  js["nearest_pose"] = to_json(d.nearest);
  js["nearest_pose"]["without_reference"] = d.without_reference;
  js["by_class"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < d.classes.size(); ++k)
    js["by_class"].push_back({{"class", d.classes[k]},
                              {"poses", d.poses_by_class[k]},
                              {"fitted", to_json(d.fitted_by_class[k])},
                              {"nearest_pose", to_json(d.nearest_by_class[k])}});
  return js;
}

std::string reach_table(const DecoderReach& d, const ActganInspectOptions& opt) {
  std::string out = fmt::format(
      "{} poses of {} ({} part; references: {} poses{}), latent codes fitted in {} steps\n"
      "{:<34} {:>10} {:>16}\n",
      d.poses, opt.input, d.part, d.training_poses,
      d.part == "all" ? " of other sequences" : " of the training part", opt.steps, "", "RMS",
      "joint distance");
  auto line = [&](const std::string& what, const PoseError& e) {
    out += fmt::format("{:<34} {:>10.4g} {:>16.4g}\n", what, e.rms, e.joint_distance);
  };
  line("decoder, fitted codes Dec(h*, y)", d.fitted);
  line("decoder at h = 0", d.start);
  line("nearest pose of the class", d.nearest);
  line("mean pose", d.mean_pose);
  if (d.without_reference)
    out += fmt::format("({} poses have no pose of their class in another sequence: counted at 0)\n",
                       d.without_reference);
  out += "per class, RMS: fitted / nearest pose\n";
  for (std::size_t k = 0; k < d.classes.size(); ++k)
    out += fmt::format("  {:<32} {:>10.4g} / {:.4g}\n", d.classes[k], d.fitted_by_class[k].rms,
                       d.nearest_by_class[k].rms);
  return out;
}

}  // namespace

void inspect_actgan(const ActganInspectOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.json}, common.force, {opt.model, opt.input});
  if (opt.steps < 0) throw UsageError("--steps must not be negative");
  if (!(opt.lr > 0)) throw UsageError("--lr must be positive");
  const ActganModel m = load_actgan_model(opt.model);
  const io::SkeletonFile s = io::read_skeleton_file(opt.input);
  const DecoderReach d = decoder_reach(m, s, opt);
  const nlohmann::ordered_json js = reach_json(d, opt);
  if (opt.json == "-") {
    std::cout << js.dump(2) << "\n";
    return;
  }
  std::cout << reach_table(d, opt) << std::flush;
  if (!opt.json.empty())
    write_text_output(opt.json, js.dump(2) + "\n", common.force, {opt.model, opt.input});
}

}  // namespace df::apps
