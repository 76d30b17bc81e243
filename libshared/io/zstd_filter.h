// The zstd compression filter for HDF5 under its registered id 32015 (cd_values[0] = level),
// byte-compatible with the community plugin: each chunk is one zstd frame with its content
// size. The same code is registered in-process (register_zstd_filter) and built as the plugin
// `libh5zstd.so` (zstd_plugin.cpp) for h5dump, h5diff and h5py via HDF5_PLUGIN_PATH.
#pragma once

#include <hdf5.h>

namespace df::h5 {

inline constexpr H5Z_filter_t kZstdFilterId = 32015;

/// The filter's class description (also what the plugin hands to HDF5).
const H5Z_class2_t* zstd_filter_class();

/// Registers the filter with the HDF5 library of this process (idempotent).
void register_zstd_filter();

}  // namespace df::h5
