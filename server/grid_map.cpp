#include "server/grid_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "server/isolines.h"
#include "server/legend.h"

namespace lambert {
namespace {

constexpr Rgb kDark{40, 40, 40};
constexpr double kMargin = 24, kTitleHeight = 72, kFooterHeight = 56, kMapLegendGap = 24;
constexpr double kCellValueMin_px = 38;  // cells narrower than this show no number
constexpr int kLegendTicks = 12;

LegendStyle map_legend_style() { return {kBlack, kWhite, 14}; }

std::vector<std::string> map_legend_title(ScaleKind kind) { return legend_title("Illuminance", "lx", kind); }

TextStyle style(double size, Rgb colour, HAlign h, VAlign v, Weight w = Weight::Normal) {
  TextStyle t;
  t.size_px = size;
  t.colour = colour;
  t.h = h;
  t.v = v;
  t.weight = w;
  return t;
}

// Black text on light colours, white on dark ones (by the colour's luminance).
Rgb readable_on(Rgb c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b > 110 ? kBlack : kWhite; }

std::string summary(const GridValues& g) {
  const auto [lo, hi] = std::minmax_element(g.illuminance_lx.begin(), g.illuminance_lx.end());
  const double mean = std::accumulate(g.illuminance_lx.begin(), g.illuminance_lx.end(), 0.0) / g.illuminance_lx.size();
  char text[200];
  std::snprintf(text, sizeof text, "min %s lx   mean %s lx   max %s lx   U0 = min/mean = %.2f", tick_label(*lo).c_str(),
                tick_label(mean).c_str(), tick_label(*hi).c_str(), mean > 0 ? *lo / mean : 0.0);
  return text;
}

struct Box {
  double x0, y0, x1, y1;
  bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// Each level's line, and its value on the first of a few places along it (its middle segment, then
// the quarters, ...) where the label covers no label already placed.
void draw_contours(Canvas& canvas, const GridValues& g, const ColourScale& scale, const GridMapLayout& layout) {
  std::vector<Box> placed;
  for (double level : isolux_levels(g, scale)) {
    const std::vector<Segment2> segments = isolines(g.illuminance_lx, g.nu, g.nv, level);
    for (const Segment2& s : segments)
      canvas.line(layout.centre(s.a.x, s.a.y), layout.centre(s.b.x, s.b.y), kBlack, 1.6);
    const std::string label = tick_label(level);
    const TextStyle t = style(12, kBlack, HAlign::Centre, VAlign::Middle);
    const double half_w = text_width(label, t) / 2 + 3, half_h = 8;
    for (double f : {0.5, 0.25, 0.75, 0.125, 0.375, 0.625, 0.875}) {
      if (segments.empty()) break;
      const Segment2& s = segments[static_cast<std::size_t>(f * (segments.size() - 1))];
      const Point2 mid = layout.centre((s.a.x + s.b.x) / 2, (s.a.y + s.b.y) / 2);
      const Box box{mid.x - half_w, mid.y - half_h, mid.x + half_w, mid.y + half_h};
      if (std::any_of(placed.begin(), placed.end(), [&](const Box& b) { return b.overlaps(box); })) continue;
      placed.push_back(box);
      canvas.fill_rect({box.x0, box.y0}, {box.x1, box.y1}, kWhite);
      canvas.text(mid, label, t);
      break;
    }
  }
}

}  // namespace

GridMapLayout grid_map_layout(const GridValues& g, const ColourScale& scale) {
  const double legend = legend_width(scale, map_legend_title(scale.kind), map_legend_style());
  const double room_w = kGridMapWidth - 2 * kMargin - kMapLegendGap - legend;
  const double room_h = kGridMapHeight - kTitleHeight - kFooterHeight;
  const double aspect = g.cell_v / g.cell_u;  // cell height over width
  GridMapLayout layout;
  layout.cell_w = std::min(room_w / g.nu, room_h / (g.nv * aspect));
  layout.cell_h = layout.cell_w * aspect;
  layout.origin = {kMargin, kTitleHeight + (room_h + g.nv * layout.cell_h) / 2};
  return layout;
}

std::vector<double> isolux_levels(const GridValues& g, const ColourScale& scale) {
  const auto [lo, hi] = std::minmax_element(g.illuminance_lx.begin(), g.illuminance_lx.end());
  std::vector<double> levels;
  for (const Tick& t : scale_ticks(scale, kLegendTicks))
    if (t.value > *lo && t.value < *hi) levels.push_back(t.value);
  return levels;
}

Image draw_grid_map(const GridValues& g, ScaleKind kind) {
  const std::size_t n = static_cast<std::size_t>(g.nu) * static_cast<std::size_t>(g.nv);
  if (g.nu < 1 || g.nv < 1 || g.illuminance_lx.size() != n || !(g.cell_u > 0) || !(g.cell_v > 0))
    throw std::invalid_argument("grid map: " + g.name + " has " + std::to_string(g.illuminance_lx.size()) +
                                " values for " + std::to_string(g.nu) + " x " + std::to_string(g.nv) + " cells");
  const ColourScale scale = colour_scale(g.illuminance_lx, kind);
  const GridMapLayout layout = grid_map_layout(g, scale);
  Canvas canvas(kGridMapWidth, kGridMapHeight, kWhite);
  canvas.text({kMargin, 14}, g.name + ": illuminance on the probe grid", style(20, kBlack, HAlign::Left, VAlign::Top, Weight::Bold));
  char size[160];
  std::snprintf(size, sizeof size, "%d x %d points at cell centres, cells %s x %s %s (u to the right, v up)", g.nu, g.nv,
                tick_label(g.cell_u).c_str(), tick_label(g.cell_v).c_str(), g.unit.c_str());
  canvas.text({kMargin, 54}, size, style(13, kDark, HAlign::Left, VAlign::Baseline));

  const bool numbers = layout.cell_w >= kCellValueMin_px && layout.cell_h >= 18;
  for (int b = 0; b < g.nv; ++b)
    for (int a = 0; a < g.nu; ++a) {
      const double E = g.illuminance_lx[static_cast<std::size_t>(b) * g.nu + a];
      const Rgb colour = false_colour_ramp(scale.position(E));
      const Point2 c = layout.centre(a, b);
      canvas.fill_rect({c.x - layout.cell_w / 2, c.y - layout.cell_h / 2}, {c.x + layout.cell_w / 2, c.y + layout.cell_h / 2}, colour);
      if (numbers) canvas.text(c, tick_label(E), style(std::min(12.0, layout.cell_w / 4), readable_on(colour), HAlign::Centre, VAlign::Middle));
    }
  draw_contours(canvas, g, scale, layout);
  canvas.stroke_rect(layout.origin, {layout.origin.x + g.nu * layout.cell_w, layout.origin.y - g.nv * layout.cell_h}, kBlack, 1);
  canvas.text({kMargin, kGridMapHeight - 22.0}, summary(g), style(14, kBlack, HAlign::Left, VAlign::Baseline));
  const double legend_right = layout.origin.x + g.nu * layout.cell_w + kMapLegendGap +
                              legend_width(scale, map_legend_title(kind), map_legend_style());
  draw_legend(canvas, scale, map_legend_title(kind), {legend_right, layout.origin.y - g.nv * layout.cell_h},
              g.nv * layout.cell_h, map_legend_style());
  return canvas.pixels();
}

}  // namespace lambert
