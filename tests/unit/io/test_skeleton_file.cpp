#include <catch2/catch.hpp>

#include "core/error.h"
#include "helpers.h"
#include "io/file_header.h"
#include "io/skeleton_file.h"

namespace {

// Two one-frame sequences of a 2-joint figure, classes walk / wave / jump.
df::io::SkeletonFile two_sequences() {
  df::io::SkeletonFile s;
  s.frames = 2, s.joints = 2, s.dims = 3;
  s.poses = {0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0.5f};
  s.offsets = {0, 1, 2};
  s.sequence_names = {"a", "b"};
  s.labels = {1, 0};
  s.class_names = {"walk", "wave", "jump"};
  s.parents = {-1, 0};
  s.joint_names = {"hips", "head"};
  return s;
}

df::io::SkeletonFile round_trip(const df::io::SkeletonFile& s, const std::string& path) {
  {
    df::h5::File f(path, df::h5::File::Mode::create);
    df::io::write_header(f, "skeleton");
    df::io::write_skeleton_data(f, s);
  }
  return df::io::read_skeleton_file(path);
}

}  // namespace

TEST_CASE("skeleton file: mixture weights round-trip and name what a sequence was made for",
          "[io]") {
  df::test::TempDir tmp;
  auto s = two_sequences();
  SECTION("without weights every sequence is its class") {
    const auto back = round_trip(s, tmp / "plain.h5");
    CHECK(back.label_weights.empty());
    CHECK_FALSE(back.is_mixture(0));
    CHECK(back.label_text(0) == "wave");
    CHECK(back.label_text(1) == "walk");
  }
  SECTION("a mixture row and a one-hot row") {
    s.label_weights = {0.25f, 0.75f, 0, 1, 0, 0};
    const auto back = round_trip(s, tmp / "mix.h5");
    CHECK(back.label_weights == s.label_weights);
    CHECK(back.is_mixture(0));
    CHECK(back.label_text(0) == "walk 0.25 + wave 0.75");
    CHECK_FALSE(back.is_mixture(1));
    CHECK(back.label_text(1) == "walk");
  }
  SECTION("weights that do not sum to 1, or a negative one, are refused with the object named") {
    const auto refused = [&](std::vector<float> w, const std::string& message) {
      s.label_weights = std::move(w);
      {
        df::h5::File f(tmp / "bad.h5", df::h5::File::Mode::create);
        df::io::write_header(f, "skeleton");
        df::io::write_skeleton_data(f, s);  // written as given: the reader checks
      }
      try {
        df::io::read_skeleton_file(tmp / "bad.h5");
        FAIL("read without an error");
      } catch (const df::InvalidInput& e) {
        CHECK_THAT(e.what(), Catch::Contains(message));
        CHECK_THAT(e.where(), Catch::Contains("/sequences/label_weights"));
      }
    };
    refused({0.5f, 0.75f, 0, 1, 0, 0}, "row 0 sums to 1.25, not 1");
    refused({1, 0, 0, 1.5f, -0.5f, 0}, "a negative weight in row 1");
  }
}
