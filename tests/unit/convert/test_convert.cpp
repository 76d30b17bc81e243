#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>

#include "convert/acap2obj.h"
#include "convert/frame_reader.h"
#include "convert/obj2acap.h"
#include "core/error.h"
#include "core/log.h"
#include "core/provenance.h"
#include "helpers.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/md2.h"
#include "io/schema.h"
#include "synth/meshseq.h"

namespace fs = std::filesystem;
using df::h5::File;

namespace {
df::CommonOptions quiet() {
  df::log::set_level(df::log::Level::warning);
  return {};
}

// Writes frames of a small bending finger as OBJ files into dir.
void write_finger(const std::string& dir, int frames, int resolution = 6) {
  fs::create_directories(dir);
  df::synth::MeshSeqParams p;
  p.frames = frames;
  p.resolution = resolution;
  p.twist_degrees = 120;
  df::synth::MeshSequenceGenerator g(p);
  for (int t = 0; t < frames; ++t)
    df::io::write_mesh(dir + "/" + std::to_string(t) + ".obj", {g.frame(t), g.rest().faces});
}

// A tiny MD2 file: 3 vertices, 1 triangle, frames "walk1" "walk2" "jump1".
void write_md2(const std::string& path) {
  const int nv = 3, frame_size = 40 + 4 * nv, nframes = 3;
  std::int32_t h[17] = {0, 8, 0, 0, frame_size, 0, nv, 0, 1, 0, nframes, 68, 68, 68, 80, 0, 0};
  std::memcpy(&h[0], "IDP2", 4);
  h[16] = 80 + frame_size * nframes;
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(h), sizeof h);
  std::uint16_t tri[6] = {0, 1, 2, 0, 0, 0};
  out.write(reinterpret_cast<const char*>(tri), sizeof tri);
  const char* names[3] = {"walk1", "walk2", "jump1"};
  for (int f = 0; f < nframes; ++f) {
    float st[6] = {0.5f, 1, 2, 10, 0, -1};  // scale, translate
    out.write(reinterpret_cast<const char*>(st), sizeof st);
    char name[16] = {};
    std::strncpy(name, names[f], 15);
    out.write(name, 16);
    unsigned char v[12] = {0, 0, 0, 0, static_cast<unsigned char>(2 + f), 0, 0, 0, 0, 4, 0, 0};
    out.write(reinterpret_cast<const char*>(v), sizeof v);
  }
}
}  // namespace

TEST_CASE("read_md2: frames decoded with scale/translate, winding flipped, animations",
          "[convert]") {
  df::test::TempDir tmp;
  write_md2(tmp / "m.md2");
  auto m = df::io::read_md2(tmp / "m.md2");
  REQUIRE(m.frames.size() == 3);
  CHECK(m.faces.row(0) == Eigen::RowVector3i(0, 2, 1));
  CHECK(m.frames[1].row(1) == Eigen::RowVector3d(10 + 0.5 * 3, 0, -1));
  REQUIRE(m.animations.size() == 2);
  CHECK(m.animations[0].name == "walk");
  CHECK(m.animations[0].count == 2);
  CHECK(m.animations[1].name == "jump");
  df::test::write_text(
      tmp / "bad.md2",
      "IDPX and more bytes to pass the header size check........................................");
  CHECK_THROWS_WITH(df::io::read_md2(tmp / "bad.md2"), Catch::Contains("not an MD2 file"));
}

