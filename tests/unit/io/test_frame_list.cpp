#include <catch2/catch.hpp>

#include "core/error.h"
#include "helpers.h"
#include "io/frame_list.h"

namespace fs = std::filesystem;

TEST_CASE("expand_frames: directories in natural order, files, and @lists", "[io]") {
  df::test::TempDir tmp;
  fs::create_directory(tmp / "seq");
  for (const char* n : {"10.obj", "2.obj", "1.obj", "notes.txt", "3.PLY"})
    df::test::write_text(tmp / (std::string("seq/") + n), "");
  auto frames = df::io::expand_frames(tmp / "seq");
  REQUIRE(frames.size() == 4);
  CHECK(frames[0].name == "1");
  CHECK(frames[1].name == "2");
  CHECK(frames[2].name == "3");
  CHECK(frames[3].name == "10");
  df::test::write_text(tmp / "list.txt", "# frames\nseq/10.obj\n\n  seq/1.obj  \nseq\n");
  auto listed = df::io::expand_frames("@" + (tmp / "list.txt"));
  REQUIRE(listed.size() == 6);
  CHECK(listed[0].name == "10");
  CHECK(listed[1].name == "1");
  CHECK(listed[2].name == "1");
  auto both = df::io::expand_frames(std::vector<std::string>{tmp / "seq/2.obj", tmp / "seq"});
  CHECK(both.size() == 5);
}

TEST_CASE("expand_frames: missing paths and empty directories are errors", "[io]") {
  df::test::TempDir tmp;
  CHECK_THROWS_WITH(df::io::expand_frames(tmp / "nope"),
                    Catch::Contains("no such file or directory"));
  fs::create_directory(tmp / "empty");
  CHECK_THROWS_WITH(df::io::expand_frames(tmp / "empty"), Catch::Contains("no mesh files"));
  df::test::write_text(tmp / "list.txt", "a.obj\nmissing.obj\n");
  df::test::write_text(tmp / "a.obj", "");
  CHECK_THAT(df::test::error_message([&] { df::io::expand_frames("@" + (tmp / "list.txt")); }),
             Catch::Contains("missing.obj") && Catch::Contains("list.txt:2)"));
  CHECK_THROWS_WITH(df::io::expand_frames("@" + (tmp / "nolist.txt")),
                    Catch::Contains("no such list file"));
}
