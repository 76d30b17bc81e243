#include "render/canvas.h"

#include <cairo/cairo.h>

#include <algorithm>
#include <cstring>

#include "core/error.h"

namespace df::render {

Panel read_png(const std::filesystem::path& path) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    const std::string why = cairo_status_to_string(cairo_surface_status(s));
    cairo_surface_destroy(s);
    throw IOError("cannot read PNG: " + why, path.string());
  }
  cairo_surface_flush(s);
  Panel p{cairo_image_surface_get_width(s), cairo_image_surface_get_height(s), {}};
  p.pixels.resize(static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height));
  const unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  for (int y = 0; y < p.height; ++y)
    std::memcpy(p.pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(p.width),
                data + static_cast<std::ptrdiff_t>(y) * stride,
                static_cast<std::size_t>(p.width) * 4);
  cairo_surface_destroy(s);
  return p;
}

Canvas::Canvas(int width, int height, const Rgb& background) : width_(width), height_(height) {
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
  cr_ = cairo_create(surface_);
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS) {
    const std::string why = cairo_status_to_string(cairo_status(cr_));
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    throw Error("cannot create a " + std::to_string(width) + " x " + std::to_string(height) +
                " picture: " + why);
  }
  cairo_set_source_rgb(cr_, background.r, background.g, background.b);
  cairo_paint(cr_);
}

Canvas::~Canvas() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void Canvas::blit(const Panel& panel, int x, int y) {
  cairo_surface_flush(surface_);
  unsigned char* data = cairo_image_surface_get_data(surface_);
  const int stride = cairo_image_surface_get_stride(surface_);
  const int c0 = std::max(0, -x),
            c1 = std::min(panel.width, width_ - x);  // columns inside the picture
  for (int r = std::max(0, -y); r < panel.height && y + r < height_ && c0 < c1; ++r)
    std::memcpy(data + static_cast<std::ptrdiff_t>(y + r) * stride +
                    static_cast<std::ptrdiff_t>(x + c0) * 4,
                panel.pixels.data() +
                    static_cast<std::size_t>(r) * static_cast<std::size_t>(panel.width) +
                    static_cast<std::size_t>(c0),
                static_cast<std::size_t>(c1 - c0) * 4);
  cairo_surface_mark_dirty(surface_);
}

void Canvas::font(double size, bool bold) {
  cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size);
}

double Canvas::text_width(const std::string& s, double size, bool bold) {
  font(size, bold);
  cairo_text_extents_t e;
  cairo_text_extents(cr_, s.c_str(), &e);
  return e.x_advance;
}

void Canvas::text(const std::string& s, double x, double y, double size, int align,
                  const Rgb& color, bool bold) {
  font(size, bold);
  cairo_text_extents_t e;
  cairo_text_extents(cr_, s.c_str(), &e);
  cairo_font_extents_t fe;
  cairo_font_extents(cr_, &fe);
  const double left = align < 0 ? x : align == 0 ? x - e.x_advance / 2 : x - e.x_advance;
  const double baseline = y + (fe.ascent - fe.descent) / 2;
  cairo_set_source_rgb(cr_, color.r, color.g, color.b);
  cairo_move_to(cr_, left, baseline);
  cairo_show_text(cr_, s.c_str());
}

void Canvas::line(double x0, double y0, double x1, double y1, double width, const Rgb& color) {
  cairo_set_source_rgb(cr_, color.r, color.g, color.b);
  cairo_set_line_width(cr_, width);
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  cairo_move_to(cr_, x0, y0);
  cairo_line_to(cr_, x1, y1);
  cairo_stroke(cr_);
}

void Canvas::disc(double x, double y, double radius, const Rgb& color) {
  cairo_set_source_rgb(cr_, color.r, color.g, color.b);
  cairo_new_sub_path(cr_);
  cairo_arc(cr_, x, y, radius, 0, 6.283185307179586);
  cairo_fill(cr_);
}

void Canvas::rectangle(double x, double y, double w, double h, const Rgb& color,
                       double line_width) {
  cairo_set_source_rgb(cr_, color.r, color.g, color.b);
  cairo_rectangle(cr_, x, y, w, h);
  if (line_width > 0) {
    cairo_set_line_width(cr_, line_width);
    cairo_stroke(cr_);
  } else {
    cairo_fill(cr_);
  }
}

void Canvas::push_clip(double x, double y, double w, double h) {
  cairo_save(cr_);
  cairo_rectangle(cr_, x, y, w, h);
  cairo_clip(cr_);
}

void Canvas::pop_clip() {
  cairo_restore(cr_);
}

void Canvas::vertical_gradient(double x, double y, double w, double h, Colormap map) {
  cairo_pattern_t* g = cairo_pattern_create_linear(0, y + h, 0, y);
  const int stops = 64;
  for (int k = 0; k <= stops; ++k) {
    const double t = static_cast<double>(k) / stops;
    const Rgb c = map_color(map, t);
    cairo_pattern_add_color_stop_rgb(g, t, c.r, c.g, c.b);
  }
  cairo_set_source(cr_, g);
  cairo_rectangle(cr_, x, y, w, h);
  cairo_fill(cr_);
  cairo_pattern_destroy(g);
}

std::uint32_t Canvas::pixel(int x, int y) {
  cairo_surface_flush(surface_);
  std::uint32_t p;
  std::memcpy(&p,
              cairo_image_surface_get_data(surface_) +
                  static_cast<std::ptrdiff_t>(y) * cairo_image_surface_get_stride(surface_) + x * 4,
              4);
  return p;
}

void Canvas::write_png(const std::filesystem::path& path, const std::string& display_name) {
  cairo_surface_flush(surface_);
  const cairo_status_t st = cairo_surface_write_to_png(surface_, path.c_str());
  if (st != CAIRO_STATUS_SUCCESS)
    throw IOError(std::string("cannot write PNG: ") + cairo_status_to_string(st), display_name);
}

}  // namespace df::render
