#include "server/legend.h"

#include <algorithm>
#include <cmath>

namespace lambert {
namespace {

constexpr double kPad = 8, kTickLength = 5, kLabelGap = 4, kBarWidth = 16;
constexpr double kTickSpacing_em = 1.6;  // labels at least this many font sizes apart

TextStyle label_style(const LegendStyle& style, HAlign h, VAlign v) {
  TextStyle t;
  t.size_px = style.font_px;
  t.colour = style.text;
  t.h = h;
  t.v = v;
  return t;
}

constexpr double kLineSpacing_em = 1.3;

// From the panel's top to the bar's: the title's lines and half a line of space.
double title_height(std::size_t lines, const LegendStyle& style) { return (lines + 0.5) * kLineSpacing_em * style.font_px; }

}  // namespace

double LegendBar::y_of(const ColourScale& scale, double v) const {
  return top_left.y + height - scale.position(v) * height;
}

std::vector<std::string> legend_title(const std::string& quantity, const std::string& unit, ScaleKind kind) {
  return {quantity + " (" + unit + ")", kind == ScaleKind::Log ? "log scale" : "linear scale"};
}

double legend_width(const ColourScale& scale, const std::vector<std::string>& title, const LegendStyle& style) {
  double labels = 0;
  const TextStyle t = label_style(style, HAlign::Left, VAlign::Middle);
  for (const Tick& tick : scale_ticks(scale, 12)) labels = std::max(labels, text_width(tick.label, t));
  double titles = 0;
  for (const std::string& line : title) titles = std::max(titles, text_width(line, t));
  return std::max(kBarWidth + kTickLength + kLabelGap + labels, titles) + 2 * kPad;
}

LegendBar legend_bar(const ColourScale& scale, const std::vector<std::string>& title, Point2 top_right, double height,
                     const LegendStyle& style) {
  const double width = legend_width(scale, title, style);
  LegendBar bar;
  // On whole pixels, so that each row of the ramp fills one row of pixels.
  bar.top_left = {std::round(top_right.x - width + kPad), std::round(top_right.y + kPad + title_height(title.size(), style))};
  bar.width = kBarWidth;
  bar.height = std::max(1.0, std::round(height - 2 * kPad - title_height(title.size(), style)));
  return bar;
}

LegendBar draw_legend(Canvas& canvas, const ColourScale& scale, const std::vector<std::string>& title, Point2 top_right,
                      double height, const LegendStyle& style) {
  const double width = legend_width(scale, title, style);
  const Point2 top_left{top_right.x - width, top_right.y};
  canvas.fill_rect(top_left, {top_right.x, top_right.y + height}, style.panel);
  for (std::size_t k = 0; k < title.size(); ++k)
    canvas.text({top_left.x + kPad, top_left.y + kPad + k * kLineSpacing_em * style.font_px}, title[k],
                label_style(style, HAlign::Left, VAlign::Top));

  const LegendBar bar = legend_bar(scale, title, top_right, height, style);
  // One-pixel rows of the ramp, the bottom row at position 0 and the top row at 1.
  const int rows = std::max(1, static_cast<int>(std::lround(bar.height)));
  for (int r = 0; r < rows; ++r) {
    const double t = rows > 1 ? static_cast<double>(rows - 1 - r) / (rows - 1) : 1.0;
    canvas.fill_rect({bar.top_left.x, bar.top_left.y + r}, {bar.top_left.x + bar.width, bar.top_left.y + r + 1},
                     false_colour_ramp(t));
  }
  const int max_ticks = std::max(2, static_cast<int>(bar.height / (kTickSpacing_em * style.font_px)) + 1);
  for (const Tick& tick : scale_ticks(scale, max_ticks)) {
    const double y = bar.y_of(scale, tick.value);
    const double x = bar.top_left.x + bar.width;
    canvas.line({x, y}, {x + kTickLength, y}, style.text, 1.5);
    canvas.text({x + kTickLength + kLabelGap, y}, tick.label, label_style(style, HAlign::Left, VAlign::Middle));
  }
  return bar;
}

}  // namespace lambert
