// libFuzzer target: the .npy array reader (header dictionary, versions, dtypes, shapes, Fortran
// order), as skel2h5 reads joint arrays.
#include <string_view>

#include "core/error.h"
#include "io/npy_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    df::io::parse_npy(std::string_view(reinterpret_cast<const char*>(data), size), "input.npy");
  } catch (const df::Error&) {
  }
  return 0;
}
