// The speed-against-error plot of `lambert bench --plot`: log-log, time on x, error on y, one colour
// and marker per series, points joined in the order given (the bench's ladder order).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "server/canvas.h"

namespace lambert {

// Errors at round-off are often exactly 0; a log axis cannot show them, so errors below this
// (0 and negatives included) are drawn at it, and the legend says so when any is.
inline constexpr double kErrorFloor = 1e-16;

struct PlotPoint {
  double time_s = 0;
  double error = 0;
};

struct PlotSeries {
  std::string name;
  std::vector<PlotPoint> points;  // points with a non-finite value or time <= 0 are left out
};

// One log10 axis: 10^lo_decade sits at pixel_lo and 10^hi_decade at pixel_hi (for y, pixel_lo is
// the bottom row, so pixel_lo > pixel_hi).
struct LogAxis {
  int lo_decade = 0, hi_decade = 1;
  int pixel_lo = 0, pixel_hi = 1;
};

struct PlotFrame {
  LogAxis x;  // time, s
  LogAxis y;  // error
};

struct Pixel {
  int x = 0, y = 0;
  bool operator==(const Pixel&) const = default;
};

// Unrounded pixel coordinate of value > 0: linear in log10(value).
double axis_pixel(const LogAxis& axis, double value);
// The error as drawn: max(error, kErrorFloor).
double plotted_error(double error);
// The pixel of a data point: axis_pixel of time and of plotted_error(error), rounded to nearest.
Pixel data_pixel(const PlotFrame& frame, const PlotPoint& p);

// The axes of the plot of these series: from the decade below the smallest plotted value to the
// decade above the largest (a value on a decade is never on the box edge), placed in the fixed image
// layout. With no plottable point: 1 ms to 10 s, and 1e-16 to 1.
PlotFrame plot_frame(const std::vector<PlotSeries>& series);

// Tick label of 10^exponent in plain decimals from 0.01 to 1000 ("0.01", "1", "1000"); outside that
// range none: the axis writes the power of ten with a raised exponent (Canvas::power_of_ten).
std::optional<std::string> plain_decade_label(int exponent);

Rgb series_colour(std::size_t index);

// The plot drawn in plot_frame's layout.
Image draw_speed_against_error(const std::vector<PlotSeries>& series);
// The same written as a PNG; throws std::runtime_error naming the path when it cannot be written.
void plot_speed_against_error(const std::vector<PlotSeries>& series, const std::string& png_path);

}  // namespace lambert
