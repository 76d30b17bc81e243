#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "core/error.h"
#include "synth/meshseq.h"

using df::synth::MeshSeqKind;
using df::synth::MeshSeqParams;
using df::synth::MeshSequenceGenerator;

static double edge_length_change(const MeshSequenceGenerator& g, const df::Vertices& V) {
  const auto& F = g.rest().faces;
  const auto& R = g.rest().vertices;
  double worst = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = F(f, k), b = F(f, (k + 1) % 3);
      double l0 = (R.row(a) - R.row(b)).norm(), l1 = (V.row(a) - V.row(b)).norm();
      worst = std::max(worst, std::abs(l1 - l0) / l0);
    }
  return worst;
}

TEST_CASE("synth finger: first frame is the rest shape; the tip twists by the requested angle",
          "[synth]") {
  MeshSeqParams p;
  p.kind = MeshSeqKind::finger;
  p.frames = 40;
  p.periods = 1;
  p.amplitude = 0.0;  // twist only
  p.twist_degrees = 400;
  MeshSequenceGenerator g(p);
  CHECK(g.rest().vertices.rows() == 16 * 65 + 2);
  CHECK((g.frame(0) - g.rest().vertices).cwiseAbs().maxCoeff() < 1e-12);
  // Peak of the period (frame 20): ring at the tip rotated by 400 deg = 40 deg mod 360.
  auto V = g.frame(20);
  const int tip_first = 16 * 64;  // first vertex of the last ring, rest angle 0
  double angle = std::atan2(V(tip_first, 1), V(tip_first, 0)) * 180 / std::numbers::pi;
  CHECK(angle == Approx(40).margin(1e-9));
  // Halfway up the finger the twist is 200 deg.
  const int mid_first = 16 * 32;
  double mid = std::atan2(V(mid_first, 1), V(mid_first, 0)) * 180 / std::numbers::pi;
  CHECK(mid == Approx(-160).margin(1e-9));
}

TEST_CASE("synth finger: bending keeps the centreline length (near-isometric)", "[synth]") {
  MeshSeqParams p;
  p.frames = 20;
  p.periods = 1;
  p.twist_degrees = 0;
  MeshSequenceGenerator g(p);
  auto V = g.frame(10);  // full 90 deg bend
  const int top = static_cast<int>(V.rows()) - 1;
  // Tip centre of a quarter circle of length 4: at (2.546.., 0, 2.546..).
  CHECK(V(top, 0) == Approx(8 / std::numbers::pi));
  CHECK(V(top, 2) == Approx(8 / std::numbers::pi));
  CHECK(edge_length_change(g, V) < 0.5);
}

namespace {
MeshSeqParams bumps_params(int frames, int resolution, std::uint64_t seed) {
  MeshSeqParams p;
  p.kind = MeshSeqKind::bumps;
  p.frames = frames;
  p.resolution = resolution;
  p.seed = seed;
  return p;
}

// Whether any vertex lies inside two planted regions.
bool regions_overlap(const MeshSequenceGenerator& g) {
  const auto& r = g.regions();
  for (std::size_t a = 0; a < r.size(); ++a)
    for (std::size_t b = a + 1; b < r.size(); ++b)
      for (std::size_t v = 0; v < r[a].mask.size(); ++v)
        if (r[a].mask[v] && r[b].mask[v]) return true;
  return false;
}
}  // namespace

TEST_CASE("synth bumps: regions at two scales with recorded ground truth", "[synth]") {
  MeshSequenceGenerator g(bumps_params(10, 30, 3));
  REQUIRE(g.regions().size() == 6);
  int coarse = 0, fine = 0;
  for (const auto& r : g.regions()) (r.scale == 0 ? coarse : fine)++;
  CHECK(coarse == 2);
  CHECK(fine == 4);
  // Vertices outside every region never move; inside they move with the region's weight.
  auto V = g.frame(5);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    bool inside = false;
    for (const auto& r : g.regions()) inside = inside || r.mask[static_cast<std::size_t>(v)];
    if (!inside) REQUIRE(V.row(v) == g.rest().vertices.row(v));
  }
  for (std::size_t r = 0; r < g.regions().size(); ++r) {
    const auto& reg = g.regions()[r];
    double w = g.region_weights(5)[r];
    CHECK(V(reg.center, 2) == Approx(reg.height * w *
                                     std::pow(1 - std::pow((g.rest().vertices.row(reg.center) -
                                                            g.rest().vertices.row(reg.center))
                                                               .norm(),
                                                           2),
                                              2))
                                  .margin(0.02));
  }
  CHECK_FALSE(regions_overlap(g));
}

TEST_CASE(
    "synth bumps: --fine-regions adds fine regions apart, leaving the first ones as they were",
    "[synth]") {
  MeshSeqParams p = bumps_params(4, 40, 1);
  MeshSequenceGenerator base(p);
  p.fine_regions = 12;
  MeshSequenceGenerator many(p);
  REQUIRE(many.regions().size() == 14);
  int fine = 0;
  for (const auto& r : many.regions()) fine += r.scale;
  CHECK(fine == 12);
  for (std::size_t r = 0; r < base.regions().size(); ++r) {
    CHECK(many.regions()[r].center == base.regions()[r].center);
    CHECK(many.regions()[r].mask == base.regions()[r].mask);
    CHECK(many.region_weights(2)[r] == base.region_weights(2)[r]);
  }
  for (const auto& r : many.regions()) CHECK(std::count(r.mask.begin(), r.mask.end(), 1) > 10);
  CHECK_FALSE(regions_overlap(many));
  // More than fit apart: a usage error that says so, never overlapping regions.
  p.fine_regions = df::synth::kMaxFineRegions;
  CHECK_THROWS_WITH(MeshSequenceGenerator(p), Catch::Contains("no room for region 17 of 18"));
  p.fine_regions = df::synth::kMaxFineRegions + 1;
  CHECK_THROWS_AS(MeshSequenceGenerator(p), df::UsageError);
}

TEST_CASE("synth: frames are pure functions of (params, t); seeds change bumps", "[synth]") {
  MeshSeqParams p;
  p.kind = MeshSeqKind::bumps;
  p.frames = 5;
  p.sequences = 2;
  MeshSequenceGenerator a(p), b(p);
  CHECK(a.total_frames() == 10);
  for (int t = 9; t >= 0; --t) CHECK(a.frame(t) == b.frame(t));
  p.seed = 1;
  MeshSequenceGenerator c(p);
  CHECK(c.frame(3) != a.frame(3));
  p.kind = MeshSeqKind::flag;
  MeshSequenceGenerator f(p);
  CHECK(f.rest().vertices.rows() == 25 * 17);
  CHECK(f.frame(2).col(0) == f.rest().vertices.col(0));  // flag points move in y and z only
}

TEST_CASE("synth: invalid parameters are usage errors", "[synth]") {
  MeshSeqParams p;
  p.frames = 0;
  CHECK_THROWS_AS(MeshSequenceGenerator(p), df::UsageError);
  p.frames = 3;
  p.amplitude = std::nan("");
  CHECK_THROWS_AS(MeshSequenceGenerator(p), df::UsageError);
  CHECK_THROWS_AS(df::synth::mesh_seq_kind_from_name("blob"), df::UsageError);
}
