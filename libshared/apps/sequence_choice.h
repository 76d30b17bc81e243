// --sequence as the tools take it (render-mesh, export-gltf): a sequence of a file by its name,
// or by its index when no sequence has that name.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace df::apps {

/// The index of sequence `wanted` among `names` (a name, else a decimal index); UsageError
/// naming `path` and listing the names (up to 12) when there is none.
std::size_t sequence_index(const std::string& wanted, const std::vector<std::string>& names,
                           const std::string& path);

}  // namespace df::apps
