// libFuzzer target: the mesh readers on one file format (DF_FUZZ_EXT = ".obj", ".ply" or
// ".off", set per target by CMake). read_mesh on the bytes; for OBJ also the fast frame reader
// against a fixed reference (a unit square of two triangles), as obj2acap reads frames 2..N.
#include "core/error.h"
#include "fuzz_common.h"
#include "io/mesh_io.h"

namespace {
const df::Mesh& square() {
  static const df::Mesh m = [] {
    df::Mesh s;
    s.vertices.resize(4, 3);
    s.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    s.faces.resize(2, 3);
    s.faces << 0, 1, 2, 0, 2, 3;
    return s;
  }();
  return m;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string path = df::fuzz::write_scratch(std::string("input") + DF_FUZZ_EXT, data, size);
  try {
    df::io::MeshReadReport report;
    df::io::read_mesh(path, &report);
  } catch (const df::Error&) {
  }
  if (std::string(DF_FUZZ_EXT) == ".obj") {
    try {
      df::io::read_obj_frame(path, square(), "square.obj");
    } catch (const df::Error&) {
    }
  }
  return 0;
}
