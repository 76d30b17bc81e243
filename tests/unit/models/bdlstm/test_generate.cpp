#include <catch2/catch.hpp>

#include "core/error.h"
#include "models/bdlstm/generate.h"

using namespace df::models;

namespace {

// One 50-frame sequence "s" whose last 10 frames (40-49) are held out; a second sequence the
// model never saw.
struct Fixture {
  BdlstmModel m;
  GenerationData d;
  Fixture() {
    m.split.sequences = {"s"};
    m.split.train_begin = {0}, m.split.train_end = {40}, m.split.test_begin = {40},
    m.split.test_end = {50};
    d.offsets = {0, 50, 80};
    d.sequences = {"s", "other"};
  }
};

}  // namespace

TEST_CASE("gen-bdlstm plan: prediction cases inside the held-out part", "[models][bdlstm]") {
  Fixture f;
  BdlstmGenerateOptions opt;
  opt.test_every = 2, opt.initial = 3, opt.test_context = 3, opt.length = 4;
  // The first predicted frame is 3 frames into the part; a case needs 3 + 4 frames.
  auto cases = plan_cases(opt, f.m, f.d, 1);
  REQUIRE(cases.size() == 2);
  CHECK(cases[0].frames == std::vector<std::int64_t>{40, 41, 42});
  CHECK(cases[0].name == "s-42");
  CHECK(cases[1].frames == std::vector<std::int64_t>{42, 43, 44});
  // One given frame, same context: the same predicted frames (43 on) as with three.
  opt.initial = 1;
  cases = plan_cases(opt, f.m, f.d, 1);
  CHECK(cases[0].frames == std::vector<std::int64_t>{42});
  // Stride 2: frames 2 apart; 3 given + 2 predicted span 9 frames: one case fits in 10.
  opt.initial = 3, opt.length = 2;
  cases = plan_cases(opt, f.m, f.d, 2);
  REQUIRE(cases.size() == 1);
  CHECK(cases[0].frames == std::vector<std::int64_t>{40, 42, 44});
  opt.length = 8;
  CHECK_THROWS_AS(plan_cases(opt, f.m, f.d, 2), df::InvalidInput);
}

TEST_CASE("gen-bdlstm plan: completion cases, --from and --keyframes", "[models][bdlstm]") {
  Fixture f;
  BdlstmGenerateOptions opt;
  opt.mode = GenerateMode::complete, opt.test_every = 3, opt.gap = 2;
  auto cases = plan_cases(opt, f.m, f.d, 1);
  REQUIRE(cases.size() == 3);  // keyframes (40, 43), (43, 46), (46, 49)
  CHECK(cases[2].frames == std::vector<std::int64_t>{46, 49});

  opt.test_every = 0;
  opt.keyframes = {"other:2", "other:10", "other:20"};
  cases = plan_cases(opt, f.m, f.d, 1);
  REQUIRE(cases.size() == 1);
  CHECK(cases[0].frames == std::vector<std::int64_t>{52, 60, 70});
  CHECK(cases[0].name == "other-2");
  CHECK_THROWS_AS(plan_cases(opt, f.m, f.d, 3),
                  df::UsageError);  // 8 frames apart: not a multiple of 3
  opt.keyframes = {"60", "52"};
  CHECK_THROWS_AS(plan_cases(opt, f.m, f.d, 1), df::UsageError);  // decreasing

  BdlstmGenerateOptions pred;
  pred.from = {"other:4", "12"};
  pred.initial = 3;
  cases = plan_cases(pred, f.m, f.d, 2);
  CHECK(cases[0].frames == std::vector<std::int64_t>{50, 52, 54});
  CHECK(cases[1].frames == std::vector<std::int64_t>{8, 10, 12});
  pred.from = {"other:3"};
  CHECK_THROWS_AS(plan_cases(pred, f.m, f.d, 2),
                  df::UsageError);  // only 2 frames of 'other' up to it
  pred.from = {"nowhere:1"};
  CHECK_THROWS_AS(plan_cases(pred, f.m, f.d, 1), df::UsageError);
}

