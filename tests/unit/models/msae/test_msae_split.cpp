#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "models/msae/components.h"
#include "models/msae/train.h"

using namespace df;
using namespace df::models;

TEST_CASE("MSAE split: every 10th shape of each sequence trains (paper 1:9)", "[models][msae]") {
  MsaeTraining t;
  const auto s = split_shapes({0, 25, 40}, t);
  CHECK(s.train == std::vector<std::int64_t>{0, 10, 20, 25, 35});
  CHECK(s.test.size() == 35);
  CHECK(s.validation.empty());
  t.validation_fraction = 0.2;
  const auto v = split_shapes({0, 25, 40}, t);
  CHECK(v.train == s.train);  // validation comes out of the held-out shapes only
  CHECK(v.validation.size() == 7);
  CHECK(v.test.size() == 28);
  for (auto f : v.validation) CHECK(std::find(v.test.begin(), v.test.end(), f) == v.test.end());
}

TEST_CASE("MSAE split: collections train on a random half drawn from the seed", "[models][msae]") {
  MsaeTraining t;
  t.split = SplitKind::collection;
  t.seed = 4;
  const auto a = split_shapes({0, 71}, t);
  CHECK(a.train.size() == 36);  // round(0.5 × 71)
  CHECK(a.test.size() == 35);
  CHECK(std::is_sorted(a.train.begin(), a.train.end()));
  CHECK(split_shapes({0, 71}, t).train == a.train);
  t.seed = 5;
  CHECK(split_shapes({0, 71}, t).train != a.train);
}

TEST_CASE("MSAE split: list files name frames by name or index", "[models][msae]") {
  const auto dir = std::filesystem::temp_directory_path() / "df-msae-lists";
  std::filesystem::create_directories(dir);
  const std::vector<std::string> names = {"a", "b", "c", "d", "e"};
  std::ofstream(dir / "train.txt") << "# shapes\nc\n\n0\n";
  std::ofstream(dir / "test.txt") << "d\n";
  auto s = split_from_lists(names, (dir / "train.txt").string(), (dir / "test.txt").string());
  CHECK(s.train == std::vector<std::int64_t>{0, 2});
  CHECK(s.test == std::vector<std::int64_t>{3});
  s = split_from_lists(names, (dir / "train.txt").string(), "");
  CHECK(s.test == std::vector<std::int64_t>{1, 3, 4});
  std::ofstream(dir / "bad.txt") << "a\nz\n";
  try {
    split_from_lists(names, (dir / "bad.txt").string(), "");
    FAIL("no error for an unknown frame");
  } catch (const InvalidInput& e) {
    CHECK(e.where().find("bad.txt:2") != std::string::npos);
  }
  std::ofstream(dir / "twice.txt") << "a\n0\n";
  CHECK_THROWS_AS(split_from_lists(names, (dir / "twice.txt").string(), ""), InvalidInput);
  std::ofstream(dir / "overlap.txt") << "c\n";
  CHECK_THROWS_AS(
      split_from_lists(names, (dir / "train.txt").string(), (dir / "overlap.txt").string()),
      InvalidInput);
  std::filesystem::remove_all(dir);
}

TEST_CASE("MSAE components: strength (eq. 7) and pruning keep strong, drop weak",
          "[models][msae]") {
  const std::array<double, 9> ref = {0, 0, 0, 1, 0, 0, 1, 0, 1};
  // 4 vertices: two moved by 0.3 (norm of the 9-vector), two untouched.
  std::vector<float> x(36);
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 9; ++d)
      x[static_cast<std::size_t>(9 * i + d)] = static_cast<float>(ref[static_cast<std::size_t>(d)]);
  x[0] += 0.3f;
  x[9 + 4] -= 0.3f;
  // only the vertices above eps1 count: (0.3 + 0.3) / 2
  CHECK(component_strength(x.data(), 4, ref, 1e-6) == Approx(0.3).epsilon(1e-6));
  CHECK(component_strength(x.data(), 4, ref, 0.5) == 0);

  // Planted components: a strong localized one, a weak one, one with no deformation.
  Components c;
  c.tmpl.vertices = Vertices::Zero(4, 3);
  c.tmpl.faces = Faces(1, 3);
  c.tmpl.faces << 0, 1, 2;
  c.normalization.min.fill(-10);
  c.normalization.max.fill(10);
  const auto nref = geometry::identity_features(&c.normalization);
  ComponentLevel level;
  level.features.resize(3, 36);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 36; ++j)
      level.features(k, j) = static_cast<float>(nref[static_cast<std::size_t>(j % 9)]);
  level.features(0, 9) += 0.5f;     // strong
  level.features(1, 18) += 0.004f;  // weak
  level.strength.assign(3, 0);
  level.center = {1, 2, 0};
  level.block = {0, 0, 0};
  level.code = {1, 1, 1};
  level.kept = {1, 1, 1};
  c.levels.push_back(level);
  prune_components(c, 1e-6, 0.01);
  CHECK(c.levels[0].kept == std::vector<std::uint8_t>{1, 0, 0});
  CHECK(c.levels[0].strength[0] == Approx(0.5).epsilon(1e-5));
  CHECK(c.levels[0].strength[2] == 0);
  CHECK_THROWS_AS(prune_components(c, -1, 0.01), UsageError);
}
