#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

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

TEST_CASE("synth-actions: the arm gestures keep the body still and differ in the right hand's path",
          "[synth]") {
  synth::ActionParams p;
  p.classes = {"wave", "gestures"};
  p.per_class = 2;
  p.frames = 40;
  p.seed = 3;
  const io::SkeletonFile s = synth::make_actions(p);
  REQUIRE(s.class_names.size() == 1 + synth::gesture_names().size());
  CHECK(s.class_names[1] == "hammer");
  const std::size_t right_hand = 11, left_hand = 7, left_foot = 15, right_foot = 19;
  // Each class's mean right-hand position over the first sequence, to tell the paths apart
  std::vector<std::array<double, 3>> mean_hand;
  for (std::size_t q = 0; q < s.sequences(); ++q) {
    const auto first = static_cast<std::size_t>(s.offsets[q]);
    double hand_travel = 0, foot_travel = 0;
    std::array<double, 3> mean{0, 0, 0};
    for (std::size_t t = first; t < first + 40; ++t) {
      for (std::size_t j = 1; j < s.joints; ++j)
        CHECK(bone(s, t, j) == Approx(bone(s, first, j)).epsilon(1e-4));
      for (std::size_t c = 0; c < 3; ++c) {
        mean[c] += s.poses[(t * s.joints + right_hand) * 3 + c] / 40;
        if (t == first) continue;
        const auto d = [&](std::size_t j) {
          return std::abs(s.poses[(t * s.joints + j) * 3 + c] -
                          s.poses[((t - 1) * s.joints + j) * 3 + c]);
        };
        hand_travel += d(s.class_names[s.labels[q]] == "clap" ? left_hand : right_hand);
        foot_travel += d(left_foot) + d(right_foot);
      }
    }
    CHECK(hand_travel > 0.5);   // the arm moves...
    CHECK(foot_travel < 1e-5);  // ...the body stands
    if (q % 2 == 0) mean_hand.push_back(mean);
  }
  for (std::size_t a = 0; a < mean_hand.size(); ++a)
    for (std::size_t b = a + 1; b < mean_hand.size(); ++b) {
      double d2 = 0;
      for (std::size_t c = 0; c < 3; ++c) d2 += std::pow(mean_hand[a][c] - mean_hand[b][c], 2);
      INFO(s.class_names[a] << " / " << s.class_names[b]);
      CHECK(std::sqrt(d2) > 0.03);  // no two classes' hands move about the same place
    }
  p.classes = {"punch", "gestures"};
  CHECK_THROWS_AS(synth::make_actions(p), UsageError);  // punch twice
}
