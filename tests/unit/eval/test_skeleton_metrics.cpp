#include <tbb/global_control.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/error.h"
#include "core/rng.h"
#include "eval/skeleton_metrics.h"
#include "synth/actions.h"

using namespace df;
using eval::RowMatrixF;

namespace {
RowMatrixF gaussian(int rows, int cols, double mean, double sd, std::uint64_t seed) {
  RowMatrixF M(rows, cols);
  Rng rng(seed);
  for (Eigen::Index i = 0; i < M.size(); ++i)
    M.data()[i] = static_cast<float>(rng.normal(mean, sd));
  return M;
}

// Synthetic actions of `classes`, per_class sequences of `frames` frames each, by `subjects`
// performers; every sequence marked as test (callers change the marks).
io::SkeletonFile actions(std::vector<std::string> classes, int per_class, int frames,
                         std::uint64_t seed, int subjects = 5) {
  synth::ActionParams p;
  p.classes = std::move(classes);
  p.per_class = per_class;
  p.frames = frames;
  p.subjects = subjects;
  p.seed = seed;
  io::SkeletonFile s = synth::make_actions(p);
  s.test.assign(s.sequences(), 1);
  return s;
}
}  // namespace

TEST_CASE("MMD: equal to a brute-force double-precision sum over every pair", "[eval]") {
  for (auto [m, n, d, shift] : {std::tuple{5, 7, 3, 0.0}, std::tuple{40, 30, 12, 0.5},
                                std::tuple{150, 170, 60, 0.2}, std::tuple{2, 2, 1, 3.0}}) {
    const RowMatrixF X = gaussian(m, d, 0, 1, 1), Y = gaussian(n, d, shift, 1.2, 2);
    const auto fast = eval::mmd2_max(X, Y);
    const auto ref = eval::mmd2_max_reference(X.cast<double>(), Y.cast<double>());
    INFO("m " << m << " n " << n << " d " << d);
    CHECK(fast.mmd2 == Approx(ref.mmd2).margin(1e-5).epsilon(1e-4));
    CHECK(fast.bandwidth == ref.bandwidth);
  }
}

TEST_CASE("MMD: about 0 for two samples of one distribution, larger the further they differ",
          "[eval]") {
  const RowMatrixF X = gaussian(300, 20, 0, 1, 3);
  const double same = eval::mmd2_max(X, gaussian(300, 20, 0, 1, 4)).mmd2;
  const double near = eval::mmd2_max(X, gaussian(300, 20, 0.3, 1, 5)).mmd2;
  const double far = eval::mmd2_max(X, gaussian(300, 20, 1.0, 1, 6)).mmd2;
  CHECK(std::abs(same) < 0.01);
  CHECK(near > 10 * std::abs(same));
  CHECK(far > near);
  // over the bandwidths the maximum is at least the widest one's value (which tends to 0)
  CHECK(eval::mmd_bandwidths().size() == 14);
  CHECK(eval::mmd_bandwidths().front() == 1e-4);
  CHECK(eval::mmd_bandwidths().back() == 1e9);
}

TEST_CASE("MMD: the same bits at 1 and 2 threads", "[eval]") {
  const RowMatrixF X = gaussian(700, 90, 0, 1, 7), Y = gaussian(650, 90, 0.1, 1, 8);
  double one = 0, two = 0;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = eval::mmd2_max(X, Y).mmd2;
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = eval::mmd2_max(X, Y).mmd2;
  }
  CHECK(one == two);
}

