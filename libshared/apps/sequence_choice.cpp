#include "apps/sequence_choice.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "core/error.h"

namespace df::apps {

std::size_t sequence_index(const std::string& wanted, const std::vector<std::string>& names,
                           const std::string& path) {
  const auto it = std::find(names.begin(), names.end(), wanted);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  if (!wanted.empty() && wanted.size() < 10 &&
      wanted.find_first_not_of("0123456789") == std::string::npos &&
      std::stoul(wanted) < names.size())
    return std::stoul(wanted);
  throw UsageError(
      fmt::format("no sequence '{}' in {} (it has {} sequences{}{})", wanted, path, names.size(),
                  names.size() <= 12 ? ": " : "",
                  names.size() <= 12 ? fmt::format("{}", fmt::join(names, ", ")) : ""));
}

}  // namespace df::apps
