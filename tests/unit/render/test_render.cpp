#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "apps/render_mesh.h"
#include "core/error.h"
#include "helpers.h"
#include "io/file_header.h"
#include "io/h5.h"
#include "io/skeleton_file.h"
#include "render/camera.h"
#include "render/canvas.h"
#include "render/color.h"
#include "render/rasterizer.h"
#include "render/sheet.h"

using namespace df::render;
using namespace df::apps;

namespace {

// Axis-aligned box [lo, hi]^3 as 12 triangles.
df::Mesh box(double lo, double hi) {
  df::Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.vertices.row(i) << (i & 1 ? hi : lo), (i & 2 ? hi : lo), (i & 4 ? hi : lo);
  m.faces.resize(12, 3);
  m.faces << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4,
      6, 1, 3, 5, 3, 7, 5;
  return m;
}

// Torus (radii 1 and 0.35) of nu × nv quads split into triangles.
df::Mesh torus(int nu, int nv) {
  df::Mesh m;
  m.vertices.resize(nu * nv, 3);
  m.faces.resize(2 * nu * nv, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      m.vertices.row(i * nv + j) << (1 + 0.35 * std::cos(v)) * std::cos(u), 0.35 * std::sin(v),
          (1 + 0.35 * std::cos(v)) * std::sin(u);
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      m.faces.row(2 * a) << a, b, c;
      m.faces.row(2 * a + 1) << a, c, d;
    }
  return m;
}

// Bounding box of the pixels that differ from `background`.
struct PixelBox {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
};
PixelBox covered(const Panel& p, std::uint32_t background) {
  PixelBox b;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x)
      if (p.at(x, y) != background)
        b.x0 = std::min(b.x0, x), b.x1 = std::max(b.x1, x), b.y0 = std::min(b.y0, y),
        b.y1 = std::max(b.y1, y);
  return b;
}

double channel_distance(const Rgb& a, const Rgb& b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

}  // namespace

TEST_CASE("render: a unit cube from the front covers the fitted pixel box", "[render]") {
  const auto cube = box(0, 1);
  Camera cam(parse_view("front", "y"));
  cam.include(cube.vertices);
  Shading s;
  s.margin = 0.05;
  for (int ss : {1, 3}) {
    s.supersample = ss;
    const Panel p =
        rasterize_mesh(cube.vertices, cube.faces, {}, {0.7, 0.7, 0.7}, cam, 200, 160, s);
    // The 1 x 1 face fills the smaller side less the margins: 160 − 2·8 = 144 pixels, centred.
    const PixelBox b = covered(p, to_argb(s.background));
    CHECK(std::abs(b.x0 - 28) <= 1);
    CHECK(std::abs(b.x1 + 1 - 172) <= 1);
    CHECK(std::abs(b.y0 - 8) <= 1);
    CHECK(std::abs(b.y1 + 1 - 152) <= 1);
    CHECK(p.at(100, 80) != to_argb(s.background));  // filled inside, not just outlined
  }
}

