// What `h5check` does: validate files against the schema they declare and summarise them.
#pragma once

#include <string>
#include <vector>

namespace df::io {

struct InspectOptions {
  bool structure_only = false;  ///< skip reading the data (no NaN/index/offset checks)
  bool show_history = true;
  std::string expected_kind;  ///< require this kind ("" = any)
};

/// Validates each file and prints a summary per file on stdout (kind, dimensions, datasets
/// with shape/type/compression, history). Invalid files are reported on stderr as
/// `h5check: error: ...` and checking continues. Returns the number of invalid files.
int inspect_files(const std::vector<std::string>& files, const InspectOptions& opt);

}  // namespace df::io
