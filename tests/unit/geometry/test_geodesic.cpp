#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numbers>

#include "core/error.h"
#include "geometry/geodesic_distance.h"

using df::geometry::HeatMethodDistance;

namespace {

// A planar n × n grid on [−1, 1]², each square split along alternating diagonals.
df::Mesh grid(int n) {
  df::Mesh m;
  m.vertices.resize(n * n, 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      m.vertices.row(y * n + x) << -1 + 2.0 * x / (n - 1), -1 + 2.0 * y / (n - 1), 0;
  m.faces.resize(2 * (n - 1) * (n - 1), 3);
  int f = 0;
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const int a = y * n + x, b = a + 1, c = a + n + 1, d = a + n;
      if ((x + y) % 2) {
        m.faces.row(f++) << a, b, c;
        m.faces.row(f++) << a, c, d;
      } else {
        m.faces.row(f++) << a, b, d;
        m.faces.row(f++) << b, c, d;
      }
    }
  return m;
}

// Unit icosphere: an icosahedron subdivided `levels` times, vertices pushed onto the sphere.
df::Mesh icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      return mid[key] = static_cast<int>(v.size() - 1);
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& [a, b, c] : f) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.push_back({a, ab, ca}), g.push_back({b, bc, ab}), g.push_back({c, ca, bc}),
          g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  df::Mesh m;
  m.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.vertices.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i)
    m.faces.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
  return m;
}

// Mean and max of |d − exact| / exact over vertices with exact > `skip`.
std::pair<double, double> relative_errors(const Eigen::VectorXd& d, const Eigen::VectorXd& exact,
                                          double skip) {
  double sum = 0, worst = 0;
  int n = 0;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (exact[i] > skip) {
      const double e = std::abs(d[i] - exact[i]) / exact[i];
      sum += e, worst = std::max(worst, e), ++n;
    }
  return {sum / n, worst};
}

}  // namespace

TEST_CASE("geodesics: distances on a plane are Euclidean", "[geometry][geodesic]") {
  const auto m = grid(41);
  const HeatMethodDistance heat(m.vertices, m.faces);
  for (int source : {20 * 41 + 20, 10 * 41 + 14}) {
    const Eigen::VectorXd d = heat.from(source);
    CHECK(d[source] == 0);
    Eigen::VectorXd exact(d.size());
    for (Eigen::Index i = 0; i < d.size(); ++i)
      exact[i] = (m.vertices.row(i) - m.vertices.row(source)).norm();
    const auto [mean, worst] = relative_errors(d, exact, 0.2);
    INFO("source " << source << ": mean relative error " << mean << ", max " << worst);
    CHECK(mean < 0.02);  // measured 0.017 and 0.018
    CHECK(worst < 0.1);  // measured 0.058 and 0.077 (near the boundary)
  }
}

TEST_CASE("geodesics: distances on a sphere follow great circles", "[geometry][geodesic]") {
  double previous = 1;
  for (int level : {3, 4}) {
    const auto m = icosphere(level);
    const HeatMethodDistance heat(m.vertices, m.faces);
    const Eigen::VectorXd d = heat.from(0);
    Eigen::VectorXd exact(d.size());
    for (Eigen::Index i = 0; i < d.size(); ++i)
      exact[i] = std::acos(std::clamp(m.vertices.row(i).dot(m.vertices.row(0)), -1.0, 1.0));
    const auto [mean, worst] = relative_errors(d, exact, 0.3);
    INFO("level " << level << " (" << m.vertices.rows() << " vertices): mean relative error "
                  << mean << ", max " << worst);
    CHECK(mean < 0.025);     // measured 0.018 (642 vertices) and 0.0099 (2,562)
    CHECK(worst < 0.08);     // measured 0.059 and 0.035
    CHECK(mean < previous);  // converges with resolution
    previous = mean;
    // The antipode is about π away.
    Eigen::Index far = 0;
    exact.maxCoeff(&far);
    CHECK(d[far] == Approx(std::numbers::pi).epsilon(0.05));
  }
}

