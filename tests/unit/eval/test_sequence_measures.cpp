#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include "core/error.h"
#include "eval/sequence_measures.h"

using namespace df;
using convert::FrameSet;

namespace {

// The unit square in z = 0, two triangles.
Vertices square() {
  Vertices v(4, 3);
  v << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  return v;
}

// Sequences of frames on the square's template, positions stored.
FrameSet frames(const std::vector<std::pair<std::string, std::vector<Vertices>>>& sequences) {
  FrameSet fs;
  fs.path = "pred.h5";
  fs.tmpl.vertices = square();
  fs.tmpl.faces.resize(2, 3);
  fs.tmpl.faces << 0, 1, 2, 0, 2, 3;
  fs.offsets = {0};
  for (const auto& [name, seq] : sequences) {
    fs.sequences.push_back(name);
    for (const auto& v : seq) {
      fs.names.push_back(name + "_" + std::to_string(fs.positions.size()));
      fs.positions.push_back(v);
    }
    fs.offsets.push_back(static_cast<std::int64_t>(fs.positions.size()));
  }
  fs.positions_stored = true;
  return fs;
}

// The square with vertex 2 lifted by z.
Vertices lifted(double z) {
  Vertices v = square();
  v(2, 2) = z;
  return v;
}

std::vector<eval::PairResult> errors(const std::vector<double>& e) {
  std::vector<eval::PairResult> out;
  for (double x : e) out.push_back({.error = x, .unit_ball = x, .sted_s = 0, .rse = -1});
  return out;
}

// The file an error names (Error::where()).
std::string where(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.where();
  }
  return "(no error)";
}

eval::FramePairs identity_pairs(std::size_t n) {
  eval::FramePairs p;
  for (std::size_t i = 0; i < n; ++i) p.emplace_back(i, i);
  return p;
}

}  // namespace

TEST_CASE("pair_frames: by /frames/source, else frame by frame; errors name the file", "[eval]") {
  FrameSet truth = frames({{"t", {square(), lifted(0.1), lifted(0.2)}}});
  truth.path = "truth.h5";
  FrameSet pred = frames({{"p", {square(), lifted(0.1), lifted(0.2)}}});
  CHECK(eval::pair_frames(pred, truth) == eval::FramePairs{{0, 0}, {1, 1}, {2, 2}});
  pred.source = {2, -1, 0};  // the middle frame has no truth
  CHECK(eval::pair_frames(pred, truth) == eval::FramePairs{{0, 2}, {2, 0}});
  pred.source = {5, 0, 0};
  CHECK_THROWS_WITH(eval::pair_frames(pred, truth), Catch::Contains("pairs with frame 5"));
  CHECK(where([&] { eval::pair_frames(pred, truth); }) == "pred.h5/frames/source");
  pred.source = {-1, -1, -1};
  CHECK_THROWS_WITH(eval::pair_frames(pred, truth), Catch::Contains("no frame pairs"));
  pred.source.clear();
  FrameSet shorter = frames({{"p", {square(), lifted(0.1)}}});
  CHECK_THROWS_WITH(eval::pair_frames(shorter, truth), Catch::Contains("has 2 frames"));
  FrameSet other = truth;
  other.tmpl.faces.row(1) << 0, 3, 2;
  CHECK_THROWS_WITH(eval::pair_frames(pred, other), Catch::Contains("template"));
  CHECK(where([&] { eval::pair_frames(pred, other); }) == "truth.h5");
}

TEST_CASE("measure_pairs: errors after alignment per pair; totals leave given frames out",
          "[eval]") {
  FrameSet truth = frames({{"t", {square(), lifted(0.1), lifted(0.2)}}});
  FrameSet pred = frames({{"p", {square(), lifted(0.1), lifted(0.2)}}});
  for (auto& v : pred.positions) v.col(0).array() += 3;  // moved: translation alignment undoes it
  const auto sh = eval::shape_of(pred);
  const auto pairs = eval::pair_frames(pred, truth);
  const auto pm = eval::measure_pairs(pred, truth, sh, pairs, {});
  REQUIRE(pm.results.size() == 3);
  for (const auto& r : pm.results) CHECK(r.error == Approx(0).margin(1e-12));
  CHECK(pm.diag == Approx(std::sqrt(2.0)));
  CHECK(pm.sted_t_n == 2);  // consecutive frames of one sequence

  // Steps: frame 0 is given (step 0), a copy of the truth, left out of the totals.
  pred.step = {0, 1, 2};
  const auto t = eval::totals_of(pred, pairs, errors({5, 1, 3}));
  CHECK(t.skip_given);
  CHECK(t.counted == 2);
  CHECK(t.err == Approx(4));
  CHECK(t.by_step.at(0) == std::pair<double, int>{5, 1});
  CHECK(t.by_step.at(2) == std::pair<double, int>{3, 1});
  pred.step.clear();  // no steps: every frame counts, by frame index
  const auto all = eval::totals_of(pred, pairs, errors({5, 1, 3}));
  CHECK_FALSE(all.skip_given);
  CHECK(all.counted == 3);
  CHECK(all.err == Approx(9));
}

