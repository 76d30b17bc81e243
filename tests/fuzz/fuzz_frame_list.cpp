// libFuzzer target: @LIST frame-list files (one path per line, comments, blank lines, relative
// paths), expanded beside two real mesh files and a directory of one, so that valid lines exist.
#include <filesystem>

#include "core/error.h"
#include "fuzz_common.h"
#include "io/frame_list.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool ready = [] {
    const char* tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::ofstream(df::fuzz::scratch() + "/a.obj") << tri;
    std::ofstream(df::fuzz::scratch() + "/b.obj") << tri;
    std::filesystem::create_directories(df::fuzz::scratch() + "/dir");
    std::ofstream(df::fuzz::scratch() + "/dir/c.obj") << tri;
    return true;
  }();
  (void)ready;
  std::string path = df::fuzz::write_scratch("list.txt", data, size);
  try {
    df::io::expand_frames("@" + path);
  } catch (const df::Error&) {
  }
  return 0;
}
