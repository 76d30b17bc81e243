// HDF5 dynamic-plugin entry points for the zstd filter (id 32015). Built as libh5zstd.so in
// <build>/hdf5-plugins; `HDF5_PLUGIN_PATH=<build>/hdf5-plugins h5dump file.h5` then reads
// our compressed datasets.
#include <H5PLextern.h>

#include "io/zstd_filter.h"

extern "C" {
__attribute__((visibility("default"))) H5PL_type_t H5PLget_plugin_type(void) {
  return H5PL_TYPE_FILTER;
}
__attribute__((visibility("default"))) const void* H5PLget_plugin_info(void) {
  return df::h5::zstd_filter_class();
}
}
