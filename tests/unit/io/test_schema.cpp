#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "helpers.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/schema.h"

using df::h5::File;

namespace {
// A minimal valid acap file: a tetrahedron template, N frames of positions, one sequence.
void write_valid_acap(File& f, std::size_t n = 3) {
  df::io::write_header(f, "acap");
  auto m = df::test::tetrahedron();
  f.write_matrix("/template/vertices", m.vertices);
  f.write_matrix("/template/faces", m.faces);
  df::h5::Array<float> pos{{n, 4, 3}, std::vector<float>(n * 12, 0.5f)};
  f.write("/frames/positions", pos);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n; ++i) names.push_back(std::to_string(i));
  f.write_strings("/frames/names", names);
  std::vector<std::int64_t> off{0, static_cast<std::int64_t>(n)};
  f.write<std::int64_t>("/sequences/offsets", off, {2});
  f.write_strings("/sequences/names", {"seq"});
}

std::string violation(const std::function<void(File&)>& spoil) {
  df::test::TempDir tmp;
  File f(tmp / "x.h5", File::Mode::create);
  write_valid_acap(f);
  spoil(f);
  try {
    df::io::validate(f, "acap");
  } catch (const df::InvalidInput& e) {
    return e.message();
  }
  return "valid";
}
}  // namespace

TEST_CASE("schema: embedded schemas load and a valid file passes", "[io]") {
  auto kinds = df::io::schema_kinds();
  CHECK(std::find(kinds.begin(), kinds.end(), "acap") != kinds.end());
  CHECK(std::find(kinds.begin(), kinds.end(), "skeleton") != kinds.end());
  CHECK_THROWS_WITH(df::io::schema("nonsense"), Catch::Contains("unknown file kind"));
  CHECK(violation([](File&) {}) == "valid");
  df::test::TempDir tmp;
  File f(tmp / "ok.h5", File::Mode::create);
  write_valid_acap(f, 5);
  auto dims = df::io::validate(f);
  CHECK(dims.at("N") == 5);
  CHECK(dims.at("V") == 4);
  CHECK(dims.at("F") == 4);
  CHECK(dims.at("S") == 1);
}

TEST_CASE("schema: each kind of violation is reported precisely", "[io]") {
  CHECK_THAT(violation([](File& f) { f.set_attr("/", "schema", "skeleton"); }),
             Catch::Contains("is a 'skeleton' file, expected a 'acap' file"));
  CHECK_THAT(violation([](File& f) { f.set_attr("/", "schema_version", 99); }),
             Catch::Contains("newer than this build"));
  CHECK_THAT(
      violation([](File& f) { f.write_matrix("/template/faces", Eigen::MatrixXi::Zero(0, 3)); }),
      Catch::Contains("F = 0 (triangles of the template) but at least 1 needed"));
  CHECK_THAT(
      violation([](File& f) { f.write_matrix("/template/vertices", Eigen::MatrixXd::Zero(4, 2)); }),
      Catch::Contains("axis 1 has size 2, expected 3") && Catch::Contains(":/template/vertices"));
  CHECK_THAT(
      violation([](File& f) { f.write_matrix("/template/vertices", Eigen::MatrixXf::Zero(4, 3)); }),
      Catch::Contains("has type float32, expected float64"));
  CHECK_THAT(violation([](File& f) {
               df::h5::Array<float> p{{3, 5, 3}, std::vector<float>(45, 0.f)};
               f.write("/frames/positions", p);
             }),
             Catch::Contains("implies V = 5") && Catch::Contains("/template/vertices has V = 4"));
  CHECK_THAT(violation([](File& f) {
               df::h5::Array<float> p{{3, 4}, std::vector<float>(12, 0.f)};
               f.write("/frames/positions", p);
             }),
             Catch::Contains("has rank 2"));
  CHECK_THAT(violation([](File& f) {
               df::h5::Array<float> p{{3, 4, 3}, std::vector<float>(36, 0.f)};
               p.data[2 * 12 + 1 * 3 + 2] = std::numeric_limits<float>::quiet_NaN();
               f.write("/frames/positions", p);
             }),
             Catch::Contains("NaN at index [2,1,2]"));
  CHECK_THAT(violation([](File& f) {
               Eigen::MatrixXi faces(4, 3);
               faces << 0, 2, 1, 0, 1, 3, 0, 3, 7, 1, 2, 3;
               f.write_matrix("/template/faces", faces);
             }),
             Catch::Contains("value 7 at index [2,2] is not a valid index (V = 4)"));
  CHECK_THAT(violation([](File& f) {
               std::vector<std::int64_t> off{0, 2};
               f.write<std::int64_t>("/sequences/offsets", off, {2});
             }),
             Catch::Contains("offsets end at 2 but there are N = 3 frames"));
  CHECK_THAT(violation([](File& f) { H5Ldelete(f.id(), "/frames/names", H5P_DEFAULT); }),
             Catch::Contains("missing dataset") && Catch::Contains("/frames/names"));
  CHECK_THAT(violation([](File& f) { H5Ldelete(f.id(), "/frames/positions", H5P_DEFAULT); }),
             Catch::Contains("needs at least one of /frames/positions"));
  CHECK_THAT(violation([](File& f) {
               std::vector<std::int32_t> labels{0};
               f.write<std::int32_t>("/sequences/labels", labels, {1});
             }),
             Catch::Contains("without /classes/names"));
  CHECK_THAT(violation([](File& f) {
               f.create_groups("/normalization");
               f.set_attr("/normalization", "mode", "sideways");
             }),
             Catch::Contains("attribute 'mode' is 'sideways'"));
  CHECK_THAT(violation([](File& f) { H5Adelete(f.id(), "history"); }),
             Catch::Contains("missing root attribute 'history'"));
}

TEST_CASE("schema: a file without a schema attribute is not ours", "[io]") {
  df::test::TempDir tmp;
  File f(tmp / "foreign.h5", File::Mode::create);
  f.write_matrix("/data", Eigen::MatrixXd::Zero(2, 2));
  CHECK_THROWS_WITH(df::io::validate(f), Catch::Contains("not a deformflow file"));
}

TEST_CASE("schema: skeleton kind checks parents and the coordinate count", "[io]") {
  df::test::TempDir tmp;
  File f(tmp / "s.h5", File::Mode::create);
  df::io::write_header(f, "skeleton");
  f.set_attr("/", "frame_rate", 30.0);
  df::h5::Array<float> poses{{6, 3, 3}, std::vector<float>(54, 0.1f)};
  f.write("/poses", poses);
  std::vector<std::int64_t> off{0, 2, 6};
  f.write<std::int64_t>("/sequences/offsets", off, {3});
  std::vector<std::int32_t> labels{0, 1}, parents{-1, 0, 1};
  f.write<std::int32_t>("/sequences/labels", labels, {2});
  f.write_strings("/classes/names", {"walk", "wave"});
  f.write<std::int32_t>("/skeleton/parents", parents, {3});
  f.write_strings("/skeleton/joint_names", {"hip", "spine", "head"});
  auto dims = df::io::validate(f, "skeleton");
  CHECK(dims.at("J") == 3);
  CHECK(dims.at("D") == 3);
  df::h5::Array<float> flat{{6, 3, 4}, std::vector<float>(72, 0.1f)};
  f.write("/poses", flat);
  CHECK_THROWS_WITH(df::io::validate(f),
                    Catch::Contains("D = 4") && Catch::Contains("one of 2, 3"));
}
