#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <csignal>
#include <cstdio>
#include <fstream>

#include "core/atomic_output.h"
#include "core/error.h"
#include "helpers.h"

namespace fs = std::filesystem;
using df::AtomicOutput;

static std::size_t count_entries(const fs::path& dir) {
  return static_cast<std::size_t>(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
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
  CHECK_THROWS_WITH(
      AtomicOutput(tmp / "frames", AtomicOutput::Kind::directory, true, {tmp / "frames/0000.obj"}),
      Catch::Contains("holds an input"));
}

TEST_CASE(
    "OutputClaim: nests within a process, leaves no lock file, refuses another process's output",
    "[core]") {
  df::test::TempDir tmp;
  const fs::path out = tmp / "out.h5";
  const fs::path lock = df::OutputClaim::lock_path(out);
  CHECK(lock == tmp / ".out.h5.lock");
  {
    df::OutputClaim claim(out);
    CHECK(fs::exists(lock));
    {
      AtomicOutput a(out, AtomicOutput::Kind::file, false);  // the writer of a claimed output
      df::test::write_text(a.temp_path().string(), "data");
      a.commit();
    }
    CHECK(fs::exists(lock));  // still claimed by the outer claim
  }
  CHECK_FALSE(fs::exists(lock));
  CHECK(count_entries(tmp.path()) == 1);

  // Another process holds the lock (as a running tool does): refused at once, naming its PID.
  int ready[2];
  REQUIRE(pipe(ready) == 0);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // only system calls after fork
    const int fd = open(lock.c_str(), O_RDWR | O_CREAT, 0644);
    if (fd < 0 || flock(fd, LOCK_EX) != 0) _exit(1);
    char pid[32];
    const int n = snprintf(pid, sizeof pid, "%d\n", getpid());
    if (write(fd, pid, static_cast<std::size_t>(n)) != n || write(ready[1], "x", 1) != 1) _exit(1);
    pause();
    _exit(0);
  }
  char c = 0;
  REQUIRE(read(ready[0], &c, 1) == 1);
  CHECK_THROWS_WITH(df::OutputClaim(out),
                    Catch::Contains("another process (PID " + std::to_string(child) +
                                    ") is writing this output"));
  CHECK_THROWS_AS(AtomicOutput(out, AtomicOutput::Kind::file, true), df::IOError);
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  close(ready[0]);
  close(ready[1]);
  // The holder died: its lock died with it, the stale lock file is taken over and removed.
  { df::OutputClaim claim(out); }
  CHECK_FALSE(fs::exists(lock));
}

TEST_CASE("OutputClaim: the temporaries of processes that no longer run are removed", "[core]") {
  df::test::TempDir tmp;
  const pid_t gone = fork();  // a PID that surely ran and ended
  REQUIRE(gone >= 0);
  if (gone == 0) _exit(0);
  waitpid(gone, nullptr, 0);
  const fs::path out = tmp / "out.h5";
  const std::string stale = ".out.h5.tmp-" + std::to_string(gone) + "-0";
  const std::string live =
      ".out.h5.tmp-" + std::to_string(getppid()) + "-0";                     // a running process's
  const std::string other = ".other.h5.tmp-" + std::to_string(gone) + "-0";  // another output's
  for (const auto& name : {stale, live, other}) df::test::write_text(tmp / name, "partial");
  fs::create_directory(tmp /
                       (".out.h5.tmp-" + std::to_string(gone) + "-1"));  // a directory output's
  df::test::write_text(tmp / (".out.h5.tmp-" + std::to_string(gone) + "-1/0.obj"), "v 0 0 0");
  { df::OutputClaim claim(out); }
  CHECK_FALSE(fs::exists(tmp / stale));
  CHECK_FALSE(fs::exists(tmp / (".out.h5.tmp-" + std::to_string(gone) + "-1")));
  CHECK(fs::exists(tmp / live));
  CHECK(fs::exists(tmp / other));
}

TEST_CASE("claim_output: refuses an existing output before any work, a missing directory too",
          "[core]") {
  df::test::TempDir tmp;
  df::test::write_text(tmp / "old.h5", "old");
  CHECK_THROWS_WITH(df::claim_output(tmp / "old.h5", false), Catch::Contains("output exists"));
  CHECK_NOTHROW(df::claim_output(tmp / "old.h5", true));
  CHECK_THROWS_WITH(df::claim_output(tmp / "old.h5", true, {tmp / "old.h5"}),
                    Catch::Contains("overwrite an input"));
  CHECK_THROWS_WITH(df::claim_output(tmp / "no/x.h5", false),
                    Catch::Contains("directory does not exist"));
  CHECK(df::claim_outputs({"", "-", tmp / "new.h5"}, false).size() == 1);
  CHECK(count_entries(tmp.path()) == 1);  // no lock file left
}
