// Mesh I/O on the real research data of ../shared/data (label shared-data): every frame of each
// set reads with the documented vertex/face counts and one connectivity.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>

#include "io/frame_list.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;

namespace {
std::string data_dir(const std::string& set) {
  const char* root = std::getenv("DF_SHARED_DATA");
  REQUIRE(root != nullptr);
  fs::path p = fs::path(root) / set / set;
  REQUIRE(fs::is_directory(p));
  return p.string();
}

struct Expect {
  const char* set;
  std::size_t frames, vertices, triangles;
};

void check_set(const Expect& e, const std::string& input) {
  auto frames = df::io::expand_frames(input);
  REQUIRE(frames.size() == e.frames);
  df::io::MeshReadReport rep;
  auto ref = df::io::read_mesh(frames[0].path, &rep);
  CHECK(static_cast<std::size_t>(ref.vertices.rows()) == e.vertices);
  CHECK(static_cast<std::size_t>(ref.faces.rows()) == e.triangles);
  for (std::size_t i = 1; i < frames.size(); ++i) {
    auto m = df::io::read_mesh(frames[i].path);
    REQUIRE_NOTHROW(df::io::check_same_connectivity(ref, frames[0].name, m, frames[i].name));
  }
}
}  // namespace

TEST_CASE("real data: pcow, 204 OBJ frames in natural order", "[shared-data]") {
  auto frames = df::io::expand_frames(data_dir("pcow"));
  CHECK(frames[0].name == "1");
  CHECK(frames[9].name == "10");
  CHECK(frames.back().name == "204");
  check_set({"pcow", 204, 2904, 5804}, data_dir("pcow"));
}

TEST_CASE("real data: chickenCrossing, 400 OBJ frames", "[shared-data]") {
  check_set({"chickenCrossing", 400, 3030, 5664}, data_dir("chickenCrossing"));
}

TEST_CASE("real data: cactus, 19 ASCII PLY frames", "[shared-data]") {
  check_set({"cactus", 19, 5261, 10518}, data_dir("cactus"));
}

TEST_CASE("real data: cat and lion poses", "[shared-data]") {
  check_set({"cat-poses", 9, 7207, 14410}, data_dir("cat-poses"));
  check_set({"lion-poses", 9, 5000, 9996}, data_dir("lion-poses"));
}

TEST_CASE("real data: lowpoly_cat mixes triangles and quads (fan-triangulated)", "[shared-data]") {
  // 170 triangles + 312 quads per frame = 794 triangles; 36 frames + the reference.
  check_set({"lowpoly_cat", 37, 398, 794}, data_dir("lowpoly_cat"));
  df::io::MeshReadReport rep;
  df::io::read_mesh(data_dir("lowpoly_cat") + "/cat_000001.obj", &rep);
  CHECK(rep.polygons_triangulated == 312);
}
