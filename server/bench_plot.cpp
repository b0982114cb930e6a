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
constexpr int kScale = 2;                                       // text: 10 × 14 pixel glyphs
constexpr int kLegendGap = 30, kRightMargin = 20;
constexpr int kLegendSample = 36;          // the line-and-marker sample in front of each legend name
constexpr std::size_t kMaxNameChars = 32;  // longer names are cut so the axes keep most of the width
constexpr int kLineThickness = 2;

constexpr Rgb kBlack{0, 0, 0}, kGrid{225, 225, 225}, kNote{90, 90, 90}, kWhite{255, 255, 255};

bool plottable(const PlotPoint& p) { return std::isfinite(p.time_s) && std::isfinite(p.error) && p.time_s > 0; }

std::string legend_name(const std::string& name) {
  return name.size() <= kMaxNameChars ? name : name.substr(0, kMaxNameChars - 2) + "..";
}

const char* const kFloorNote[] = {"errors below 1e-16", "shown at 1e-16"};
static_assert(kErrorFloor == 1e-16, "the floor note states the floor");

int legend_width(const std::vector<PlotSeries>& series) {
  int text = 0;
  for (const char* line : kFloorNote) text = std::max(text, text_width(line, kScale));
  for (const PlotSeries& s : series) text = std::max(text, kLegendSample + 8 + text_width(legend_name(s.name), kScale));
  return text + 16;  // 8 pixels of padding inside the legend's border on each side
}

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

// Radii that give the four shapes about the same area (80-120 pixels), so none looks more important.
int marker_radius(Marker shape) {
  constexpr int kRadius[] = {5, 4, 6, 6};  // in the order of enum Marker: circle, square, diamond, triangle
  return kRadius[static_cast<int>(shape)];
}

void draw_marker(Image& img, Pixel at, std::size_t index) {
  const Marker shape = series_marker(index);
  img.marker(at.x, at.y, marker_radius(shape), shape, series_colour(index));
}

void draw_axes(Image& img, const PlotFrame& f) {
  const int left = f.x.pixel_lo, right = f.x.pixel_hi, bottom = f.y.pixel_lo, top = f.y.pixel_hi;
  // Minor ticks at 2..9 × 10^k, only when a decade is wide enough for them not to blur into a bar.
  const bool minor_x = (right - left) / (f.x.hi_decade - f.x.lo_decade) >= 40;
  const bool minor_y = (bottom - top) / (f.y.hi_decade - f.y.lo_decade) >= 40;
  const int step_x = label_step(f.x, 70), step_y = label_step(f.y, 24);
  for (int k = f.x.lo_decade; k <= f.x.hi_decade; ++k) {
    const int x = static_cast<int>(std::lround(axis_pixel(f.x, std::pow(10.0, k))));
    img.line(x, top, x, bottom, kGrid);
    img.line(x, bottom, x, bottom + 6, kBlack);
    if (labelled(k, step_x)) {
      const std::string label = decade_label(k);
      img.text(x - text_width(label, kScale) / 2, bottom + 12, label, kBlack, kScale);
    }
    for (int m = 2; minor_x && m <= 9 && k < f.x.hi_decade; ++m) {
      const int xm = static_cast<int>(std::lround(axis_pixel(f.x, m * std::pow(10.0, k))));
      img.line(xm, bottom, xm, bottom + 3, kBlack);
    }
  }
  for (int k = f.y.lo_decade; k <= f.y.hi_decade; ++k) {
    const int y = static_cast<int>(std::lround(axis_pixel(f.y, std::pow(10.0, k))));
    img.line(left, y, right, y, kGrid);
    img.line(left - 6, y, left, y, kBlack);
    if (labelled(k, step_y)) {
      const std::string label = decade_label(k);
      img.text(left - 12 - text_width(label, kScale), y - kGlyphHeight * kScale / 2, label, kBlack, kScale);
    }
    for (int m = 2; minor_y && m <= 9 && k < f.y.hi_decade; ++m) {
      const int ym = static_cast<int>(std::lround(axis_pixel(f.y, m * std::pow(10.0, k))));
      img.line(left - 3, ym, left, ym, kBlack);
    }
  }
  img.line(left, top, right, top, kBlack);
  img.line(left, bottom, right, bottom, kBlack);
  img.line(left, top, left, bottom, kBlack);
  img.line(right, top, right, bottom, kBlack);

  img.text(kLeft, 16, "lambert bench: speed against error", kBlack, 3);
  img.text(left - 60, top - 34, "error vs exact answer", kBlack, kScale);
  const std::string x_title = "time (s)";
  img.text((left + right - text_width(x_title, kScale)) / 2, bottom + 44, x_title, kBlack, kScale);
}