TEST_CASE("FrameReader: directories, @lists and runs of files become sequences", "[convert]") {
  df::test::TempDir tmp;
  write_finger(tmp / "walk", 3);
  write_finger(tmp / "run", 2);
  df::test::write_text(tmp / "list.txt", "walk/2.obj\nwalk/0.obj\n");
  df::convert::FrameReader r(
      {tmp / "walk", "@" + (tmp / "list.txt"), tmp / "run/0.obj", tmp / "run/1.obj"});
  REQUIRE(r.sequences().size() == 3);
  CHECK(r.sequences()[0].name == "walk");
  CHECK(r.sequences()[0].count == 3);
  CHECK(r.sequences()[1].name == "list");
  CHECK(r.frame_name(3) == "2");
  CHECK(r.sequences()[2].name == "run");  // consecutive files: one sequence
  CHECK(r.sequences()[2].count == 2);
  CHECK(r.size() == 7);
  write_md2(tmp / "m.md2");
  df::convert::FrameReader md({tmp / "m.md2"});
  REQUIRE(md.sequences().size() == 2);
  CHECK(md.sequences()[1].label == "jump");
}

TEST_CASE("parse_frame_selection: ranges, open ends, errors", "[convert]") {
  using df::convert::parse_frame_selection;
  CHECK(parse_frame_selection("", 3) == std::vector<std::size_t>{0, 1, 2});
  CHECK(parse_frame_selection("5,0-1,8-", 10) == std::vector<std::size_t>{0, 1, 5, 8, 9});
  CHECK_THROWS_AS(parse_frame_selection("3-1", 10), df::UsageError);
  CHECK_THROWS_AS(parse_frame_selection("12", 10), df::UsageError);
  CHECK_THROWS_AS(parse_frame_selection("a-b", 10), df::UsageError);
}

TEST_CASE("obj2acap + acap2obj: round trip on a small bending, twisting finger", "[convert]") {
  df::test::TempDir tmp;
  write_finger(tmp / "f", 12);
  df::convert::Obj2AcapOptions o;
  o.inputs = {tmp / "f"};
  o.output = tmp / "f.h5";
  o.labels = {"twist"};
  const char* argv1[] = {"obj2acap", "f", "-o", "f.h5"};
  df::provenance::set_command_line(4, argv1);
  df::convert::obj2acap(o, quiet());
  File f(tmp / "f.h5", File::Mode::read);
  auto dims = df::io::validate(f, "acap");
  CHECK(dims.at("N") == 12);
  CHECK(f.read_strings("/classes/names") == std::vector<std::string>{"twist"});
  auto norm = f.read<float>("/features/normalized").data;
  for (float x : norm) REQUIRE(std::abs(x) <= 0.95f);
  f.close();

  df::convert::Acap2ObjOptions a;
  a.input = tmp / "f.h5";
  a.output = tmp / "back.h5";
  const char* argv2[] = {"acap2obj", "f.h5", "-o", "back.h5"};
  df::provenance::set_command_line(4, argv2);
  df::convert::acap2obj(a, quiet());
  File b(tmp / "back.h5", File::Mode::read);
  df::io::validate(b, "acap");
  auto P = b.read<float>("/frames/positions").data;
  File in(tmp / "f.h5", File::Mode::read);
  auto Q = in.read<float>("/frames/positions").data;
  double worst = 0;
  for (std::size_t k = 0; k < P.size(); ++k)
    worst = std::max(worst, static_cast<double>(std::abs(P[k] - Q[k])));
  CHECK(worst < 1e-5);  // exact solver; positions stored as float32
  // Provenance: this run first, then the input's history.
  auto history = df::provenance::history_lines(df::io::read_history(b));
  REQUIRE(history.size() == 2);
  CHECK_THAT(history[0], Catch::EndsWith("acap2obj f.h5 -o back.h5"));
  CHECK_THAT(history[1], Catch::EndsWith("obj2acap f -o f.h5"));

  // Normalized features reconstruct like raw ones (float precision).
  a.output = tmp / "meshes";
  a.features = "normalized";
  a.frames = "3-4";
  df::convert::acap2obj(a, quiet());
  CHECK(fs::exists(tmp / "meshes/3.obj"));
  CHECK(fs::exists(tmp / "meshes/4.obj"));
  CHECK(std::distance(fs::directory_iterator(tmp / "meshes"), fs::directory_iterator()) == 2);
}

