#include "render/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "core/error.h"

namespace df::render {
namespace {

// Viridis at t = 0, 1/9, ..., 1 (the 10-colour viridis palette, #440154 ... #fde725).
constexpr std::array<Rgb, 10> kViridis{{{0x44 / 255.0, 0x01 / 255.0, 0x54 / 255.0},
                                        {0x48 / 255.0, 0x28 / 255.0, 0x78 / 255.0},
                                        {0x3e / 255.0, 0x49 / 255.0, 0x89 / 255.0},
                                        {0x31 / 255.0, 0x68 / 255.0, 0x8e / 255.0},
                                        {0x26 / 255.0, 0x82 / 255.0, 0x8e / 255.0},
                                        {0x1f / 255.0, 0x9e / 255.0, 0x89 / 255.0},
                                        {0x35 / 255.0, 0xb7 / 255.0, 0x79 / 255.0},
                                        {0x6e / 255.0, 0xce / 255.0, 0x58 / 255.0},
                                        {0xb5 / 255.0, 0xde / 255.0, 0x2b / 255.0},
                                        {0xfd / 255.0, 0xe7 / 255.0, 0x25 / 255.0}}};
// Jet at t = 0, 1/8, 3/8, 5/8, 7/8, 1, given as 9 evenly spaced control colours.
constexpr std::array<Rgb, 9> kJet{{{0, 0, 0.5},
                                   {0, 0, 1},
                                   {0, 0.5, 1},
                                   {0, 1, 1},
                                   {0.5, 1, 0.5},
                                   {1, 1, 0},
                                   {1, 0.5, 0},
                                   {1, 0, 0},
                                   {0.5, 0, 0}}};

Rgb interpolate(std::span<const Rgb> stops, double t) {
  if (!(t > 0)) return stops.front();  // also NaN
  if (t >= 1) return stops.back();
  const double x = t * static_cast<double>(stops.size() - 1);
  const auto k = static_cast<std::size_t>(x);
  const double u = x - static_cast<double>(k);
  const Rgb& a = stops[k];
  const Rgb& b = stops[k + 1];
  return {a.r + u * (b.r - a.r), a.g + u * (b.g - a.g), a.b + u * (b.b - a.b)};
}

std::uint32_t channel(double v) {
  return static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

}  // namespace

Rgb parse_color(const std::string& text) {
  if (text == "white") return {1, 1, 1};
  if (text == "black") return {0, 0, 0};
  if (text == "grey" || text == "gray") return {0.5, 0.5, 0.5};
  if (text.size() == 7 && text[0] == '#' &&
      text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
    const auto v = std::stoul(text.substr(1), nullptr, 16);
    return {((v >> 16) & 255) / 255.0, ((v >> 8) & 255) / 255.0, (v & 255) / 255.0};
  }
  throw UsageError("bad colour '" + text + "' (expected white, black, grey or #rrggbb)");
}

std::uint32_t to_argb(const Rgb& c) {
  return 0xff000000u | (channel(c.r) << 16) | (channel(c.g) << 8) | channel(c.b);
}

Rgb from_argb(std::uint32_t p) {
  return {((p >> 16) & 255) / 255.0, ((p >> 8) & 255) / 255.0, (p & 255) / 255.0};
}

Colormap parse_colormap(const std::string& name) {
  if (name == "viridis") return Colormap::viridis;
  if (name == "jet") return Colormap::jet;
  throw UsageError("unknown colour map '" + name + "' (viridis or jet)");
}

Rgb map_color(Colormap map, double t) {
  switch (map) {
    case Colormap::jet:
      return interpolate(kJet, t);
    case Colormap::viridis:
      break;
  }
  return interpolate(kViridis, t);
}

}  // namespace df::render