TEST_CASE("diverse samples: groups by NAME~k, spread between samples, each against the truth",
          "[eval]") {
  Vertices doubled = square() * 2;
  FrameSet pred = frames({{"a~0", {square(), square()}},
                          {"a~1", {square(), doubled}},
                          {"b~0", {square(), square()}},
                          {"b~1", {square(), square()}},
                          {"c~0", {square(), square()}},
                          {"d", {square(), square()}}});
  pred.step = {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1};
  const auto groups = eval::sample_groups(pred);
  REQUIRE(groups.size() == 2);  // c has one sample, d none
  CHECK(groups.at("a") == std::vector<std::size_t>{0, 1});
  CHECK(groups.at("b") == std::vector<std::size_t>{2, 3});
  // The doubled square, moved onto the square's centroid, lies sqrt(1/2) from it at every vertex;
  // the given frames (step 0) are not compared: two pairs, one per case.
  const auto sh = eval::shape_of(pred);
  const auto [spread, n] = eval::sample_spread(pred, groups, sh);
  CHECK(n == 2);
  CHECK(spread == Approx(std::sqrt(0.5)));
  // Each sample's mean error over its generated frames: a 2 and 4, b 1 and 1.
  const auto v = eval::samples_vs_truth(pred, groups, identity_pairs(12),
                                        errors({9, 2, 9, 4, 9, 1, 9, 1, 0, 0, 0, 0}), true);
  CHECK(v.cases == 2);
  CHECK(v.best == Approx(1.5));
  CHECK(v.mean == Approx(2));
  CHECK(v.worst == Approx(2.5));
  // Samples of one name must be equally long.
  FrameSet uneven = frames({{"a~0", {square(), square()}}, {"a~1", {square()}}});
  CHECK_THROWS_WITH(eval::sample_spread(uneven, eval::sample_groups(uneven), sh),
                    Catch::Contains("different lengths"));
}

TEST_CASE("pace: a prediction moving half as far per frame as the data has pace 1/2", "[eval]") {
  // The data lifts vertex 2 by 0.1 per frame; with each frame's centroid removed a step moves
  // the four vertices (0.075 + 3 × 0.025) / 4 = 0.0375 on average.
  std::vector<Vertices> data, half;
  for (int t = 0; t < 6; ++t) data.push_back(lifted(0.1 * t)), half.push_back(lifted(0.05 * t));
  CHECK(eval::motion_between(data[1], data[0]) == Approx(0.0375));
  Vertices moved = data[1];
  moved.col(1).array() += 7;
  CHECK(eval::motion_between(moved, data[1]) == Approx(0).margin(1e-12));

  const FrameSet truth = frames({{"t", data}});
  FrameSet pred = frames({{"p", half}});
  pred.step = {0, 1, 2, 3, 4, 5};
  pred.source = {0, 1, 2, 3, 4, 5};
  const auto cases = eval::pace_of(pred, truth);
  REQUIRE(cases.size() == 1);
  CHECK(cases[0].name == "p");
  CHECK(cases[0].truth == Approx(eval::kPaceSteps * 0.0375));
  CHECK(cases[0].predicted / cases[0].truth == Approx(0.5));
  // A case whose paced frames lack a data frame, or a file without steps, has no pace.
  pred.source[3] = -1;
  CHECK(eval::pace_of(pred, truth).empty());
  pred.source[3] = 3;
  pred.step.clear();
  CHECK(eval::pace_of(pred, truth).empty());
}
