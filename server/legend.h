// The false-colour legend drawn on Lambert's pictures: a vertical bar of the ramp (low at the
// bottom), ticks at scale_ticks' values with their labels, and a title naming the quantity, its
// unit and the scale ("Illuminance (lx)" over "log scale").
#pragma once

#include <string>
#include <vector>

#include "server/canvas.h"
#include "server/colour_scale.h"

namespace lambert {

struct LegendStyle {
  Rgb text{255, 255, 255};
  Rgb panel{0, 0, 0};  // the panel behind the legend
  double font_px = 13;
};

// Where the bar lies: its top-left corner and size.
struct LegendBar {
  Point2 top_left;
  double width = 16, height = 100;
  // The pixel row of value v: bottom − position(v) · height.
  double y_of(const ColourScale& scale, double v) const;
};

// The title's lines: {"Illuminance (lx)", "log scale"}, {"Luminance (cd/m²)", "linear scale"}.
std::vector<std::string> legend_title(const std::string& quantity, const std::string& unit, ScaleKind kind);

// The panel's width for this scale's labels and title.
double legend_width(const ColourScale& scale, const std::vector<std::string>& title, const LegendStyle& style);

// Where draw_legend puts the bar of a panel with its top-right corner at `top_right`, `height`
// pixels tall.
LegendBar legend_bar(const ColourScale& scale, const std::vector<std::string>& title, Point2 top_right, double height,
                     const LegendStyle& style);

// Draws the panel with its top-right corner at `top_right`, `height` pixels tall; returns the bar.
LegendBar draw_legend(Canvas& canvas, const ColourScale& scale, const std::vector<std::string>& title, Point2 top_right,
                      double height, const LegendStyle& style);

}  // namespace lambert