TEST_CASE("obj2acap: bad input is one clear error and leaves no output", "[convert]") {
  df::test::TempDir tmp;
  write_finger(tmp / "f", 3);
  auto run = [&](std::vector<std::string> inputs) {
    df::convert::Obj2AcapOptions o;
    o.inputs = std::move(inputs);
    o.output = tmp / "out.h5";
    return df::test::error_message([&] { df::convert::obj2acap(o, quiet()); });
  };
  // A frame with different connectivity: name the frame and the first differing face.
  auto m = df::io::read_mesh(tmp / "f/2.obj");
  std::swap(m.faces(7, 0), m.faces(7, 1));
  df::io::write_mesh(tmp / "f/2.obj", m);
  CHECK_THAT(run({tmp / "f"}), Catch::Contains("first at triangle 8") && Catch::Contains("2.obj"));
  CHECK_FALSE(fs::exists(tmp / "out.h5"));
  df::test::write_text(tmp / "f/2.obj", "");
  CHECK_THAT(run({tmp / "f"}), Catch::Contains("empty file"));
  df::test::write_text(tmp / "f/2.obj", "this is not a mesh\n");
  CHECK_THAT(run({tmp / "f"}), Catch::Contains("has 0 vertices but the reference"));
  CHECK_THAT(run({tmp / "missing"}), Catch::Contains("no such file"));
  CHECK(std::distance(fs::directory_iterator(tmp.path()), fs::directory_iterator()) ==
        1);  // only f/
  df::convert::Obj2AcapOptions o;
  o.inputs = {tmp / "f/0.obj"};
  o.output = tmp / "f/0.obj";
  o.reference = "";
  CHECK_THAT(df::test::error_message([&] { df::convert::obj2acap(o, quiet()); }),
             Catch::Contains("overwrite an input"));
}

TEST_CASE("acap2obj: wrong kind, no features, NaN features, mismatched V", "[convert]") {
  df::test::TempDir tmp;
  write_finger(tmp / "f", 3);
  df::convert::Obj2AcapOptions o;
  o.inputs = {tmp / "f"};
  o.output = tmp / "ok.h5";
  df::convert::obj2acap(o, quiet());
  auto run = [&](const std::string& input) {
    df::convert::Acap2ObjOptions a;
    a.input = input;
    a.output = tmp / "out";
    return df::test::error_message([&] { df::convert::acap2obj(a, quiet()); });
  };
  {  // positions only (synth output): no features
    df::synth::MeshSeqParams p;
    p.frames = 2;
    df::synth::synth_meshseq(p, tmp / "pos.h5", "obj", quiet());
  }
  CHECK_THAT(run(tmp / "pos.h5"), Catch::Contains("has no features"));
  fs::copy_file(tmp / "ok.h5", tmp / "nan.h5");
  {
    File f(tmp / "nan.h5", File::Mode::read_write);
    std::vector<double> row(f.info("/features/raw").dims[1] * 9);
    f.read_rows<double>("/features/raw", 1, 1, row.data());
    row[40] = std::nan("");
    f.write_rows<double>("/features/raw", 1, 1, row.data());
  }
  CHECK_THAT(run(tmp / "nan.h5"), Catch::Contains("NaN") && Catch::Contains("/features/raw"));
  fs::copy_file(tmp / "ok.h5", tmp / "kind.h5");
  {
    File f(tmp / "kind.h5", File::Mode::read_write);
    f.set_attr("/", "schema", "skeleton");
  }
  CHECK_THAT(run(tmp / "kind.h5"), Catch::Contains("is a 'skeleton' file, expected a 'acap' file"));
  fs::copy_file(tmp / "ok.h5", tmp / "v.h5");
  {
    File f(tmp / "v.h5", File::Mode::read_write);
    auto V = f.read_matrix<double>("/template/vertices");
    f.write_matrix("/template/vertices", V.topRows(V.rows() - 1).eval());
  }
  CHECK_THAT(run(tmp / "v.h5"), Catch::Contains("V = "));
  CHECK_FALSE(fs::exists(tmp / "out"));
}
