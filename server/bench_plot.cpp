// The speed-against-error plot (see bench_plot.h). Layout, 1200 × 720 pixels: title and y-axis title
// on top, the axes box on the left, x tick labels and the x-axis title below it, the legend to the
// right of the box, where it cannot cover data.
#include "server/bench_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lambert {
namespace {

constexpr int kWidth = 1200, kHeight = 720;
constexpr int kLeft = 100, kTop = 80, kBottom = kHeight - 80;  // the axes box, right edge from the legend
constexpr double kFont_px = 15, kTitleFont_px = 22;
constexpr int kLegendGap = 30, kRightMargin = 20;
constexpr int kLegendSample = 36;          // the line-and-marker sample in front of each legend name
constexpr std::size_t kMaxNameChars = 32;  // longer names are cut so the axes keep most of the width
constexpr double kLineThickness = 2;

constexpr Rgb kGrid{225, 225, 225}, kNote{90, 90, 90};

bool plottable(const PlotPoint& p) { return std::isfinite(p.time_s) && std::isfinite(p.error) && p.time_s > 0; }

std::string legend_name(const std::string& name) {
  return name.size() <= kMaxNameChars ? name : name.substr(0, kMaxNameChars - 2) + "..";
}

const char* const kFloorNote[] = {"errors below 1e-16", "shown at 1e-16"};
static_assert(kErrorFloor == 1e-16, "the floor note states the floor");

TextStyle label(HAlign h = HAlign::Left, VAlign v = VAlign::Middle, Rgb colour = kBlack) {
  TextStyle t;
  t.size_px = kFont_px;
  t.colour = colour;
  t.h = h;
  t.v = v;
  return t;
}

int legend_width(const std::vector<PlotSeries>& series) {
  double text = 0;
  for (const char* line : kFloorNote) text = std::max(text, text_width(line, label()));
  for (const PlotSeries& s : series) text = std::max(text, kLegendSample + 8 + text_width(legend_name(s.name), label()));
  return static_cast<int>(std::ceil(text)) + 16;  // 8 pixels of padding inside the legend's border on each side
}

// The centre of pixel p: lines and markers drawn there cover the pixel itself.
Point2 centre(Pixel p) { return {p.x + 0.5, p.y + 0.5}; }
Point2 centre(double x, double y) { return {std::round(x) + 0.5, std::round(y) + 0.5}; }

// Whole decades strictly below lo and above hi: a value on a decade (the floor, a lone value, all-equal
// values) gets a decade of room rather than a marker cut in half by the box edge.
void fit_decades(double lo, double hi, LogAxis& axis) {
  axis.lo_decade = static_cast<int>(std::ceil(std::log10(lo))) - 1;
  axis.hi_decade = static_cast<int>(std::floor(std::log10(hi))) + 1;
}

// Label every `step`-th decade, step chosen so that labels stay at least min_spacing pixels apart;
// multiples of step are labelled, so 1 is whenever it is in range.
int label_step(const LogAxis& axis, int min_spacing) {
  const double per_decade = std::abs(axis.pixel_hi - axis.pixel_lo) / double(axis.hi_decade - axis.lo_decade);
  return std::max(1, static_cast<int>(std::ceil(min_spacing / per_decade)));
}

bool labelled(int decade, int step) { return ((decade % step) + step) % step == 0; }

Marker series_marker(std::size_t index) {
  // Four shapes against eight colours: from the ninth series on, the shape shifts by one, so no two
  // of the first 32 series look the same.
  constexpr Marker kShapes[] = {Marker::Circle, Marker::Square, Marker::Diamond, Marker::Triangle};
  return kShapes[(index + index / 8) % 4];
}

// Circumscribed radii that give the four shapes about the same area (about 80 pixels), so none looks
// more important: π r², 2 r², 2 r², (3√3/4) r².
double marker_radius(Marker shape) {
  constexpr double kRadius[] = {5, 6.3, 6.3, 7.8};  // in the order of enum Marker: circle, square, diamond, triangle
  return kRadius[static_cast<int>(shape)];
}

void draw_marker(Canvas& c, Pixel at, std::size_t index) {
  const Marker shape = series_marker(index);
  c.marker(centre(at), marker_radius(shape), shape, series_colour(index));
}

// A decade's tick label, plain or as a power of ten.
void decade_text(Canvas& c, Point2 at, int k, const TextStyle& style) {
  if (const auto plain = plain_decade_label(k))
    c.text(at, *plain, style);
  else
    c.power_of_ten(at, k, style);
}

void draw_axes(Canvas& c, const PlotFrame& f) {
  const int left = f.x.pixel_lo, right = f.x.pixel_hi, bottom = f.y.pixel_lo, top = f.y.pixel_hi;
  // Minor ticks at 2..9 × 10^k, only when a decade is wide enough for them not to blur into a bar.
  const bool minor_x = (right - left) / (f.x.hi_decade - f.x.lo_decade) >= 40;
  const bool minor_y = (bottom - top) / (f.y.hi_decade - f.y.lo_decade) >= 40;
  const int step_x = label_step(f.x, 70), step_y = label_step(f.y, 24);
  for (int k = f.x.lo_decade; k <= f.x.hi_decade; ++k) {
    const double x = std::round(axis_pixel(f.x, std::pow(10.0, k))) + 0.5;
    c.line({x, double(top)}, {x, double(bottom)}, kGrid);
    c.line({x, double(bottom)}, {x, bottom + 6.0}, kBlack);
    if (labelled(k, step_x)) decade_text(c, {x, bottom + 10.0}, k, label(HAlign::Centre, VAlign::Top));
    for (int m = 2; minor_x && m <= 9 && k < f.x.hi_decade; ++m) {
      const double xm = std::round(axis_pixel(f.x, m * std::pow(10.0, k))) + 0.5;
      c.line({xm, double(bottom)}, {xm, bottom + 3.0}, kBlack);
    }
  }
  for (int k = f.y.lo_decade; k <= f.y.hi_decade; ++k) {
    const double y = std::round(axis_pixel(f.y, std::pow(10.0, k))) + 0.5;
    c.line({double(left), y}, {double(right), y}, kGrid);
    c.line({left - 6.0, y}, {double(left), y}, kBlack);
    if (labelled(k, step_y)) decade_text(c, {left - 10.0, y}, k, label(HAlign::Right, VAlign::Middle));
    for (int m = 2; minor_y && m <= 9 && k < f.y.hi_decade; ++m) {
      const double ym = std::round(axis_pixel(f.y, m * std::pow(10.0, k))) + 0.5;
      c.line({left - 3.0, ym}, {double(left), ym}, kBlack);
    }
  }
  c.stroke_rect(centre(left, top), centre(right, bottom), kBlack);

  TextStyle title = label(HAlign::Left, VAlign::Top);
  title.size_px = kTitleFont_px;
  title.weight = Weight::Bold;
  c.text({double(kLeft), 16}, "lambert bench: speed against error", title);
  c.text({left - 60.0, top - 24.0}, "error against the exact answer", label(HAlign::Left, VAlign::Baseline));
  c.text({(left + right) / 2.0, bottom + 40.0}, "time (s)", label(HAlign::Centre, VAlign::Top));
}

void draw_legend(Canvas& c, const PlotFrame& f, const std::vector<PlotSeries>& series, bool floored) {
  const double x0 = f.x.pixel_hi + kLegendGap + 0.5, row = 26;
  const int lines = static_cast<int>(series.size()) + (floored ? 3 : 0);  // the note after a blank row
  if (lines == 0) return;
  const double x1 = kWidth - kRightMargin + 0.5, top = f.y.pixel_hi + 0.5, y1 = top + 8 + lines * row;
  c.stroke_rect({x0, top}, {x1, y1}, kBlack);
  double y = top + 8 + row / 2;
  for (std::size_t i = 0; i < series.size(); ++i, y += row) {
    c.line({x0 + 8, y}, {x0 + 8 + kLegendSample, y}, series_colour(i), kLineThickness);
    draw_marker(c, {static_cast<int>(x0 + 8 + kLegendSample / 2), static_cast<int>(y)}, i);
    c.text({x0 + 16 + kLegendSample, y}, legend_name(series[i].name), label());
  }
  if (floored) {
    y += row;
    for (const char* line : kFloorNote) {
      c.text({x0 + 8, y}, line, label(HAlign::Left, VAlign::Middle, kNote));
      y += row;
    }
  }
}

}  // namespace

