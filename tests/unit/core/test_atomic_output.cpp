#include <catch2/catch.hpp>
#include <fstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "helpers.h"

namespace fs = std::filesystem;
using df::AtomicOutput;

static std::size_t count_entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST_CASE("AtomicOutput: file appears only on commit", "[core]") {
  df::test::TempDir tmp;
  std::string out = tmp / "out.h5";
  {
    AtomicOutput a(out, AtomicOutput::Kind::file, false);
    df::test::write_text(a.temp_path().string(), "data");
    CHECK(a.temp_path().parent_path() == fs::path(out).parent_path());
    CHECK_FALSE(fs::exists(out));
    a.commit();
  }
  CHECK(fs::exists(out));
  CHECK(count_entries(tmp.path()) == 1);
}

TEST_CASE("AtomicOutput: an exception before commit leaves nothing behind", "[core]") {
  df::test::TempDir tmp;
  std::string out = tmp / "out.h5";
  try {
    AtomicOutput a(out, AtomicOutput::Kind::file, false);
    df::test::write_text(a.temp_path().string(), "partial");
    throw std::runtime_error("boom");
  } catch (const std::runtime_error&) {
  }
  CHECK(count_entries(tmp.path()) == 0);
  try {
    AtomicOutput d(tmp / "frames", AtomicOutput::Kind::directory, false);
    df::test::write_text((d.temp_path() / "0.obj").string(), "v 0 0 0");
    throw std::runtime_error("boom");
  } catch (const std::runtime_error&) {
  }
  CHECK(count_entries(tmp.path()) == 0);
}

TEST_CASE("AtomicOutput: refuses existing outputs without force, and inputs always", "[core]") {
  df::test::TempDir tmp;
  std::string out = tmp / "out.h5";
  df::test::write_text(out, "old");
  CHECK_THROWS_AS(AtomicOutput(out, AtomicOutput::Kind::file, false), df::IOError);
  CHECK_THROWS_WITH(AtomicOutput(out, AtomicOutput::Kind::file, true, {out}),
                    Catch::Contains("overwrite an input"));
  CHECK_THROWS_WITH(AtomicOutput(tmp / "missing-dir/out.h5", AtomicOutput::Kind::file, false),
                    Catch::Contains("directory does not exist"));
  {
    AtomicOutput a(out, AtomicOutput::Kind::file, true);
    df::test::write_text(a.temp_path().string(), "new");
    a.commit();
  }
  std::ifstream in(out);
  std::string s;
  in >> s;
  CHECK(s == "new");
}

TEST_CASE("AtomicOutput: forced directory replacement keeps no old files", "[core]") {
  df::test::TempDir tmp;
  fs::create_directory(tmp / "frames");
  df::test::write_text(tmp / "frames/old.obj", "x");
  {
    AtomicOutput d(tmp / "frames", AtomicOutput::Kind::directory, true);
    df::test::write_text((d.temp_path() / "0000.obj").string(), "y");
    d.commit();
  }
  CHECK(fs::exists(tmp / "frames/0000.obj"));
  CHECK_FALSE(fs::exists(tmp / "frames/old.obj"));
  CHECK(count_entries(tmp.path()) == 1);
  // A directory that holds an input is never replaced.
  CHECK_THROWS_WITH(AtomicOutput(tmp / "frames", AtomicOutput::Kind::directory, true, {tmp / "frames/0000.obj"}),
                    Catch::Contains("holds an input"));
}
