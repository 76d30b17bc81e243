// Colours of the pictures: RGB triples, named and #rrggbb colours, and the colour maps that turn a
// per-vertex scalar (error, deformation magnitude) into a colour.
#pragma once

#include <cstdint>
#include <string>

namespace df::render {

/// A colour with channels in [0, 1].
struct Rgb {
  double r = 0, g = 0, b = 0;
};

/// "white", "black", "grey"/"gray", "none" is not a colour; "#rrggbb" hex. UsageError otherwise.
Rgb parse_color(const std::string& text);

/// Opaque pixel in Cairo's ARGB32 layout (0xAARRGGBB, alpha 255), channels rounded.
std::uint32_t to_argb(const Rgb& c);
/// The colour of an opaque ARGB32 pixel.
Rgb from_argb(std::uint32_t pixel);

enum class Colormap {
  viridis,  ///< perceptually uniform, dark blue -> yellow (matplotlib's default)
  jet,      ///< dark blue -> cyan -> yellow -> dark red (the papers' error maps)
};
/// "viridis" or "jet"; UsageError otherwise.
Colormap parse_colormap(const std::string& name);

/// The colour of t in [0, 1] (clamped; NaN maps to 0): piecewise-linear between the map's
/// control colours, exactly the first at t <= 0 and the last at t >= 1.
Rgb map_color(Colormap map, double t);

}  // namespace df::render
