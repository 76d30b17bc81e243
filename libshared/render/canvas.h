// A picture being composed with Cairo (anti-aliased lines, dots and text, PNG encoding): panels
// from the rasteriser are copied in, captions, colour bars and stick figures are drawn on top.
// No display is involved (an image surface in memory).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "render/color.h"
#include "render/rasterizer.h"

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace df::render {

/// Reads a PNG file into ARGB32 pixels (tests compare pictures with it). IOError on failure.
Panel read_png(const std::filesystem::path& path);

class Canvas {
 public:
  /// A width by height picture filled with `background`.
  Canvas(int width, int height, const Rgb& background);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }

  /// Copies a panel with its top-left corner at (x, y).
  void blit(const Panel& panel, int x, int y);
  /// Text centred vertically on y; `align` −1 left of x starts, 0 centred on x, 1 ends at x.
  void text(const std::string& s, double x, double y, double size, int align, const Rgb& color = {},
            bool bold = false);
  /// Width of `s` in pixels at `size`.
  double text_width(const std::string& s, double size, bool bold = false);
  void line(double x0, double y0, double x1, double y1, double width, const Rgb& color);
  void disc(double x, double y, double radius, const Rgb& color);
  void rectangle(double x, double y, double w, double h, const Rgb& color, double line_width = 0);
  /// Restricts drawing to a rectangle until pop_clip() (a panel: nothing spills into the next).
  void push_clip(double x, double y, double w, double h);
  void pop_clip();
  /// A w by h rectangle whose colour runs through `map` from t = 0 at the bottom to 1 at the top.
  void vertical_gradient(double x, double y, double w, double h, Colormap map);

  /// The pixel at (x, y), ARGB32.
  std::uint32_t pixel(int x, int y);
  /// Writes the picture as PNG to `path` (the caller makes that atomic). IOError on failure.
  void write_png(const std::filesystem::path& path, const std::string& display_name);

 private:
  void font(double size, bool bold);
  int width_, height_;
  cairo_surface_t* surface_;
  cairo_t* cr_;
};

}  // namespace df::render