TEST_CASE("skeleton metrics: per class against the real test part, in the real file's coordinates",
          "[eval]") {
  io::SkeletonFile real = actions({"walk", "wave"}, 12, 20, 1);
  for (std::size_t s = 0; s < real.sequences(); ++s) real.test[s] = s % 2 == 0;
  const io::SkeletonFile gen =
      actions({"walk", "wave"}, 12, 25, 2);  // longer: compared over the first 20
  const auto r = eval::skeleton_metrics(gen, real);
  CHECK(r.frames == 20);
  REQUIRE(r.classes.size() == 2);
  CHECK(r.classes[0].generated == 12);
  CHECK(r.classes[0].real == 6);
  // the generated walks against the real waves: much further apart
  io::SkeletonFile swapped = gen;
  for (auto& l : swapped.labels) l = 1 - l;
  const auto w = eval::skeleton_metrics(swapped, real);
  CHECK(w.mmd_seq > 3 * r.mmd_seq);
  CHECK(w.mmd_avg > 3 * r.mmd_avg);
  CHECK(r.classes[0].spread_mean > 0);
}

TEST_CASE("skeleton metrics: sequences picked by subject, a file against itself", "[eval]") {
  io::SkeletonFile data = actions({"walk", "wave"}, 12, 20, 1, 4);
  for (std::size_t s = 0; s < data.sequences(); ++s) data.test[s] = data.subjects[s] == 4;
  eval::SkeletonSelection select;
  select.pred_subjects = {1, 2, 3};
  // against the test part (subject 4) by default: every subject-4 clip of a class, 3 subjects' of
  // PRED
  const auto r = eval::skeleton_metrics(data, data, select);
  REQUIRE(r.classes.size() == 2);
  CHECK(r.classes[0].generated == 9);
  CHECK(r.classes[0].real == 3);
  // the same with TRUTH's subjects named: test flags do not matter then
  select.truth_subjects = {4};
  io::SkeletonFile unflagged = data;
  unflagged.test.assign(data.sequences(), 0);
  const auto named = eval::skeleton_metrics(data, unflagged, select);
  CHECK(named.mmd_avg == r.mmd_avg);
  CHECK(named.mmd_seq == r.mmd_seq);
  // one subject's clips against themselves: no difference left (MMD_u^2 of a sample with itself
  // is negative, the unbiased estimator's -2/(n-1) mean cross term)
  select.pred_subjects = {2};
  select.truth_subjects = {2};
  CHECK(eval::skeleton_metrics(data, data, select).mmd_seq < 0.1 * r.mmd_seq);
  SECTION("errors") {
    select.truth_subjects = {7};
    CHECK_THROWS_WITH(eval::skeleton_metrics(data, data, select), Catch::Contains("subject 7"));
    select.truth_subjects = {4};
    select.all_truth = true;
    CHECK_THROWS_AS(eval::skeleton_metrics(data, data, select), UsageError);
    select.all_truth = false;
    io::SkeletonFile anonymous = data;
    anonymous.subjects.clear();
    CHECK_THROWS_WITH(eval::skeleton_metrics(anonymous, data, select),
                      Catch::Contains("names no subjects"));
  }
}

TEST_CASE("skeleton metrics: the motion MMD tells sequences held still from moving ones",
          "[eval]") {
  const io::SkeletonFile real = actions({"walk", "kick"}, 30, 20, 1);
  const io::SkeletonFile gen = actions({"walk", "kick"}, 30, 20, 2);
  io::SkeletonFile still = gen;  // every sequence holds its first pose
  const std::size_t fs = gen.frame_size();
  for (std::size_t s = 0; s < gen.sequences(); ++s)
    for (auto t = gen.offsets[s]; t < gen.offsets[s + 1]; ++t)
      std::copy_n(gen.poses.begin() + gen.offsets[s] * static_cast<std::ptrdiff_t>(fs), fs,
                  still.poses.begin() + t * static_cast<std::ptrdiff_t>(fs));
  const auto r = eval::skeleton_metrics(gen, real);
  const auto w = eval::skeleton_metrics(still, real);
  CHECK(w.mmd_motion_avg > 10 * r.mmd_motion_avg);
  CHECK(w.mmd_motion_seq > 10 * r.mmd_motion_seq);
  CHECK(r.classes[0].mmd_motion_seq == r.classes[0].mmd_motion_seq);  // not NaN
  // one frame: no motion to measure
  io::SkeletonFile one = gen;
  for (std::size_t s = 0; s <= one.sequences(); ++s) one.offsets[s] = static_cast<std::int64_t>(s);
  one.poses.resize(one.sequences() * fs);
  one.frames = one.sequences();
  CHECK(std::isnan(eval::skeleton_metrics(one, real).mmd_motion_seq));
}

