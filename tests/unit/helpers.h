// Small fixtures shared by the unit tests (pmp's tests/helpers.h idea).
#pragma once

#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "geometry/mesh_topology.h"
#include "io/mesh_io.h"

namespace df::test {

/// A fresh directory removed at scope exit.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "deformflow-test-XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// The one-line message (`WHAT (WHERE)`) of the df::Error that f throws, or "no error".
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const df::Error& e) {
    return e.message();
  }
  return "no error";
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Regular tetrahedron-like closed mesh: 4 vertices, 4 outward triangles.
inline Mesh tetrahedron() {
  Mesh m;
  m.vertices.resize(4, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.faces.resize(4, 3);
  m.faces << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  return m;
}

/// The edges of a 3 × 3 vertex grid of 8 triangles: a mesh small enough for finite differences of
/// every weight of a network on it.
inline std::vector<std::array<int, 2>> grid3x3_edges() {
  Faces f(8, 3);
  f << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7;
  return geometry::mesh_topology(f, 9).edges;
}

}  // namespace df::test
