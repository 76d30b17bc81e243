// How well extracted deformation components localize planted regions (synth-meshseq --kind
// bumps writes the regions as /synthetic): for each region, the best-matching kept component at
// the level of the region's scale (coarse regions → level 0, fine → level 1), scored by the IoU
// of supports. A component's support is the set of vertices where its deformation ‖(X − X_r)_i‖
// reaches `threshold` × its maximum (default 0.1: a bump h(1 − d²)² deforms the whole disc above
// 10 % of its peak slope except a sliver at the centre and rim); a region's support is its disc.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "models/msae/components.h"

namespace df::apps {

struct RegionMatch {
  int region = 0, scale = 0;  ///< scale 0 coarse, 1 fine
  int level = 0;              ///< the level searched
  int component = -1;         ///< index within the level (-1: no kept component there)
  int block = -1;
  std::string name;  ///< as the components' acap file names it (L<level>.<block>.<k>)
  double iou = 0;
  int region_size = 0, support_size = 0;
};

/// @param regions  [R][V] 0/1 masks; @param scales  [R]
std::vector<RegionMatch> localization_scores(const models::Components& c,
                                             const std::vector<std::vector<std::uint8_t>>& regions,
                                             const std::vector<int>& scales,
                                             double threshold = 0.1);

/// eval-metrics COMPONENTS TRUTH: prints the table (and JSON) of localization_scores against
/// TRUTH's /synthetic regions; `force` lets the JSON file replace an existing one.
void eval_components(const std::string& components, const std::string& truth,
                     const std::string& json, double threshold, bool force);

}  // namespace df::apps
