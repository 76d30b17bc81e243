// libFuzzer target: the .npz archive reader (zip directory, stored and deflated members, zip64
// records, every member parsed as a .npy), as skel2h5 reads joint arrays.
#include <string_view>

#include "core/error.h"
#include "io/npz_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    df::io::parse_npz(std::string_view(reinterpret_cast<const char*>(data), size), "input.npz");
  } catch (const df::Error&) {
  }
  return 0;
}
