#include <catch2/catch.hpp>
#include <cstdlib>

#include "core/provenance.h"

TEST_CASE("provenance: command line is quoted and history is newest first, deduplicated",
          "[core]") {
  const char* argv[] = {"/usr/bin/obj2acap", "in dir/", "-o", "out.h5", "it's"};
  df::provenance::set_command_line(5, argv);
  CHECK(df::provenance::command_line() == "obj2acap 'in dir/' -o out.h5 'it'\\''s'");
  setenv("SOURCE_DATE_EPOCH", "0", 1);
  CHECK(df::provenance::now_iso8601() == "1970-01-01T00:00:00Z");
  std::string h = df::provenance::history(
      {"2026-01-02T00:00:00Z synth a\n2026-01-01T00:00:00Z base\n", "2026-01-01T00:00:00Z base\n"});
  auto lines = df::provenance::history_lines(h);
  REQUIRE(lines.size() == 3);
  CHECK(lines[0] == "1970-01-01T00:00:00Z obj2acap 'in dir/' -o out.h5 'it'\\''s'");
  CHECK(lines[1] == "2026-01-02T00:00:00Z synth a");
  CHECK(lines[2] == "2026-01-01T00:00:00Z base");
  unsetenv("SOURCE_DATE_EPOCH");
}