void draw_legend(Image& img, const PlotFrame& f, const std::vector<PlotSeries>& series, bool floored) {
  const int x0 = f.x.pixel_hi + kLegendGap, row = 26;
  const int lines = static_cast<int>(series.size()) + (floored ? 3 : 0);  // the note after a blank row
  if (lines == 0) return;
  const int x1 = kWidth - kRightMargin, y1 = f.y.pixel_hi + 8 + lines * row;
  img.line(x0, f.y.pixel_hi, x1, f.y.pixel_hi, kBlack);
  img.line(x0, y1, x1, y1, kBlack);
  img.line(x0, f.y.pixel_hi, x0, y1, kBlack);
  img.line(x1, f.y.pixel_hi, x1, y1, kBlack);
  int y = f.y.pixel_hi + 10;
  for (std::size_t i = 0; i < series.size(); ++i, y += row) {
    const int mid = y + kGlyphHeight * kScale / 2;
    img.line(x0 + 8, mid, x0 + 8 + kLegendSample, mid, series_colour(i), kLineThickness);
    draw_marker(img, {x0 + 8 + kLegendSample / 2, mid}, i);
    img.text(x0 + 16 + kLegendSample, y, legend_name(series[i].name), kBlack, kScale);
  }
  if (floored) {
    y += row;
    for (const char* line : kFloorNote) {
      img.text(x0 + 8, y, line, kNote, kScale);
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

std::string decade_label(int exponent) {
  static const char* const kPlain[] = {"0.01", "0.1", "1", "10", "100", "1000"};
  if (exponent >= -2 && exponent <= 3) return kPlain[exponent + 2];
  return "1e" + std::to_string(exponent);
}

Rgb series_colour(std::size_t index) {
  // Dark enough to read on white, far apart in hue.
  constexpr Rgb kPalette[] = {{0, 90, 200},  {230, 120, 0}, {0, 150, 70},  {200, 30, 40},
                              {130, 60, 180}, {140, 90, 40}, {210, 60, 160}, {0, 150, 160}};
  return kPalette[index % 8];
}

void plot_speed_against_error(const std::vector<PlotSeries>& series, const std::string& png_path) {
  const PlotFrame f = plot_frame(series);
  Image img(kWidth, kHeight, kWhite);
  draw_axes(img, f);
  bool floored = false;
  // Every series' lines first, then every marker, so no line runs across another series' marker.
  for (std::size_t i = 0; i < series.size(); ++i) {
    const PlotPoint* prev = nullptr;
    for (const PlotPoint& p : series[i].points) {
      if (!plottable(p)) continue;
      floored = floored || p.error < kErrorFloor;
      if (prev != nullptr) {
        const Pixel a = data_pixel(f, *prev), b = data_pixel(f, p);
        img.line(a.x, a.y, b.x, b.y, series_colour(i), kLineThickness);
      }
      prev = &p;
    }
  }
  for (std::size_t i = 0; i < series.size(); ++i) {
    for (const PlotPoint& p : series[i].points)
      if (plottable(p)) draw_marker(img, data_pixel(f, p), i);
  }
  draw_legend(img, f, series, floored);
  img.write_png(png_path);
}

}  // namespace lambert
