#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "helpers.h"
#include "io/mesh_io.h"

using df::Mesh;
using df::io::read_mesh;
using df::test::write_text;

TEST_CASE("read_mesh: OBJ keeps vertex order and fan-triangulates polygons", "[io]") {
  df::test::TempDir tmp;
  write_text(tmp / "q.obj",
             "# quad and pentagon\n"
             "v 0 0 0\n"
             "v 1 0 0\n"
             "v 1 1 0\n"
             "v 0 1 0\n"
             "v 2 0.5 0\n"
             "vt 0 0\n"
             "f 1/1 2/1 3/1 4/1\n"
             "f 2 5 3\n");
  df::io::MeshReadReport rep;
  Mesh m = read_mesh(tmp / "q.obj", &rep);
  REQUIRE(m.vertices.rows() == 5);
  REQUIRE(m.faces.rows() == 3);
  CHECK(m.vertices.row(4) == Eigen::RowVector3d(2, 0.5, 0));
  CHECK(m.faces.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(m.faces.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(m.faces.row(2) == Eigen::RowVector3i(1, 4, 2));
  CHECK(rep.polygons_triangulated == 1);
  CHECK(rep.nonmanifold_edges == 0);
}

TEST_CASE("read_mesh: OFF, ASCII PLY and binary PLY", "[io]") {
  df::test::TempDir tmp;
  write_text(tmp / "t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  write_text(tmp / "t.ply",
             "ply\n"
             "format ascii 1.0\n"
             "element vertex 4\n"
             "property float x\n"
             "property float y\n"
             "property float z\n"
             "element face 1\n"
             "property list uchar int vertex_indices\n"
             "end_header\n"
             "0 0 0\n"
             "1 0 0\n"
             "1 1 0\n"
             "0 1 0\n"
             "4 0 1 2 3\n");
  {
    std::ofstream b(tmp / "b.ply", std::ios::binary);
    b << "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
         "y\n"
         "property float z\n"
         "element face 1\n"
         "property list uchar int vertex_indices\n"
         "end_header\n";
    float v[9] = {0, 0, 0, 1, 0, 0, 0.25f, 1, 0};
    b.write(reinterpret_cast<const char*>(v), sizeof v);
    unsigned char n = 3;
    int idx[3] = {0, 1, 2};
    b.write(reinterpret_cast<const char*>(&n), 1);
    b.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  Mesh off = read_mesh(tmp / "t.off");
  Mesh ply = read_mesh(tmp / "t.ply");
  Mesh bin = read_mesh(tmp / "b.ply");
  CHECK(off.vertices == ply.vertices);
  CHECK(off.faces == ply.faces);
  CHECK(bin.vertices.rows() == 3);
  CHECK(bin.vertices(2, 0) == 0.25);
  CHECK(bin.faces.row(0) == Eigen::RowVector3i(0, 1, 2));
}

TEST_CASE("read_mesh: bad input gives a clear error naming the file", "[io]") {
  df::test::TempDir tmp;
  CHECK_THROWS_WITH(read_mesh(tmp / "missing.obj"), Catch::Contains("no such file"));
  write_text(tmp / "empty.obj", "");
  CHECK_THROWS_WITH(read_mesh(tmp / "empty.obj"), Catch::Contains("empty file"));
  write_text(tmp / "text.obj", "hello\nthis is not a mesh\n");
  CHECK_THROWS_WITH(read_mesh(tmp / "text.obj"), Catch::Contains("no vertices found"));
  write_text(tmp / "points.obj", "v 0 0 0\nv 1 1 1\n");
  CHECK_THROWS_WITH(read_mesh(tmp / "points.obj"), Catch::Contains("no faces"));
  write_text(tmp / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  CHECK_THAT(df::test::error_message([&] { read_mesh(tmp / "range.obj"); }),
             Catch::Contains("names vertex 9, but 3 are defined before it") &&
                 Catch::Contains("range.obj:4)"));
  write_text(tmp / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  CHECK_THAT(df::test::error_message([&] { read_mesh(tmp / "nan.obj"); }),
             Catch::Contains("non-finite coordinate") && Catch::Contains("nan.obj:3)"));
  write_text(tmp / "nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n");
  CHECK_THAT(df::test::error_message([&] { read_mesh(tmp / "nan.off"); }),
             Catch::Contains("nan.off:5)"));
  write_text(tmp / "inf.ply",
             "ply\n"
             "format ascii 1.0\n"
             "element vertex 3\n"
             "property float x\n"
             "property float y\n"
             "property float z\n"
             "element face 1\n"
             "property list uchar int vertex_indices\n"
             "end_header\n"
             "0 0 0\n"
             "1 -inf 0\n"
             "0 1 0\n"
             "3 0 1 2\n");
  CHECK_THAT(df::test::error_message([&] { read_mesh(tmp / "inf.ply"); }),
             Catch::Contains("inf.ply:11)"));
  write_text(tmp / "word.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n");
  CHECK_THROWS_WITH(read_mesh(tmp / "word.obj"),
                    Catch::Contains("1 of 3 vertex lines could not be read"));
  write_text(tmp / "mesh.stl", "solid x\n");
  CHECK_THROWS_WITH(read_mesh(tmp / "mesh.stl"), Catch::Contains("unknown mesh format"));
  std::filesystem::create_directory(tmp / "dir.obj");
  CHECK_THROWS_WITH(read_mesh(tmp / "dir.obj"), Catch::Contains("is a directory"));
}

// What OpenMesh's readers cannot survive (found by fuzzing: an assertion abort, a crash in the
// PLY header parser, minutes of looping) is refused before they see it, naming file and line.
TEST_CASE("read_mesh: structure checks refuse what OpenMesh's readers cannot survive", "[io]") {
  df::test::TempDir tmp;
  auto error = [&](const std::string& name, const std::string& text) {
    write_text(tmp / name, text);
    return df::test::error_message([&] { read_mesh(tmp / name); });
  };
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  CHECK_THAT(error("zero.obj", tri + "f 1 2 0\n"),
             Catch::Contains("names vertex 0") && Catch::Contains("zero.obj:4)"));
  CHECK_THAT(error("novertex.obj", tri + "f /1/1 2 3\n"), Catch::Contains("face corner '/1/1'"));
  CHECK_THAT(error("texture.obj", tri + "vt 0 0\nf 1/1 2/2 3/1\n"),
             Catch::Contains("texture coordinate 2, but 1"));
  CHECK_THAT(error("two.obj", tri + "f 1 2\n"), Catch::Contains("fewer than 3 corners"));
  CHECK_NOTHROW(read_mesh(
      (write_text(tmp / "relative.obj", tri + "vt 0 0\nf -3/1 -2/1 -1\n"), tmp / "relative.obj")));
  CHECK_THAT(error("huge.off", "OFF\n410719722 1 0\n0 0 0\n"),
             Catch::Contains("more than the file's"));
  CHECK_THAT(error("corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000 0 1 2\n"),
             Catch::Contains("corner count") && Catch::Contains("corners.off:6)"));
  CHECK_THAT(error("drift.off", "OFF\n3 1 0\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n"),
             Catch::Contains("exactly 3 coordinates") && Catch::Contains("drift.off:3)"));
  CHECK_THAT(error("color.off", "COFF\n3 1 0\n"), Catch::Contains("only plain OFF"));
  CHECK_THAT(error("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
             Catch::Contains("not a vertex index below 3"));
  const std::string header =
      "ply\n"
      "format ascii 1.0\n"
      "element vertex 3\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "element face 1\n"
      "property list uchar int vertex_indices\n";
  CHECK_THAT(error("format.ply", header + "format binary_little_endian 1.0\nend_header\n"),
             Catch::Contains("one 'format"));
  CHECK_THAT(
      error("type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n"),
      Catch::Contains("unknown type 'quad'"));
  CHECK_THAT(error("short.ply", header + "end_header\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n"),
             Catch::Contains("fewer values") && Catch::Contains("short.ply:13)"));
  CHECK_THAT(error("records.ply", header + "end_header\n0 0 0\n1 0 0\n"),
             Catch::Contains("ends after 2 of 3 'vertex'"));
  const std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\n";
  CHECK_THAT(error("binary.ply", binary + std::string(12, '\0')),
             Catch::Contains("file ends inside 'vertex' record 3 of 1000"));
}

TEST_CASE("read_mesh: non-manifold and zero-area faces are kept and counted", "[io]") {
  df::test::TempDir tmp;
  // Three triangles on edge (1,2); a zero-area triangle (collinear corners); a face with a
  // repeated corner (OpenMesh's OBJ reader skips it: counted as dropped).
  write_text(tmp / "nm.obj",
             "v 0 0 0\n"
             "v 1 0 0\n"
             "v 0 1 0\n"
             "v 0 0 1\n"
             "v 1 1 1\n"
             "v 5 5 5\n"
             "v 2 0 0\n"
             "f 1 2 3\n"
             "f 2 1 4\n"
             "f 1 2 5\n"
             "f 1 2 7\n"
             "f 3 3 4\n");
  df::io::MeshReadReport rep;
  Mesh m = read_mesh(tmp / "nm.obj", &rep);
  CHECK(m.vertices.rows() == 7);  // OpenMesh's kernel would have duplicated vertices
  CHECK(m.faces.rows() == 4);
  CHECK(rep.nonmanifold_edges == 1);
  CHECK(rep.degenerate_faces == 1);
  CHECK(rep.isolated_vertices == 1);
  CHECK(rep.dropped_faces == 1);
}

TEST_CASE("MeshWriter: OBJ, OFF and PLY round-trip at full precision", "[io]") {
  df::test::TempDir tmp;
  Mesh m = df::test::tetrahedron();
  m.vertices(3, 2) = 1.0 / 3.0;
  for (const char* ext : {".obj", ".off", ".ply"}) {
    std::string p = tmp / (std::string("t") + ext);
    df::io::write_mesh(p, m);
    Mesh r = read_mesh(p);
    CHECK(r.faces == m.faces);
    CHECK((r.vertices - m.vertices).cwiseAbs().maxCoeff() < 1e-8);
  }
  CHECK_THROWS_WITH(df::io::write_mesh(tmp / "t.stl", m), Catch::Contains("unknown mesh format"));
}

TEST_CASE("check_same_connectivity: names the frame and the first differing face", "[io]") {
  Mesh ref = df::test::tetrahedron(), frame = ref;
  CHECK_NOTHROW(df::io::check_same_connectivity(ref, "0.obj", frame, "1.obj"));
  frame.faces(2, 1) = 1;
  CHECK_THROWS_WITH(df::io::check_same_connectivity(ref, "0.obj", frame, "1.obj"),
                    Catch::Contains("first at triangle 3: (1 2 3) instead of (1 4 3)"));
  Mesh fewer = ref;
  fewer.vertices.conservativeResize(3, 3);
  CHECK_THROWS_WITH(df::io::check_same_connectivity(ref, "0.obj", fewer, "2.obj"),
                    Catch::Contains("has 3 vertices but the reference 0.obj has 4"));
}

TEST_CASE("read_obj_frame: the fast parser agrees with read_mesh and checks every face", "[io]") {
  df::test::TempDir tmp;
  const std::string head =
      "mtllib x.mtl\n"
      "o thing\n"
      "v 0 0 0\n"
      "v 1 0 0\n"
      "v 1 1 0\n"
      "v 0 1 0.123456789012345678\n"
      "v 2 0.5 0\n"
      "vt 0 0\n"
      "vn 0 0 1\n"
      "s off\n";
  write_text(tmp / "a.obj", head + "f 1/1/1 2/1/1 3/1/1 4/1/1\nf 2//1 -1//1 -3//1\n");
  Mesh ref = read_mesh(tmp / "a.obj");
  df::Vertices fast = df::io::read_obj_frame(tmp / "a.obj", ref, "a.obj");
  CHECK(fast == ref.vertices);
  CHECK(fast(3, 2) == 0.123456789012345678);  // double precision, unlike OpenMesh's float reader
  CHECK(ref.faces.row(2) == Eigen::RowVector3i(1, 4, 2));  // relative indices resolved
  write_text(tmp / "b.obj", head + "f 1 2 3 4\nf 2 5 4\n");
  CHECK_THAT(df::test::error_message([&] { df::io::read_obj_frame(tmp / "b.obj", ref, "a.obj"); }),
             Catch::Contains("first at triangle 3: (2 5 4) instead of (2 5 3)") &&
                 Catch::Contains("b.obj)"));
  write_text(tmp / "c.obj",
             "v 0 0 0\nv 1 0 0\nv 1 inf 0\nv 0 1 0\nv 2 0.5 0\nf 1 2 3 4\nf 2 5 3\n");
  CHECK_THAT(df::test::error_message([&] { df::io::read_obj_frame(tmp / "c.obj", ref, "a.obj"); }),
             Catch::Contains("non-finite") && Catch::Contains("c.obj:3)"));
  write_text(tmp / "d.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  CHECK_THAT(df::test::error_message([&] { df::io::read_obj_frame(tmp / "d.obj", ref, "a.obj"); }),
             Catch::Contains("has 4 vertices but the reference a.obj has 5"));
}