double axis_pixel(const LogAxis& axis, double value) {
  const double t = (std::log10(value) - axis.lo_decade) / (axis.hi_decade - axis.lo_decade);
  return axis.pixel_lo + t * (axis.pixel_hi - axis.pixel_lo);
}

double plotted_error(double error) { return std::max(error, kErrorFloor); }

Pixel data_pixel(const PlotFrame& frame, const PlotPoint& p) {
  return {static_cast<int>(std::lround(axis_pixel(frame.x, p.time_s))),
          static_cast<int>(std::lround(axis_pixel(frame.y, plotted_error(p.error))))};
}

PlotFrame plot_frame(const std::vector<PlotSeries>& series) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double t_lo = inf, t_hi = -inf, e_lo = inf, e_hi = -inf;
  for (const PlotSeries& s : series) {
    for (const PlotPoint& p : s.points) {
      if (!plottable(p)) continue;
      t_lo = std::min(t_lo, p.time_s);
      t_hi = std::max(t_hi, p.time_s);
      e_lo = std::min(e_lo, plotted_error(p.error));
      e_hi = std::max(e_hi, plotted_error(p.error));
    }
  }
  PlotFrame f;
  if (t_lo == inf) {
    f.x.lo_decade = -3, f.x.hi_decade = 1;
    f.y.lo_decade = -16, f.y.hi_decade = 0;
  } else {
    fit_decades(t_lo, t_hi, f.x);
    fit_decades(e_lo, e_hi, f.y);
  }
  f.x.pixel_lo = kLeft;
  f.x.pixel_hi = kWidth - kRightMargin - legend_width(series) - kLegendGap;
  f.y.pixel_lo = kBottom;
  f.y.pixel_hi = kTop;
  return f;
}