TEST_CASE("gen-bdlstm completion: switch or cross-fade at the merge", "[models][bdlstm]") {
  // A gap of L = 6 steps; forward frames are 0, backward frames 1 (one row, one column).
  const int L = 6;
  std::vector<df::nn::Matrix<float>> F(L + 1, df::nn::Matrix<float>::Zero(1, 1)),
      B(L + 1, df::nn::Matrix<float>::Ones(1, 1));
  auto weights = [&](std::int64_t merge, int blend) {
    std::vector<float> w;
    for (const auto& m : merged_path(F, B, 0, merge, blend)) w.push_back(m(0, 0));
    return w;
  };
  // blend 0 (the paper): forward up to the merge, backward after it.
  REQUIRE(weights(2, 0) == std::vector<float>{0, 0, 1, 1, 1, 1});
  // blend 2: two frames in between, symmetric around the switch.
  const auto b2 = weights(2, 2);
  REQUIRE(b2[0] == 0);
  REQUIRE(b2[1] == Approx(1.0 / 3));
  REQUIRE(b2[2] == Approx(2.0 / 3));
  REQUIRE(b2[3] == 1);
  // The last step is the second keyframe whatever the merge and blend.
  REQUIRE(weights(6, 4).back() == 1);
  REQUIRE(weights(0, 0) == std::vector<float>{1, 1, 1, 1, 1, 1});
  for (int blend : {0, 1, 3, 8}) {
    const auto w = weights(3, blend);
    REQUIRE(std::is_sorted(w.begin(), w.end()));
  }
}

TEST_CASE("gen-bdlstm completion: weighted mix of the two chains", "[models][bdlstm]") {
  const int L = 4;
  std::vector<df::nn::Matrix<float>> F, B;
  for (int t = 0; t <= L; ++t) {
    F.push_back(df::nn::Matrix<float>::Constant(2, 1, static_cast<float>(t)));       // row 0, 1
    B.push_back(df::nn::Matrix<float>::Constant(2, 1, static_cast<float>(10 + t)));  // B_j
  }
  const auto p = weighted_path(F, B, 1);
  REQUIRE(p.size() == 4);
  // step t: (1 − t/4) t + (t/4)(10 + 4 − t)
  for (int t = 1; t <= L; ++t) {
    const double w = t / 4.0;
    REQUIRE(p[static_cast<std::size_t>(t - 1)](0, 0) == Approx((1 - w) * t + w * (14 - t)));
  }
  REQUIRE(p.back()(0, 0) == 10);  // the second keyframe B_0
}

TEST_CASE("gen-bdlstm --method nearest: motion matching in the training part", "[models][bdlstm]") {
  // Sequence "s" of 50 frames, one feature: a ramp 0..39 over the training part (frames 0-39),
  // then the held-out part. Frames 10-12 are given a copy at 40-42: the match is the window at
  // 10 (distance 0), whose change after its 3rd frame is +1 per frame.
  Fixture f;
  f.d.features = df::nn::Matrix<float>::Zero(80, 1);
  for (int t = 0; t < 40; ++t) f.d.features(t, 0) = static_cast<float>(t);
  for (int t = 40; t < 50; ++t) f.d.features(t, 0) = 100;  // the held-out part: far away
  f.d.features(40, 0) = 10, f.d.features(41, 0) = 11, f.d.features(42, 0) = 12;
  auto p = nearest_motion(f.m, f.d, {40, 41, 42}, 3, 1, 1);
  REQUIRE(p.size() == 3);
  CHECK(p[0](0, 0) == 13);
  CHECK(p[2](0, 0) == 15);
  // Stride 2: the match steps 2 frames, so +2 per step.
  f.d.features(42, 0) = 14, f.d.features(41, 0) = 12;  // given 10, 12, 14 at frames 40-42
  p = nearest_motion(f.m, f.d, {40, 41, 42}, 2, 2, 1);
  CHECK(p[1](0, 0) == 18);
  // Two neighbours: windows at 10 and 9 (distance 3) or 11 (distance 3, the later one loses the
  // tie); both move +1 per frame, so their mean does too.
  f.d.features(41, 0) = 11, f.d.features(42, 0) = 12;
  p = nearest_motion(f.m, f.d, {40, 41, 42}, 3, 1, 2);
  CHECK(p[0](0, 0) == Approx(13));
  // A still stretch in the training part matches still given frames: zero motion predicted.
  for (int t = 20; t < 30; ++t) f.d.features(t, 0) = 7;
  f.d.features(40, 0) = 7, f.d.features(41, 0) = 7, f.d.features(42, 0) = 7;
  p = nearest_motion(f.m, f.d, {40, 41, 42}, 3, 1, 1);
  CHECK(p[0](0, 0) == 7);
  CHECK(p[2](0, 0) == 7);
  // No window of 3 + 40 frames fits in 40 training frames; DATA without the model's sequence.
  CHECK_THROWS_AS(nearest_motion(f.m, f.d, {40, 41, 42}, 40, 1, 1), df::InvalidInput);
  f.d.sequences = {"renamed", "other"};
  CHECK_THROWS_AS(nearest_motion(f.m, f.d, {40, 41, 42}, 3, 1, 1), df::InvalidInput);
}