TEST_CASE("variety: mean distance between two sequences and MMD of a set's halves", "[eval]") {
  // three rows at 0, 3 and 4 along one axis: distances 3, 4, 1 -> mean 8/3
  RowMatrixF X = RowMatrixF::Zero(3, 2);
  X(1, 0) = 3;
  X(2, 0) = 4;
  CHECK(eval::mean_pairwise_distance(X) == Approx(8.0 / 3));
  CHECK(eval::mean_pairwise_distance(X.topRows(1)) == 0);
  CHECK(std::isnan(eval::halves_mmd(X, 1)));  // below 4 rows
  // the halves of one sample: near 0; of a set whose even rows differ from its odd ones: large
  const RowMatrixF same = gaussian(40, 6, 0, 1, 3);
  RowMatrixF split = same;
  for (Eigen::Index r = 1; r < split.rows(); r += 2) split.row(r).array() += 3;
  CHECK(std::abs(eval::halves_mmd(same, 3)) < 0.1);
  CHECK(eval::halves_mmd(split, 3) > 10 * std::abs(eval::halves_mmd(same, 3)));

  // in skeleton_metrics: copies of one generated sequence have no variety, the real clips some
  io::SkeletonFile real = actions({"walk", "wave"}, 12, 20, 1);
  io::SkeletonFile gen = actions({"walk", "wave"}, 12, 20, 2);
  const auto r = eval::skeleton_metrics(gen, real);
  CHECK(r.classes[0].pairwise_real > 0);
  CHECK(r.classes[0].pairwise_generated / r.classes[0].pairwise_real == Approx(1).margin(0.5));
  for (std::size_t s = 0; s < gen.sequences(); ++s) {  // every sequence a copy of its class's first
    const auto first = static_cast<std::size_t>(
        std::find(gen.labels.begin(), gen.labels.end(), gen.labels[s]) - gen.labels.begin());
    std::copy_n(gen.poses.begin() + gen.offsets[first] * 60, 20 * 60,
                gen.poses.begin() + gen.offsets[s] * 60);
  }
  const auto copies = eval::skeleton_metrics(gen, real);
  CHECK(copies.classes[0].pairwise_generated == Approx(0).margin(1e-6));
  CHECK(copies.pairwise_ratio < 0.01);
}

TEST_CASE("pace: the distance a pose moves per frame, generated over real", "[eval]") {
  io::SkeletonFile real = actions({"walk", "wave"}, 8, 20, 1);
  io::SkeletonFile gen = real;
  eval::SkeletonSelection all;
  all.all_truth = true;
  const auto same = eval::skeleton_metrics(gen, real, all);
  CHECK(same.pace_ratio == Approx(1.0));
  CHECK(same.classes[0].motion_real > 0);
  // Every pose moved half as far from its sequence's first: x'_t = x_0 + (x_t - x_0) / 2, so
  // every step from one frame to the next is half as long.
  for (std::size_t s = 0; s < gen.sequences(); ++s) {
    const auto first = static_cast<std::size_t>(gen.offsets[s]);
    for (std::size_t t = first + 1; t < static_cast<std::size_t>(gen.offsets[s + 1]); ++t)
      for (std::size_t k = 0; k < 60; ++k)
        gen.poses[t * 60 + k] =
            gen.poses[first * 60 + k] + (real.poses[t * 60 + k] - real.poses[first * 60 + k]) / 2;
  }
  const auto half = eval::skeleton_metrics(gen, real, all);
  CHECK(half.pace_ratio == Approx(0.5).epsilon(1e-4));
  CHECK(half.classes[1].motion_generated == Approx(half.classes[1].motion_real / 2).epsilon(1e-4));
}