TEST_CASE(
    "geodesics: normalized rows lie in [0, 1], nearly symmetric; other parts as the crow flies",
    "[geometry][geodesic]") {
  auto m = grid(9);
  // A second, disconnected copy shifted away.
  df::Mesh two;
  two.vertices.resize(2 * m.vertices.rows(), 3);
  two.vertices << m.vertices, m.vertices.rowwise() + Eigen::RowVector3d(5, 0, 0);
  two.faces.resize(2 * m.faces.rows(), 3);
  two.faces << m.faces, m.faces.array() + static_cast<int>(m.vertices.rows());
  df::geometry::GeodesicRows rows(two.vertices, two.faces);
  const auto n = m.vertices.rows();
  Eigen::MatrixXf D(2 * n, 2 * n);
  for (Eigen::Index i = 0; i < D.rows(); ++i) D.row(i) = rows.row(static_cast<int>(i)).transpose();
  // Rows are solved from each source, not symmetrised: d_ij and d_ji agree up to the heat
  // method's error (measured 0.067 of the diameter at worst on this coarse 9 × 9 grid, near its
  // boundary; the plane test above bounds the error per source at 0.1).
  CHECK((D - D.transpose()).cwiseAbs().maxCoeff() < 0.1);
  CHECK(D.diagonal().cwiseAbs().maxCoeff() < 1e-6);
  CHECK(D.maxCoeff() == 1);
  CHECK(D.minCoeff() >= 0);
  // Other parts are as far as the straight line: vertex 0 at (−1, −1) and its copy at (4, −1) are
  // 5 apart; the farthest pair is a corner of one grid and the far corner of the other, (−1, −1)
  // and (6, 1), √53 apart, which the sweeps from vertex 0 find.
  const double diameter = std::sqrt(53.0);
  CHECK(rows.diameter() == Approx(diameter).epsilon(1e-9));
  CHECK(rows.parts() == 2);
  CHECK(df::geometry::GeodesicRows(m.vertices, m.faces).parts() == 1);
  CHECK(D(0, n) == Approx(5 / diameter).epsilon(1e-6));
  CHECK(D(0, 2 * n - 1) == Approx(1).epsilon(1e-6));
  CHECK(D(2 * n - 1, 0) == Approx(1).epsilon(1e-6));
  // Within a part the distances stay geodesic: opposite corners of one grid are 2√2 apart.
  CHECK(D(0, n - 1) == Approx(2 * std::sqrt(2.0) / diameter).epsilon(0.05));
  HeatMethodDistance heat(two.vertices, two.faces);
  CHECK(std::isinf(heat.from(0)[n]));
  CHECK_THROWS_AS(heat.from(-1), df::InvalidInput);
  CHECK_THROWS_AS(HeatMethodDistance(two.vertices, df::Faces(0, 3)), df::InvalidInput);
}

TEST_CASE("geodesics: rows on demand are normalized by the swept diameter",
          "[geometry][geodesic]") {
  const auto m = grid(41);
  df::geometry::GeodesicRows rows(m.vertices, m.faces);
  // The plane [−1, 1]²: the diameter is the diagonal 2√2 (up to the heat method's error).
  CHECK(rows.diameter() == Approx(2 * std::sqrt(2.0)).epsilon(0.04));
  const int centre = 20 * 41 + 20;
  rows.prepare({centre, 0, centre});
  const Eigen::VectorXf& d = rows.row(centre);
  CHECK(d[centre] == 0);
  CHECK(d.maxCoeff() <= 1);
  // The corners are half the diameter away from the centre.
  CHECK(d[0] == Approx(0.5).epsilon(0.05));
  // Solving the same row again (another provider, no sweeps) gives the same numbers.
  df::geometry::GeodesicRows again(m.vertices, m.faces, rows.diameter());
  CHECK((again.row(centre) - d).cwiseAbs().maxCoeff() == 0);
  CHECK_THROWS_AS(df::geometry::GeodesicRows(m.vertices, m.faces, 0.0), df::InvalidInput);
}