TEST_CASE("render: views and the camera fit", "[render]") {
  Camera side(parse_view("side", "y"));
  CHECK((side.to_view({1, 0, 0}) - Eigen::Vector3d(0, 0, 1)).norm() <
        1e-12);  // +x faces the viewer
  Camera top(parse_view("top", "y"));
  CHECK((top.to_view({0, 1, 0}) - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);
  Camera zup(parse_view("front", "z"));
  CHECK((zup.to_view({0, 0, 1}) - Eigen::Vector3d(0, 1, 0)).norm() < 1e-12);   // z is up on screen
  CHECK((zup.to_view({0, -1, 0}) - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);  // looking from −y
  Camera oblique(parse_view("30,20", "y"));
  CHECK((oblique.rotation() * oblique.rotation().transpose() - Eigen::Matrix3d::Identity()).norm() <
        1e-12);
  CHECK(oblique.rotation().determinant() == Approx(1));
  CHECK_THROWS_AS(parse_view("diagonal", "y"), df::UsageError);
  CHECK_THROWS_AS(parse_view("10,95", "y"), df::UsageError);
  CHECK_THROWS_AS(parse_view("front", "x"), df::UsageError);
}

TEST_CASE("render: the nearer triangle hides the farther one, whatever the drawing order",
          "[render]") {
  // Two squares overlapping on screen: red at z = 1 (near), blue at z = 0.
  df::Vertices V(8, 3);
  V << 0, 0, 1, 2, 0, 1, 2, 2, 1, 0, 2, 1,  // red
      1, 1, 0, 3, 1, 0, 3, 3, 0, 1, 3, 0;   // blue, shifted
  std::vector<Rgb> colors(8, {0, 0, 1});
  for (int i = 0; i < 4; ++i) colors[static_cast<std::size_t>(i)] = {1, 0, 0};
  df::Faces red_first(4, 3), blue_first(4, 3);
  red_first << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7;
  blue_first << 4, 5, 6, 4, 6, 7, 0, 1, 2, 0, 2, 3;
  Camera cam(parse_view("front", "y"));
  cam.include(V);
  Shading s;
  s.light = Eigen::Vector3d::UnitZ();
  for (const auto& F : {red_first, blue_first}) {
    const Panel p = rasterize_mesh(V, F, colors, {}, cam, 120, 120, s);
    // The overlap (world x, y in 1..2) is at panel (60 ± 27, 60 ± 27); sample its centre.
    const Eigen::Vector3d c = cam.to_panel({1.5, 1.5, 0}, 120, 120, s.margin);
    const Rgb px = from_argb(p.at(static_cast<int>(c.x()), static_cast<int>(c.y())));
    CHECK(px.r > 0.9);
    CHECK(px.b < 0.3);
    const Eigen::Vector3d only_blue = cam.to_panel({2.7, 2.7, 0}, 120, 120, s.margin);
    CHECK(from_argb(p.at(static_cast<int>(only_blue.x()), static_cast<int>(only_blue.y()))).b >
          0.9);
  }
}

TEST_CASE("render: colour maps have exact ends and clamp", "[render]") {
  const Rgb v0 = map_color(Colormap::viridis, 0), v1 = map_color(Colormap::viridis, 1);
  CHECK(to_argb(v0) == 0xff440154u);
  CHECK(to_argb(v1) == 0xfffde725u);
  CHECK(to_argb(map_color(Colormap::viridis, -3)) == to_argb(v0));
  CHECK(to_argb(map_color(Colormap::viridis, 7)) == to_argb(v1));
  CHECK(to_argb(map_color(Colormap::viridis, std::nan(""))) == to_argb(v0));
  CHECK(to_argb(map_color(Colormap::jet, 0)) == to_argb({0, 0, 0.5}));
  CHECK(to_argb(map_color(Colormap::jet, 1)) == to_argb({0.5, 0, 0}));
  CHECK(to_argb(map_color(Colormap::jet, 0.5)) == to_argb({0.5, 1, 0.5}));
  // Monotone in "lightness" for viridis: green channel rises along the map.
  for (int k = 0; k < 10; ++k)
    CHECK(map_color(Colormap::viridis, k / 10.0).g <
          map_color(Colormap::viridis, (k + 1) / 10.0).g);
  CHECK_THROWS_AS(parse_colormap("rainbow"), df::UsageError);
  CHECK(to_argb(parse_color("#ff8000")) == 0xffff8000u);
  CHECK_THROWS_AS(parse_color("#ff80"), df::UsageError);
}

TEST_CASE(
    "render: the colour bar runs from the map's first colour at the bottom to its last at the top",
    "[render]") {
  SheetSpec spec;
  spec.rows = 2, spec.cols = 3, spec.panel_width = 100, spec.panel_height = 100;
  spec.bar = ColorBar{Colormap::jet, 0, 0.25, "error"};
  spec.column_labels = {"a", "b", "c"};
  spec.row_labels = {"one", "two"};
  const SheetLayout L = layout_sheet(spec);
  CHECK(L.bar_x > L.panel_x(2, spec) + spec.panel_width);  // right of the grid
  CHECK(L.width >= L.bar_x + L.bar_width);
  CHECK(L.height >= L.bar_y + L.bar_height);
  Canvas c(L.width, L.height, spec.background);
  draw_sheet_frame(c, spec, L);
  const int x = L.bar_x + L.bar_width / 2;
  auto t_at = [&](int y) {
    return (L.bar_y + L.bar_height - (y + 0.5)) / L.bar_height;
  };  // pixel centre
  for (int y : {L.bar_y + L.bar_height - 2, L.bar_y + 1, L.bar_y + L.bar_height / 2})
    CHECK(channel_distance(from_argb(c.pixel(x, y)), map_color(Colormap::jet, t_at(y))) < 0.03);
  CHECK(channel_distance(from_argb(c.pixel(x, L.bar_y + L.bar_height - 2)),
                         map_color(Colormap::jet, 0)) < 0.05);
  CHECK(channel_distance(from_argb(c.pixel(x, L.bar_y + 1)), map_color(Colormap::jet, 1)) < 0.05);
  // Tick labels are drawn to the right of the bar.
  int ink = 0;
  for (int y = L.bar_y; y < L.bar_y + L.bar_height; ++y)
    for (int xx = L.bar_x + L.bar_width + 6; xx < L.width; ++xx)
      ink += c.pixel(xx, y) != 0xffffffffu;
  CHECK(ink > 50);
  CHECK(bar_ticks(0, 0.25) == std::vector<double>{0, 0.0625, 0.125, 0.1875, 0.25});
}

TEST_CASE("render: a title longer than the grid widens the sheet instead of being cut",
          "[render]") {
  SheetSpec spec;
  spec.rows = 1, spec.cols = 2, spec.panel_width = 60, spec.panel_height = 60;
  spec.row_labels = {"one"};
  const SheetLayout plain = layout_sheet(spec);
  spec.title = "a title that is clearly much longer than two panels of sixty pixels";
  const SheetLayout L = layout_sheet(spec);
  Canvas scratch(1, 1, spec.background);
  CHECK(L.width > plain.width);
  CHECK(L.width >= L.left + scratch.text_width(spec.title, 16, true));
  CHECK(L.left == plain.left);  // the panels stay where they were
  spec.title = "short";
  CHECK(layout_sheet(spec).width == plain.width);  // a title that fits changes nothing
}

// The golden picture: a torus coloured by height, oblique view, smooth shading, no text (fonts
// differ between machines). Regenerate only on purpose: `make update-golden` (sets
// DF_UPDATE_GOLDEN=1 for this test) and review the new PNG.
TEST_CASE("render: golden picture of a coloured torus", "[render][golden]") {
  const auto t = torus(32, 16);
  std::vector<Rgb> colors;
  for (Eigen::Index i = 0; i < t.vertices.rows(); ++i)
    colors.push_back(map_color(Colormap::viridis, (t.vertices(i, 1) + 0.35) / 0.7));
  Camera cam(parse_view("30,35", "y"));
  cam.include(t.vertices);
  const Panel p = rasterize_mesh(t.vertices, t.faces, colors, {}, cam, 160, 120, Shading{});
  const std::filesystem::path golden =
      std::filesystem::path(DF_SOURCE_DIR) / "tests/unit/render/golden/torus.png";
  if (std::getenv("DF_UPDATE_GOLDEN")) {
    Canvas c(p.width, p.height, {1, 1, 1});
    c.blit(p, 0, 0);
    c.write_png(golden, golden.string());
    WARN("rewrote " << golden);
  }
  const Panel g = read_png(golden);
  REQUIRE(g.width == p.width);
  REQUIRE(g.height == p.height);
  // Tolerance for floating-point differences between compilers / CPUs: channels within 8/255
  // on all but 0.5% of the pixels, and a mean difference below 0.5/255.
  int far = 0;
  double sum = 0;
  for (std::size_t k = 0; k < p.pixels.size(); ++k) {
    const double d = channel_distance(from_argb(p.pixels[k]), from_argb(g.pixels[k])) * 255;
    far += d > 8;
    sum += d;
  }
  CHECK(far <= static_cast<int>(p.pixels.size() / 200));
  CHECK(sum / static_cast<double>(p.pixels.size()) < 0.5);
}

TEST_CASE("render: stick figures of a hand-written skeleton file", "[render]") {
  df::test::TempDir tmp;
  // A 5-joint figure (hips, chest, head, left hand, right hand), 2 sequences of 3 frames; the
  // left hand rises over the frames.
  df::io::SkeletonFile s;
  s.frames = 6, s.joints = 5, s.dims = 3;
  for (std::size_t t = 0; t < 6; ++t) {
    const float lift = 0.2f * static_cast<float>(t % 3);
    const float pose[15] = {0, 0, 0, 0, 1, 0, 0, 1.5f, 0, -0.6f, 0.6f + lift, 0, 0.6f, 0.6f, 0};
    s.poses.insert(s.poses.end(), pose, pose + 15);
  }
  s.offsets = {0, 3, 6};
  s.sequence_names = {"wave-a", "wave-b"};
  s.labels = {0, 0};
  s.class_names = {"wave"};
  s.parents = {-1, 0, 1, 1, 1};
  s.joint_names = {"hips", "chest", "head", "left_hand", "right_hand"};
  {
    df::h5::File f(tmp / "skel.h5", df::h5::File::Mode::create);
    df::io::write_header(f, "skeleton");
    df::io::write_skeleton_data(f, s);
  }
  const auto back = df::io::read_skeleton_file(tmp / "skel.h5");
  CHECK(back.poses == s.poses);
  CHECK(back.parents == s.parents);

  RenderOptions opt;
  opt.inputs = {tmp / "skel.h5"};
  opt.output = tmp / "skel.png";
  opt.width = opt.height = 100;
  render_mesh(opt, {});
  const Panel p = read_png(opt.output);
  // 2 rows (sequences) of 3 frames: the picture is wider than 3 panels and taller than 2.
  CHECK(p.width > 300);
  CHECK(p.height > 200);
  // Joints are orange dots: count strongly orange pixels, and blue (left) and red (right) bones.
  int orange = 0, blue = 0, red = 0;
  for (auto px : p.pixels) {
    const Rgb c = from_argb(px);
    orange += c.r > 0.85 && c.g > 0.4 && c.g < 0.7 && c.b < 0.25;
    blue += c.b > 0.6 && c.r < 0.3;
    red += c.r > 0.65 && c.g < 0.3 && c.b < 0.3;
  }
  CHECK(orange > 6 * 5 * 4);  // 6 panels × 5 joints, several pixels each
  CHECK(blue > 6 * 10);
  CHECK(red > 6 * 10);

  // One sequence, one frame: a single panel.
  opt.sequences = {"wave-b"};
  opt.frames = "2";
  opt.output = tmp / "one.png";
  render_mesh(opt, {});
  CHECK(read_png(opt.output).width < 250);
  opt.frames = "3";  // out of range in a 3-frame sequence
  CHECK_THROWS_AS(render_mesh(opt, {}), df::UsageError);
  opt.frames.clear();
  opt.color = "deformation";  // a valid colouring for meshes, not for skeletons
  CHECK(df::test::error_message([&] {
          render_mesh(opt, {});
        }).find("skeleton files are drawn without") != std::string::npos);
}
