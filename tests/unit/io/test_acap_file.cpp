// The ACAP file kind's owner: what AcapWriter writes, AcapReader reads back (and the schema
// accepts), and ModelData's three ways to the model's normalization.
#include <catch2/catch.hpp>
#include <cmath>

#include "helpers.h"
#include "io/acap_file.h"
#include "models/common/model_data.h"

using namespace df;
using df::test::error_message;
using df::test::TempDir;

namespace {

Mesh triangle() {
  Mesh m;
  m.vertices.resize(3, 3);
  m.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  m.faces.resize(1, 3);
  m.faces << 0, 1, 2;
  return m;
}

FeatureNormalization numbers(double lo, double hi) {
  FeatureNormalization nz;
  nz.min.fill(lo);
  nz.max.fill(hi);
  return nz;
}

// Two frames of a triangle: raw features 0.1 (k + 1) for value k, normalized with `nz`;
// `with_raw` false leaves the raw ones out.
void write_file(const std::string& path, const FeatureNormalization& nz, bool with_raw) {
  io::AcapWriter w(path, path, {"made by the test"});
  w.write_template(triangle());
  w.write_normalization(nz);
  w.write_frame_names({"a", "b"});
  w.write_sequences({0, 2}, {"walk"});
  w.write_labels({0}, {"walking"});
  std::vector<double> raw(2 * 27);
  std::vector<float> normalized(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    raw[k] = 0.1 * static_cast<double>(k % 9 + 1);
    normalized[k] = static_cast<float>(nz.normalize(static_cast<int>(k % 9), raw[k]));
  }
  if (with_raw) {
    w.create_raw(2, 3);
    w.write_raw_rows(0, 2, raw.data());
  }
  w.write_normalized(2, 3, normalized.data());
  std::vector<float> positions(2 * 9, 0.5f);
  w.write_positions(2, 3, positions.data());
  w.close();
}

}  // namespace

TEST_CASE("ACAP file: written by AcapWriter, read back by AcapReader", "[io]") {
  TempDir dir;
  const auto nz = numbers(-1, 2);
  write_file(dir / "a.h5", nz, true);
  const io::AcapReader r(dir / "a.h5");
  CHECK(r.frames() == 2);
  CHECK(r.vertices() == 3);
  CHECK(r.read_template().faces == triangle().faces);
  CHECK(r.frame_names() == std::vector<std::string>{"a", "b"});
  CHECK(r.offsets() == std::vector<std::int64_t>{0, 2});
  CHECK(r.sequence_labels() == std::vector<std::string>{"walking"});
  CHECK(r.has_raw());
  CHECK(r.has_positions());
  CHECK(!r.has_source());
  CHECK(r.normalization().same_numbers(nz));
  CHECK(r.history().find("made by the test") != std::string::npos);
  std::vector<double> raw(27);
  r.read_raw(1, 1, raw.data());
  CHECK(raw[4] == Approx(0.5));
}

TEST_CASE("ACAP file: raw features from /features/raw, else from the normalized ones", "[io]") {
  TempDir dir;
  const auto nz = numbers(-1, 2);
  write_file(dir / "a.h5", nz, true);
  write_file(dir / "no-raw.h5", nz, false);
  std::vector<double> stored(27), undone(27);
  io::AcapReader(dir / "a.h5").read_features(1, 1, stored.data());
  io::AcapReader(dir / "no-raw.h5").read_features(1, 1, undone.data());
  for (std::size_t k = 0; k < 27; ++k) {
    CHECK(stored[k] == 0.1 * static_cast<double>(k % 9 + 1));  // as written
    CHECK(undone[k] == Approx(stored[k]).epsilon(1e-6));       // through float
  }
  {  // positions only
    io::AcapWriter w(dir / "p.h5", dir / "p.h5", {});
    w.write_template(triangle());
    w.write_frame_names({"a"});
    w.write_sequences({0, 1}, {"s"});
    std::vector<float> positions(9, 0.5f);
    w.write_positions(1, 3, positions.data());
    w.close();
  }
  CHECK(error_message([&] {
          io::AcapReader(dir / "p.h5").read_features(0, 1, stored.data());
        }).find("run obj2acap") != std::string::npos);
}

TEST_CASE("model data: the model's normalization from stored, raw or renormalized features",
          "[io]") {
  TempDir dir;
  const auto file_nz = numbers(-1, 2), model_nz = numbers(0, 1);
  write_file(dir / "a.h5", file_nz, true);
  write_file(dir / "no-raw.h5", file_nz, false);
  const models::ModelData same(dir / "a.h5", triangle());
  // the same numbers: the stored values as they are
  const auto x = same.all_features(file_nz);
  CHECK(x(1, 4) == static_cast<float>(file_nz.normalize(4, 0.5)));
  // other numbers: the raw features normalized with them
  const auto y = same.features({1}, model_nz);
  CHECK(y.rows() == 1);
  CHECK(y(0, 4) == static_cast<float>(model_nz.normalize(4, 0.5)));
  // no raw features: through the file's own numbers (float rounding on the way)
  const auto z = models::ModelData(dir / "no-raw.h5", triangle()).features({0, 1}, model_nz);
  CHECK(z(1, 4) == Approx(model_nz.normalize(4, 0.5)).margin(1e-6));
  CHECK(z(0, 7) == Approx(model_nz.normalize(7, 0.8)).margin(1e-6));

  // the same counts, other triangles: the message says which triangle differs, not two equal counts
  Mesh other = triangle();
  other.faces << 0, 2, 1;
  CHECK(error_message([&] { models::ModelData(dir / "a.h5", other); })
            .find("has another template than the model: the same 3 vertices and 1 triangles, but "
                  "triangle 0 joins vertices (0 1 2) here and (0 2 1) in the model (counting from "
                  "0): the two must share the "
                  "template") == 0);
  Mesh bigger = triangle();
  bigger.vertices.conservativeResize(4, 3);
  bigger.vertices.row(3) << 1, 1, 0;
  CHECK(
      error_message([&] {
        models::ModelData(dir / "a.h5", bigger);
      }).find("has another template than the model (3 vertices, 1 triangles; the model's: 4, 1)") ==
      0);
}
