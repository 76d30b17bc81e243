// The layout of a contact sheet: a grid of equal panels (one row per input or sequence, one
// column per selected frame) with an optional title, row and column captions, and a colour bar
// with tick labels and units at the right.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "render/canvas.h"
#include "render/color.h"

namespace df::render {

struct ColorBar {
  Colormap map = Colormap::viridis;
  double lo = 0, hi = 1;  ///< the values at the bottom and the top
  std::string units;      ///< shown above the bar
};

struct SheetSpec {
  int rows = 1, cols = 1;
  int panel_width = 320, panel_height = 320;
  std::string title;
  std::vector<std::string> row_labels;     ///< empty, or one per row
  std::vector<std::string> column_labels;  ///< empty, or one per column
  std::optional<ColorBar> bar;
  Rgb background{1, 1, 1};
};

/// Where everything goes, in pixels of the whole picture.
struct SheetLayout {
  int width = 0, height = 0;
  int left = 0, top = 0;  ///< top-left corner of the first panel
  int gap = 4;            ///< between panels
  int title_y = 0, column_label_y = 0;
  int bar_x = 0, bar_y = 0, bar_width = 0, bar_height = 0;  ///< the colour ramp itself
  int panel_x(int col, const SheetSpec& s) const { return left + col * (s.panel_width + gap); }
  int panel_y(int row, const SheetSpec& s) const { return top + row * (s.panel_height + gap); }
};

/// Computes the layout (text widths measured with Cairo's font metrics).
SheetLayout layout_sheet(const SheetSpec& spec);

/// Draws the title, captions and colour bar (the panels are drawn by the caller).
void draw_sheet_frame(Canvas& canvas, const SheetSpec& spec, const SheetLayout& layout);

/// Tick values for a colour bar from lo to hi: 5 evenly spaced values.
std::vector<double> bar_ticks(double lo, double hi);

}  // namespace df::render
