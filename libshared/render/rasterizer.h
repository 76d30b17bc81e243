// A z-buffer triangle rasteriser for one panel of a picture: no display, no GPU. Each pixel is
// the mean of supersample × supersample samples (anti-aliasing); each sample keeps the nearest
// triangle (depth test) and is shaded afterwards, once, with a directional light (Lambert plus a
// small Blinn highlight, two-sided so open surfaces look the same from both sides), flat (face
// normals) or smooth (interpolated area-weighted vertex normals), in a per-vertex colour.
// Deterministic: one panel is drawn by one thread in triangle order.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "io/mesh_io.h"
#include "render/camera.h"
#include "render/color.h"

namespace df::render {

struct Shading {
  bool smooth = true;
  /// Direction towards the light in view space (x right, y up, z towards the viewer).
  Eigen::Vector3d light = Eigen::Vector3d(-0.4, 0.5, 1.0).normalized();
  Rgb background{1, 1, 1};
  int supersample = 3;   ///< samples per pixel along each axis
  double margin = 0.05;  ///< empty border around the camera's fitted extent (fraction of the panel)
};

/// A w by h image in Cairo's ARGB32 layout, row-major, opaque.
struct Panel {
  int width = 0, height = 0;
  std::vector<std::uint32_t> pixels;
  std::uint32_t at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
};

/// Renders a triangle mesh into a w by h panel through `camera`.
/// @param V       #V by 3 positions (world units)
/// @param F       #F by 3 triangles
/// @param colors  #V per-vertex colours, or empty for `base` everywhere
Panel rasterize_mesh(const Vertices& V, const Faces& F, const std::vector<Rgb>& colors,
                     const Rgb& base, const Camera& camera, int w, int h, const Shading& shading);

}  // namespace df::render
