// The options every tool shares, as the library sees them (core/tool.h declares them on the
// command line): library code takes a CommonOptions without compiling CLI11.
#pragma once

#include <cstdint>

namespace df {

/// Options every tool shares (samtools' global options): declared once, same everywhere.
struct CommonOptions {
  int threads = 0;         ///< 0 = all cores
  std::uint64_t seed = 0;  ///< only for tools that draw random numbers
  bool quiet = false;
  bool verbose = false;
  bool force = false;  ///< overwrite an existing output
};

}  // namespace df
