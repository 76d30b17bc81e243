// The root attributes of every deformflow HDF5 output: schema, schema_version, tool,
// tool_version and history (this run first, then the inputs' histories).
#pragma once

#include <string>
#include <vector>

#include "io/h5.h"

namespace df::io {

/// Writes the common root attributes of an output of `kind`; `inherited` are the history
/// attributes of the inputs, in input order.
void write_header(h5::File& f, const std::string& kind,
                  const std::vector<std::string>& inherited = {});

/// The history attribute of a file ("" if it has none).
std::string read_history(const h5::File& f);

}  // namespace df::io