std::optional<std::string> plain_decade_label(int exponent) {
  static const char* const kPlain[] = {"0.01", "0.1", "1", "10", "100", "1000"};
  if (exponent >= -2 && exponent <= 3) return kPlain[exponent + 2];
  return std::nullopt;
}

Rgb series_colour(std::size_t index) {
  // Dark enough to read on white, far apart in hue.
  constexpr Rgb kPalette[] = {{0, 90, 200},  {230, 120, 0}, {0, 150, 70},  {200, 30, 40},
                              {130, 60, 180}, {140, 90, 40}, {210, 60, 160}, {0, 150, 160}};
  return kPalette[index % 8];
}

Image draw_speed_against_error(const std::vector<PlotSeries>& series) {
  const PlotFrame f = plot_frame(series);
  Canvas c(kWidth, kHeight, kWhite);
  draw_axes(c, f);
  bool floored = false;
  // Every series' lines first, then every marker, so no line runs across another series' marker.
  for (std::size_t i = 0; i < series.size(); ++i) {
    std::vector<Point2> line;
    for (const PlotPoint& p : series[i].points) {
      if (!plottable(p)) continue;
      floored = floored || p.error < kErrorFloor;
      line.push_back(centre(data_pixel(f, p)));
    }
    c.polyline(line, series_colour(i), kLineThickness);
  }
  for (std::size_t i = 0; i < series.size(); ++i) {
    for (const PlotPoint& p : series[i].points)
      if (plottable(p)) draw_marker(c, data_pixel(f, p), i);
  }
  draw_legend(c, f, series, floored);
  return c.pixels();
}

void plot_speed_against_error(const std::vector<PlotSeries>& series, const std::string& png_path) {
  write_png(draw_speed_against_error(series), png_path);
}

}  // namespace lambert
