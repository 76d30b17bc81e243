// libFuzzer target: the MD2 keyframe-model reader (header offsets, counts, frame names).
#include "core/error.h"
#include "fuzz_common.h"
#include "io/md2.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string path = df::fuzz::write_scratch("input.md2", data, size);
  try {
    df::io::read_md2(path);
  } catch (const df::Error&) {
  }
  return 0;
}
