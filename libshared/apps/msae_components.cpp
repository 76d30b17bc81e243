#include "apps/msae_components.h"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/choice.h"
#include "core/error.h"
#include "core/log.h"
#include "io/components_file.h"
#include "models/msae/components.h"
#include "models/msae/data.h"
#include "models/msae/diagnosis.h"

namespace df::apps {
using namespace df::models;

void extract_components_tool(const ExtractOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.output, opt.acap}, common.force, {opt.model, opt.data});
  const MsaeModel m = load_msae_model(opt.model);
  const MsaeShapes train = read_msae_shapes(m, opt.data, FramePart::train);
  const auto codes = block_codes(*m.net, train.x);
  Components c = extract_components(m, codes);
  c.model = opt.model;
  write_components(opt.output, c, {opt.model, opt.data}, common.force);
  if (!opt.acap.empty())
    write_components_acap(opt.acap, c, false, {opt.model, opt.data}, common.force);
  std::size_t n = 0;
  for (const auto& L : c.levels) n += static_cast<std::size_t>(L.features.rows());
  log::info("wrote {} components in {} levels to {}{}", n, c.levels.size(), opt.output,
            opt.acap.empty() ? "" : " and " + opt.acap);
  if (!opt.report.empty()) {
    const MsaeShapes held =
        read_msae_shapes(m, opt.data, parse_choice<FramePart>(opt.report, "--report"));
    if (held.x.rows() == 0)
      throw InvalidInput(fmt::format("the model's {} part is empty", opt.report), opt.model);
    fmt::print("{}", format_diagnosis(diagnose_msae(m, c, train.x, codes, held.x), opt.report));
  }
}

void prune_components_tool(const PruneOptions& opt, const CommonOptions& common) {
  const auto claims = claim_outputs({opt.output, opt.acap, opt.json}, common.force, {opt.input});
  Components c = read_components(opt.input);
  io::require_acap_components(c, opt.input, "prune-components (eq. 7's strength)");
  prune_components(c, opt.eps1, opt.eps2);
  nlohmann::json report = {
      {"eps1", opt.eps1}, {"eps2", opt.eps2}, {"levels", nlohmann::json::array()}};
  fmt::print("level  component  block  centre  strength  kept\n");
  for (std::size_t l = 0; l < c.levels.size(); ++l) {
    const auto& L = c.levels[l];
    nlohmann::json level = {{"level", l}, {"components", nlohmann::json::array()}};
    std::size_t kept = 0;
    for (std::size_t k = 0; k < L.strength.size(); ++k) {
      fmt::print("{:>5}  {:>9}  {:>5}  {:>6}  {:>8.4f}  {}\n", l, k, L.block[k], L.center[k],
                 L.strength[k], L.kept[k] ? "yes" : "no");
      level["components"].push_back({{"block", L.block[k]},
                                     {"center", L.center[k]},
                                     {"strength", L.strength[k]},
                                     {"kept", L.kept[k] != 0}});
      kept += L.kept[k];
    }
    level["kept"] = kept;
    level["dropped"] = L.strength.size() - kept;
    fmt::print("level {}: {} kept, {} dropped (strength < {})\n", l, kept, L.strength.size() - kept,
               opt.eps2);
    report["levels"].push_back(level);
  }
  std::size_t kept = 0;
  for (const auto& L : c.levels)
    kept += static_cast<std::size_t>(std::count(L.kept.begin(), L.kept.end(), 1));
  if (!opt.acap.empty() && kept == 0)
    throw InvalidInput(
        fmt::format("no component has strength >= {}: nothing to write to {}", opt.eps2, opt.acap),
        opt.input);
  write_components(opt.output, c, {opt.input}, common.force);
  if (!opt.acap.empty()) write_components_acap(opt.acap, c, true, {opt.input}, common.force);
  if (!opt.json.empty())
    write_text_output(opt.json, report.dump(1) + "\n", common.force, {opt.input});
}

}  // namespace df::apps
