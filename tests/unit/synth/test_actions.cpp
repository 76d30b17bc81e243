#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "synth/actions.h"

using namespace df;

namespace {
double bone(const io::SkeletonFile& s, std::size_t t, std::size_t j) {
  const auto p = static_cast<std::size_t>(s.parents[j]);
  double d = 0;
  for (std::size_t c = 0; c < 3; ++c) {
    const double x = s.poses[(t * s.joints + j) * 3 + c] - s.poses[(t * s.joints + p) * 3 + c];
    d += x * x;
  }
  return std::sqrt(d);
}
}  // namespace

TEST_CASE("synth-actions: labelled sequences of a rigid skeleton that moves, same per seed",
          "[synth]") {
  synth::ActionParams p;
  p.per_class = 4;
  p.frames = 30;
  p.subjects = 2;
  p.seed = 9;
  const io::SkeletonFile s = synth::make_actions(p);
  CHECK(s.class_names == synth::action_names());
  CHECK(s.sequences() == 20);
  CHECK(s.frames == 600);
  CHECK(s.labels[5] == 1);
  CHECK(s.subjects[5] == 2);  // round robin over 2 subjects
  CHECK(s.sequence_names[5] == "wave_001");
  for (std::size_t q = 0; q < s.sequences(); ++q) {
    const auto first = static_cast<std::size_t>(s.offsets[q]);
    double motion = 0;
    for (std::size_t t = first + 1; t < first + 30; ++t) {
      for (std::size_t j = 1; j < s.joints; ++j)
        CHECK(bone(s, t, j) == Approx(bone(s, first, j)).epsilon(1e-4));
      for (std::size_t k = 0; k < s.frame_size(); ++k)
        motion += std::abs(s.poses[t * s.frame_size() + k] - s.poses[first * s.frame_size() + k]);
    }
    CHECK(motion > 1.0);  // every action moves
  }
  CHECK(synth::make_actions(p).poses == s.poses);
  p.seed = 10;
  CHECK(synth::make_actions(p).poses != s.poses);
  p.classes = {"run"};
  CHECK_THROWS_AS(synth::make_actions(p), UsageError);
}
