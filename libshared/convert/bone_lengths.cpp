#include "convert/bone_lengths.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/log.h"

namespace df::convert {
namespace {

bool untracked(const float* p) {
  return p[0] == 0 && p[1] == 0 && p[2] == 0;
}

// The p-quantile of sorted values, linear between neighbours.
double quantile(const std::vector<double>& sorted, double p) {
  const double k = p * static_cast<double>(sorted.size() - 1);
  const auto i = static_cast<std::size_t>(k);
  const std::size_t next = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (sorted[next] - sorted[i]) * (k - static_cast<double>(i));
}

}  // namespace

std::vector<BoneSpread> bone_length_spread(const RawSkeletonCollection& c) {
  const std::size_t J = c.joints(), fs = J * 3;
  std::vector<BoneSpread> bones;
  for (std::size_t j = 0; j < J; ++j) {
    const int parent = c.parents[j];
    if (parent < 0) continue;
    BoneSpread b;
    b.joint = static_cast<int>(j);
    b.parent = parent;
    b.name = c.joint_names[static_cast<std::size_t>(parent)] + "-" + c.joint_names[j];
    std::vector<double> spreads, lengths;
    double total = 0;
    std::size_t counted = 0;
    for (const auto& s : c.sequences) {
      lengths.clear();
      for (std::size_t t = 0; t * fs < s.poses.size(); ++t) {
        const float* a = s.poses.data() + t * fs + j * 3;
        const float* q = s.poses.data() + t * fs + static_cast<std::size_t>(parent) * 3;
        if (untracked(a) || untracked(q)) continue;
        lengths.push_back(
            std::hypot(double(a[0]) - q[0], double(a[1]) - q[1], double(a[2]) - q[2]));
      }
      if (lengths.size() < 2) continue;
      for (double l : lengths) total += l;
      counted += lengths.size();
      std::sort(lengths.begin(), lengths.end());
      const double mid = quantile(lengths, 0.5);
      const double spread =
          mid > 0 ? (quantile(lengths, 0.75) - quantile(lengths, 0.25)) / 1.349 / mid : 0;
      spreads.push_back(spread);
      if (spread > b.worst || b.worst_sequence.empty()) {
        b.worst = spread;
        b.worst_sequence = s.name;
      }
    }
    if (spreads.empty()) continue;
    std::sort(spreads.begin(), spreads.end());
    b.typical = quantile(spreads, 0.75);
    b.mean_length = total / static_cast<double>(counted);
    bones.push_back(std::move(b));
  }
  std::stable_sort(bones.begin(), bones.end(),
                   [](const BoneSpread& x, const BoneSpread& y) { return x.typical > y.typical; });
  return bones;
}

void check_bone_lengths(const RawSkeletonCollection& c, double tolerance, bool strict,
                        const std::string& source) {
  const auto bones = bone_length_spread(c);
  if (bones.empty()) return;
  for (const auto& b : bones)
    log::debug(
        "bone {}: length {:.4g}, spread {:.3f} (a quarter of the recordings reach it), worst "
        "{:.3f} in {}",
        b.name, b.mean_length, b.typical, b.worst, b.worst_sequence);
  std::vector<std::string> over;
  for (const auto& b : bones)
    if (b.typical > tolerance && over.size() < 5)
      over.push_back(fmt::format("{} {:.2f}", b.name, b.typical));
  if (over.empty()) {
    log::debug(
        "bone lengths: the most variable bone is {} (spread {:.3f} of its length in a quarter of "
        "the {} recordings; --bone-tolerance {})",
        bones.front().name, bones.front().typical, c.sequences.size(), tolerance);
    return;
  }
  const std::size_t n_over = static_cast<std::size_t>(std::count_if(
      bones.begin(), bones.end(), [&](const BoneSpread& b) { return b.typical > tolerance; }));
  const std::string message = fmt::format(
      "{} of {} bones change length within a recording by more than --bone-tolerance {} of their "
      "length ({}{}): is the joint order right for this format?",
      n_over, bones.size(), tolerance, fmt::join(over, ", "), n_over > over.size() ? ", ..." : "");
  if (strict) throw InvalidInput(message, source);
  log::warn("{} ({}; --strict makes this an error)", message, source);
}

}  // namespace df::convert
