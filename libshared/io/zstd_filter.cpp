#include "io/zstd_filter.h"

#include <zstd.h>

namespace df::h5 {
namespace {

// HDF5 filter callback: compresses (flags without H5Z_FLAG_REVERSE) or decompresses *buf in
// place; returns the number of valid bytes, 0 on failure. Buffers are owned by HDF5, so they
// are allocated and freed with H5allocate_memory / H5free_memory.
size_t zstd_filter(unsigned flags, size_t cd_nelmts, const unsigned cd_values[], size_t nbytes,
                   size_t* buf_size, void** buf) {
  if (flags & H5Z_FLAG_REVERSE) {
    unsigned long long size = ZSTD_getFrameContentSize(*buf, nbytes);
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN) return 0;
    void* out = H5allocate_memory(size, false);
    if (!out) return 0;
    size_t n = ZSTD_decompress(out, size, *buf, nbytes);
    if (ZSTD_isError(n) || n != size) {
      H5free_memory(out);
      return 0;
    }
    H5free_memory(*buf);
    *buf = out;
    *buf_size = size;
    return n;
  }
  int level = cd_nelmts > 0 ? static_cast<int>(cd_values[0]) : ZSTD_CLEVEL_DEFAULT;
  if (level > ZSTD_maxCLevel()) level = ZSTD_maxCLevel();
  size_t bound = ZSTD_compressBound(nbytes);
  void* out = H5allocate_memory(bound, false);
  if (!out) return 0;
  size_t n = ZSTD_compress(out, bound, *buf, nbytes, level);
  if (ZSTD_isError(n)) {
    H5free_memory(out);
    return 0;
  }
  H5free_memory(*buf);
  *buf = out;
  *buf_size = bound;
  return n;
}

const H5Z_class2_t kZstdClass = {
    H5Z_CLASS_T_VERS,
    kZstdFilterId,
    1,  // encoder present
    1,  // decoder present
    "zstd",
    nullptr,  // can_apply
    nullptr,  // set_local
    zstd_filter,
};

}  // namespace

const H5Z_class2_t* zstd_filter_class() {
  return &kZstdClass;
}

void register_zstd_filter() {
  if (H5Zfilter_avail(kZstdFilterId) <= 0) H5Zregister(&kZstdClass);
}

}  // namespace df::h5
