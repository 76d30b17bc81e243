#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/log.h"
#include "core/progress.h"
#include "helpers.h"

namespace {
// Runs f with stderr redirected to a file and returns what it wrote.
template <class F>
std::string capture_stderr(F&& f) {
  df::test::TempDir tmp;
  std::string path = tmp / "err.txt";
  std::fflush(stderr);
  int saved = dup(2);
  FILE* file = std::fopen(path.c_str(), "w");
  dup2(fileno(file), 2);
  f();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::fclose(file);
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

TEST_CASE("Progress: plain lines when redirected, nothing when silent", "[core]") {
  df::log::set_program("t");
  df::Progress::force_mode(df::Progress::Mode::lines);
  std::string lines = capture_stderr([] {
    df::Progress p("reading frames", 10);
    for (int i = 0; i < 10; ++i) p.advance();
    p.finish();
  });
  CHECK_THAT(lines, Catch::StartsWith("t: reading frames: ") && Catch::EndsWith("done\n"));
  CHECK(lines.find('\r') == std::string::npos);
  CHECK_THAT(lines, Catch::Contains("10/10 (100%)"));

  df::Progress::force_mode(df::Progress::Mode::terminal);
  std::string tty = capture_stderr([] {
    df::Progress p("x", 3);
    p.advance(3);
  });
  CHECK_THAT(tty, Catch::StartsWith("\rt: x: 3/3") && Catch::EndsWith("done\033[K\n"));

  df::Progress::force_mode(df::Progress::Mode::silent);
  CHECK(capture_stderr([] {
          df::Progress p("x", 3);
          p.advance(3);
        }).empty());
}

TEST_CASE("log: levels filter and prefix with the program", "[core]") {
  df::log::set_program("tool");
  df::log::set_level(df::log::Level::warning);
  std::string s = capture_stderr([] {
    df::log::info("hidden {}", 1);
    df::log::warn("shown {}", 2);
    df::log::error("bad {}", 3);
  });
  CHECK(s == "tool: warning: shown 2\ntool: error: bad 3\n");
  df::log::set_level(df::log::Level::info);
}

TEST_CASE("Progress: no 'done' line when unwinding from an error", "[core]") {
  df::log::set_program("t");
  df::Progress::force_mode(df::Progress::Mode::lines);
  std::string s = capture_stderr([] {
    try {
      df::Progress p("x", 10);
      p.advance(2);
      throw std::runtime_error("fail");
    } catch (const std::runtime_error&) {
    }
  });
  CHECK(s.find("done") == std::string::npos);
  df::Progress::force_mode(df::Progress::Mode::silent);
}
