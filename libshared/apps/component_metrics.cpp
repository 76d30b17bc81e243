#include "apps/component_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "io/acap_file.h"

namespace df::apps {

std::vector<RegionMatch> localization_scores(const models::Components& c,
                                             const std::vector<std::vector<std::uint8_t>>& regions,
                                             const std::vector<int>& scales, double threshold) {
  const auto ref = geometry::identity_features(&c.normalization);
  const auto V = static_cast<std::size_t>(c.tmpl.vertices.rows());
  std::vector<RegionMatch> out;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    RegionMatch m;
    m.region = static_cast<int>(r);
    m.scale = scales[r];
    m.level = std::min(scales[r], static_cast<int>(c.levels.size()) - 1);
    for (auto v : regions[r]) m.region_size += v;
    const auto& L = c.levels[static_cast<std::size_t>(m.level)];
    for (Eigen::Index k = 0; k < L.features.rows(); ++k) {
      if (!L.kept[static_cast<std::size_t>(k)]) continue;
      const auto mag =
          models::deformation_per_vertex(L.features.row(k).data(), static_cast<int>(V), ref);
      const double top = *std::max_element(mag.begin(), mag.end());
      int inter = 0, uni = 0, support = 0;
      for (std::size_t i = 0; i < V; ++i) {
        const bool in_c = top > 0 && mag[i] >= threshold * top, in_r = regions[r][i] != 0;
        inter += in_c && in_r;
        uni += in_c || in_r;
        support += in_c;
      }
      const double iou = uni ? static_cast<double>(inter) / uni : 0.0;
      if (m.component < 0 || iou > m.iou) {
        m.component = static_cast<int>(k);
        m.block = L.block[static_cast<std::size_t>(k)];
        m.name =
            io::component_name(c, static_cast<std::size_t>(m.level), static_cast<std::size_t>(k));
        m.iou = iou;
        m.support_size = support;
      }
    }
    out.push_back(m);
  }
  return out;
}

void eval_components(const std::string& components, const std::string& truth,
                     const std::string& json, double threshold, bool force) {
  if (!(threshold > 0 && threshold < 1)) throw UsageError("--support-threshold must be in (0, 1)");
  const models::Components c = models::read_components(components);
  io::require_acap_components(c, components, "localization");
  const io::AcapReader t(truth);
  if (!t.has_regions())
    throw InvalidInput(
        "has no /synthetic/regions: localization needs planted regions (synth-meshseq --kind "
        "bumps)",
        truth);
  if (t.vertices() != static_cast<std::size_t>(c.tmpl.vertices.rows()))
    throw InvalidInput(
        fmt::format("has {} vertices, the components {}", t.vertices(), c.tmpl.vertices.rows()),
        truth);
  std::vector<std::vector<std::uint8_t>> regions;
  std::vector<std::int32_t> scale;
  t.read_regions(regions, scale);
  const auto matches =
      localization_scores(c, regions, std::vector<int>(scale.begin(), scale.end()), threshold);
  nlohmann::ordered_json js;
  js["components"] = components;
  js["truth"] = truth;
  js["support_threshold"] = threshold;
  if (json != "-") {
    fmt::print("{} vs the planted regions of {} (support: deformation >= {} x its maximum)\n",
               components, truth, threshold);
    fmt::print("region  scale   level  component  block  region  support    IoU\n");
  }
  for (const auto& m : matches) {
    if (json != "-")
      fmt::print("{:>6}  {:>6}  {:>5}  {:>9}  {:>5}  {:>6}  {:>7}  {:>5.3f}\n", m.region,
                 m.scale == 0 ? "coarse" : "fine", m.level, m.component, m.block, m.region_size,
                 m.support_size, m.iou);
    js["regions"].push_back({{"region", m.region},
                             {"scale", m.scale == 0 ? "coarse" : "fine"},
                             {"level", m.level},
                             {"component", m.component},
                             {"block", m.block},
                             {"name", m.name},
                             {"region_vertices", m.region_size},
                             {"support_vertices", m.support_size},
                             {"iou", m.iou}});
  }
  if (json.empty()) return;
  if (json == "-") {
    fmt::print("{}\n", js.dump(2));
  } else {
    write_text_output(json, js.dump(2) + "\n", force, {components, truth});
  }
}

}  // namespace df::apps
