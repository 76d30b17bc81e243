#include "render/rasterizer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace df::render {
namespace {

// The G-buffer of the samples: nearest triangle, its depth and two barycentric coordinates.
struct Samples {
  int width, height;
  std::vector<float> depth, b1, b2;
  std::vector<std::int32_t> triangle;
  Samples(int w, int h)
      : width(w),
        height(h),
        depth(static_cast<std::size_t>(w) * static_cast<std::size_t>(h),
              -std::numeric_limits<float>::infinity()),
        b1(depth.size()),
        b2(depth.size()),
        triangle(depth.size(), -1) {}
};

// Screen position (samples) and depth of every vertex.
std::vector<Eigen::Vector3d> project(const Vertices& V, const Camera& camera, int w, int h,
                                     const Shading& s) {
  std::vector<Eigen::Vector3d> P(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    Eigen::Vector3d p = camera.to_panel(V.row(i).transpose(), w, h, s.margin);
    P[static_cast<std::size_t>(i)] = {p.x() * s.supersample, p.y() * s.supersample, p.z()};
  }
  return P;
}

void rasterize_triangles(const std::vector<Eigen::Vector3d>& P, const Faces& F, Samples& g) {
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d& a = P[static_cast<std::size_t>(F(f, 0))];
    const Eigen::Vector3d& b = P[static_cast<std::size_t>(F(f, 1))];
    const Eigen::Vector3d& c = P[static_cast<std::size_t>(F(f, 2))];
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (!(std::abs(area) > 1e-12)) continue;  // degenerate on screen (or NaN)
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 =
        std::min(g.width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 =
        std::min(g.height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    const double inv = 1.0 / area;
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        // Barycentric coordinates from the edge functions (signed areas over the triangle's).
        const double l0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) * inv;
        const double l1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) * inv;
        const double l2 = 1.0 - l0 - l1;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const auto z = static_cast<float>(l0 * a.z() + l1 * b.z() + l2 * c.z());
        const std::size_t k = static_cast<std::size_t>(y) * static_cast<std::size_t>(g.width) +
                              static_cast<std::size_t>(x);
        if (z > g.depth[k]) {
          g.depth[k] = z;
          g.triangle[k] = static_cast<std::int32_t>(f);
          g.b1[k] = static_cast<float>(l1);
          g.b2[k] = static_cast<float>(l2);
        }
      }
    }
  }
}

// View-space face normals (unnormalised, area-weighted) and, for smooth shading, vertex normals.
void normals(const Vertices& V, const Faces& F, const Camera& camera, bool smooth,
             std::vector<Eigen::Vector3d>& face_n, std::vector<Eigen::Vector3d>& vertex_n) {
  face_n.resize(static_cast<std::size_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(),
                          c = V.row(F(f, 2)).transpose();
    face_n[static_cast<std::size_t>(f)] = camera.rotation() * (b - a).cross(c - a);
  }
  if (!smooth) return;
  vertex_n.assign(static_cast<std::size_t>(V.rows()), Eigen::Vector3d::Zero());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      vertex_n[static_cast<std::size_t>(F(f, k))] += face_n[static_cast<std::size_t>(f)];
}

Rgb shade(Eigen::Vector3d n, const Rgb& base, const Eigen::Vector3d& light) {
  const double len = n.norm();
  if (!(len > 0)) return {base.r * 0.35, base.g * 0.35, base.b * 0.35};
  n /= len;
  if (n.z() < 0) n = -n;  // two-sided
  const double diffuse = std::max(0.0, n.dot(light));
  const Eigen::Vector3d half = (light + Eigen::Vector3d::UnitZ()).normalized();
  const double specular = 0.2 * std::pow(std::max(0.0, n.dot(half)), 40.0);
  const double k = 0.35 + 0.65 * diffuse;
  return {base.r * k + specular, base.g * k + specular, base.b * k + specular};
}

}  // namespace

Panel rasterize_mesh(const Vertices& V, const Faces& F, const std::vector<Rgb>& colors,
                     const Rgb& base, const Camera& camera, int w, int h, const Shading& shading) {
  const int ss = std::max(1, shading.supersample);
  Samples g(w * ss, h * ss);
  rasterize_triangles(project(V, camera, w, h, shading), F, g);
  std::vector<Eigen::Vector3d> face_n, vertex_n;
  normals(V, F, camera, shading.smooth, face_n, vertex_n);
  const Eigen::Vector3d light = shading.light.normalized();

  Panel out{w, h,
            std::vector<std::uint32_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h))};
  const double n_samples = ss * ss;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Rgb sum;
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          const std::size_t k =
              static_cast<std::size_t>(y * ss + sy) * static_cast<std::size_t>(g.width) +
              static_cast<std::size_t>(x * ss + sx);
          Rgb c = shading.background;
          if (const int f = g.triangle[k]; f >= 0) {
            const double l1 = g.b1[k], l2 = g.b2[k], l0 = 1.0 - l1 - l2;
            const int i0 = F(f, 0), i1 = F(f, 1), i2 = F(f, 2);
            const Eigen::Vector3d n =
                shading.smooth ? Eigen::Vector3d(l0 * vertex_n[static_cast<std::size_t>(i0)] +
                                                 l1 * vertex_n[static_cast<std::size_t>(i1)] +
                                                 l2 * vertex_n[static_cast<std::size_t>(i2)])
                               : face_n[static_cast<std::size_t>(f)];
            Rgb albedo = base;
            if (!colors.empty()) {
              const Rgb &c0 = colors[static_cast<std::size_t>(i0)],
                        &c1 = colors[static_cast<std::size_t>(i1)],
                        &c2 = colors[static_cast<std::size_t>(i2)];
              albedo = {l0 * c0.r + l1 * c1.r + l2 * c2.r, l0 * c0.g + l1 * c1.g + l2 * c2.g,
                        l0 * c0.b + l1 * c1.b + l2 * c2.b};
            }
            c = shade(n, albedo, light);
          }
          sum.r += c.r, sum.g += c.g, sum.b += c.b;
        }
      out.pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                 static_cast<std::size_t>(x)] =
          to_argb({sum.r / n_samples, sum.g / n_samples, sum.b / n_samples});
    }
  return out;
}

}  // namespace df::render
