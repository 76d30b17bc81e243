#include "render/sheet.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace df::render {
namespace {

constexpr double kTitleSize = 16, kLabelSize = 13, kTickSize = 11;
constexpr int kPad = 8;

std::string tick_text(double v) {
  return fmt::format("{:.3g}", std::abs(v) < 1e-300 ? 0.0 : v);
}

}  // namespace

std::vector<double> bar_ticks(double lo, double hi) {
  std::vector<double> t;
  for (int k = 0; k <= 4; ++k) t.push_back(lo + (hi - lo) * k / 4.0);
  return t;
}

SheetLayout layout_sheet(const SheetSpec& s) {
  Canvas scratch(1, 1, s.background);  // for text metrics
  SheetLayout L;
  int row_label_w = 0;
  for (const auto& r : s.row_labels)
    row_label_w =
        std::max(row_label_w, static_cast<int>(std::ceil(scratch.text_width(r, kLabelSize))));
  L.left = kPad + (row_label_w ? row_label_w + kPad : 0);
  L.top = kPad;
  if (!s.title.empty()) {
    L.title_y = L.top + 10;
    L.top += 24;
  }
  if (!s.column_labels.empty()) {
    L.column_label_y = L.top + 8;
    L.top += 20;
  }
  const int grid_w = s.cols * s.panel_width + (s.cols - 1) * L.gap;
  const int grid_h = s.rows * s.panel_height + (s.rows - 1) * L.gap;
  int right = kPad;
  if (s.bar) {
    int label_w = static_cast<int>(std::ceil(scratch.text_width(s.bar->units, kTickSize)));
    int tick_w = 0;
    for (double v : bar_ticks(s.bar->lo, s.bar->hi))
      tick_w = std::max(tick_w,
                        static_cast<int>(std::ceil(scratch.text_width(tick_text(v), kTickSize))));
    L.bar_width = 16;
    L.bar_x = L.left + grid_w + 2 * kPad;
    const int bar_area = std::max(L.bar_width + 6 + tick_w, label_w);
    right = 2 * kPad + bar_area + kPad;
    L.bar_y = L.top + 22;
    L.bar_height = std::max(40, std::min(grid_h, 400) - 30);
    L.height = std::max(L.height, L.bar_y + L.bar_height + kPad);
  }
  L.width = L.left + grid_w + right;
  if (!s.title.empty())  // a title longer than the grid widens the picture rather than being cut
    L.width = std::max(
        L.width,
        L.left + static_cast<int>(std::ceil(scratch.text_width(s.title, kTitleSize, true))) + kPad);
  L.height = std::max(L.height, L.top + grid_h + kPad);
  return L;
}

void draw_sheet_frame(Canvas& c, const SheetSpec& s, const SheetLayout& L) {
  const Rgb ink = (s.background.r + s.background.g + s.background.b) / 3 < 0.5 ? Rgb{1, 1, 1}
                                                                               : Rgb{0.1, 0.1, 0.1};
  if (!s.title.empty()) c.text(s.title, L.left, L.title_y, kTitleSize, -1, ink, true);
  for (int k = 0; k < static_cast<int>(s.column_labels.size()) && k < s.cols; ++k) {
    const auto& label = s.column_labels[static_cast<std::size_t>(k)];
    const double w = c.text_width(label, kLabelSize),
                 room = s.panel_width - 4.0;  // shrink to fit the column
    c.text(label, L.panel_x(k, s) + s.panel_width / 2.0, L.column_label_y,
           w > room ? kLabelSize * room / w : kLabelSize, 0, ink);
  }
  for (int r = 0; r < static_cast<int>(s.row_labels.size()) && r < s.rows; ++r)
    c.text(s.row_labels[static_cast<std::size_t>(r)], kPad, L.panel_y(r, s) + s.panel_height / 2.0,
           kLabelSize, -1, ink);
  if (!s.bar) return;
  const auto& b = *s.bar;
  c.text(b.units, L.bar_x, L.bar_y - 12, kTickSize, -1, ink);
  c.vertical_gradient(L.bar_x, L.bar_y, L.bar_width, L.bar_height, b.map);
  c.rectangle(L.bar_x + 0.5, L.bar_y + 0.5, L.bar_width - 1, L.bar_height - 1, ink, 1);
  const auto ticks = bar_ticks(b.lo, b.hi);
  for (std::size_t k = 0; k < ticks.size(); ++k) {
    const double y = L.bar_y + L.bar_height -
                     L.bar_height * static_cast<double>(k) / static_cast<double>(ticks.size() - 1);
    c.line(L.bar_x + L.bar_width, y, L.bar_x + L.bar_width + 4, y, 1, ink);
    c.text(tick_text(ticks[k]), L.bar_x + L.bar_width + 6, y, kTickSize, -1, ink);
  }
}

}  // namespace df::render
