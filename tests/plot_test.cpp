// Lambert's pictures: the cairo canvas (PNG written by cairo, read back with libpng's own reader, so
// the test sees what an image viewer sees; text in DejaVu Sans placed as aligned, by the font's
// published metrics), the false-colour scale and its ticks, the legend, and the `lambert bench --plot`
// figure, whose data-to-pixel mapping is checked against pixel positions worked out by hand.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "server/bench_plot.h"
#include "server/canvas.h"
#include "server/colour_scale.h"
#include "server/legend.h"

namespace lambert {
namespace {

// A PNG as decoded by libpng: 8-bit RGB, rows top to bottom.
struct Decoded {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Decoded read_png(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) throw std::runtime_error(path + ": " + png.message);
  png.format = PNG_FORMAT_RGB;
  Decoded d;
  d.width = static_cast<int>(png.width);
  d.height = static_cast<int>(png.height);
  d.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, d.rgb.data(), 0, nullptr))
    throw std::runtime_error(path + ": " + png.message);
  return d;
}

// A fresh file name per process, removed when the test ends.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(testing::TempDir() + "lambert_plot_test_" + std::to_string(getpid()) + "_" + name) {}
  ~TempFile() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

constexpr Rgb kWhite{255, 255, 255}, kRed{255, 0, 0};

std::string describe(Rgb c) {
  return "(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

TEST(Canvas, WrittenFileReadsBackPixelForPixel) {
  // Distinct values in each channel, so swapped channels, a wrong row stride or a flipped image show.
  Image img(37, 23);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.set(x, y, {static_cast<std::uint8_t>(7 * x), static_cast<std::uint8_t>(11 * y),
                     static_cast<std::uint8_t>((x * y) % 256)});
  ASSERT_EQ(img.at(3, 5), (Rgb{21, 55, 15}));  // the pattern, by hand: 7·3, 11·5, 3·5

  TempFile file("roundtrip.png");
  write_png(img, file.path());
  const Decoded back = read_png(file.path());
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      ASSERT_EQ(back.at(x, y), img.at(x, y)) << "pixel (" << x << ", " << y << ")";
  EXPECT_EQ(Canvas(img).pixels().pixels, img.pixels);  // and through a canvas untouched
}

TEST(Canvas, UnwritablePathThrowsNamingThePath) {
  const std::string path = testing::TempDir() + "lambert-no-such-dir-" + std::to_string(getpid()) + "/out.png";
  ASSERT_FALSE(std::filesystem::exists(std::filesystem::path(path).parent_path()));
  try {
    write_png(Image(4, 4), path);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  try {
    plot_speed_against_error({{"s", {{0.1, 1e-3}}}}, path);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(Canvas, ShapesCoverThePixelsInsideThem) {
  Canvas c(40, 40, kWhite);
  c.fill_rect({2, 3}, {10, 7}, kRed);  // pixels 2..9 × 3..6, whole
  c.marker({25.5, 25.5}, 6, Marker::Circle, kRed);
  c.line({0, 35.5}, {40, 35.5}, kRed, 1);  // along the centres of row 35
  const Image img = c.pixels();
  EXPECT_EQ(img.at(2, 3), kRed);
  EXPECT_EQ(img.at(9, 6), kRed);
  EXPECT_EQ(img.at(10, 6), kWhite);
  EXPECT_EQ(img.at(1, 3), kWhite);
  EXPECT_EQ(img.at(25, 25), kRed);
  EXPECT_EQ(img.at(25, 21), kRed);     // 4 px above the centre, inside r = 6
  EXPECT_EQ(img.at(25, 17), kWhite);   // 8 px above
  EXPECT_EQ(img.at(30, 30), kWhite);   // the bounding square's corner: √50 > 6
  EXPECT_EQ(img.at(12, 35), kRed);
  EXPECT_EQ(img.at(12, 33), kWhite);
}

TEST(Canvas, TextIsDejaVuSansAndItsInkLiesWhereItIsAligned) {
  EXPECT_EQ(picture_font_family(), "DejaVu Sans");
  TextStyle style;
  style.size_px = 20;
  style.h = HAlign::Centre;
  style.v = VAlign::Middle;
  Canvas c(200, 80, kWhite);
  c.text({100, 40}, "1000", style);
  const Image img = c.pixels();
  int x0 = 200, x1 = -1, y0 = 80, y1 = -1;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 200; ++x)
      if (img.at(x, y).r < 128) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  ASSERT_GE(x1, x0) << "no ink";
  // Centred on x = 100 and, digits having no descenders, on y = 40, to within a pixel of hinting.
  EXPECT_NEAR((x0 + x1 + 1) / 2.0, 100, 1.5);
  EXPECT_NEAR((y0 + y1 + 1) / 2.0, 40, 1.5);
  // DejaVu Sans digits advance 0.636 em and stand 0.729 em tall: four of them at 20 px (hinting may
  // round each advance to a whole pixel: up to ½ px each).
  EXPECT_NEAR(text_width("1000", style), 4 * 0.636 * 20, 2.0);
  EXPECT_NEAR(y1 - y0 + 1, 0.729 * 20, 1.5);
}

TEST(Canvas, PowersOfTenRaiseTheirExponent) {
  TextStyle style;
  style.size_px = 20;
  style.v = VAlign::Baseline;
  Canvas c(120, 60, kWhite);
  c.power_of_ten({10, 45}, -3, style);
  const Image img = c.pixels();
  // The base "10" spans about 2 × 0.636 em from x = 10; the exponent starts after it and stands higher.
  const int base_end = 10 + static_cast<int>(2 * 0.636 * 20);
  auto top_of_ink = [&](int from, int to) {
    for (int y = 0; y < 60; ++y)
      for (int x = from; x < to; ++x)
        if (img.at(x, y).r < 128) return y;
    return 60;
  };
  const int base_top = top_of_ink(10, base_end - 1), exponent_top = top_of_ink(base_end + 1, 120);
  EXPECT_LT(exponent_top, base_top - 4);
  EXPECT_GT(power_of_ten_width(-3, style), text_width("10", style));
}

TEST(ColourScale, PositionsOnLogAndLinearScales) {
  const ColourScale log = colour_scale({0, 5, 1000, 200}, ScaleKind::Log);
  EXPECT_DOUBLE_EQ(log.lo, 5);
  EXPECT_DOUBLE_EQ(log.hi, 1000);
  EXPECT_DOUBLE_EQ(colour_scale({0, 0.5, 1e6}, ScaleKind::Log).lo, 1e3);  // three decades at most
  // log(v / lo) / log(hi / lo): 50 is log(10)/log(200) = 0.4346 of the way.
  EXPECT_NEAR(log.position(50), std::log(10.0) / std::log(200.0), 1e-12);
  EXPECT_EQ(log.position(1000), 1);
  EXPECT_EQ(log.position(1), 0);  // below the scale: clamped
  EXPECT_EQ(log.position(0), 0);
  const ColourScale linear = colour_scale({0, 5, 1000, 200}, ScaleKind::Linear);
  EXPECT_EQ(linear.lo, 0);
  EXPECT_DOUBLE_EQ(linear.position(250), 0.25);
  EXPECT_EQ(colour_scale({0, -1}, ScaleKind::Log).hi, 0);
  EXPECT_EQ(false_colour_ramp(0), (Rgb{0, 0, 64}));
  EXPECT_EQ(false_colour_ramp(1), (Rgb{255, 0, 0}));
  EXPECT_EQ(false_colour_ramp(0.5), (Rgb{0, 255, 128}));
}

std::vector<double> values_of(const std::vector<Tick>& ticks) {
  std::vector<double> v;
  for (const Tick& t : ticks) v.push_back(t.value);
  return v;
}

TEST(ColourScale, TicksAreRoundNumbersInsideTheScale) {
  // Three decades from 54 to 54 000 lx: 1, 2 and 5 × 10^k.
  const ColourScale log{ScaleKind::Log, 54, 54000};
  EXPECT_EQ(values_of(scale_ticks(log, 12)),
            (std::vector<double>{100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000}));
  EXPECT_EQ(values_of(scale_ticks(log, 5)), (std::vector<double>{100, 1000, 10000}));  // only decades
  // Linear, 0 to 1234 with at most 6 ticks: the step is the first of 1, 2, 2.5, 5 × 10^k at or above
  // 1234 / 5 = 246.8, that is 250.
  EXPECT_EQ(values_of(scale_ticks({ScaleKind::Linear, 0, 1234}, 6)), (std::vector<double>{0, 250, 500, 750, 1000}));
  const std::vector<double> tenths = values_of(scale_ticks({ScaleKind::Linear, 0, 1}, 11));
  ASSERT_EQ(tenths.size(), 11u);  // 1 / 10 = 0.1 exactly a step: 0, 0.1, ..., 1
  for (std::size_t k = 0; k < 11; ++k) EXPECT_NEAR(tenths[k], k / 10.0, 1e-12);
  // A scale narrower than one tick gets its ends.
  EXPECT_EQ(values_of(scale_ticks({ScaleKind::Log, 31, 42}, 8)), (std::vector<double>{31, 42}));
  EXPECT_EQ(tick_label(0), "0");
  EXPECT_EQ(tick_label(0.25), "0.25");
  EXPECT_EQ(tick_label(0.30000000000000004), "0.3");
  EXPECT_EQ(tick_label(20), "20");
  EXPECT_EQ(tick_label(1000), "1000");
  EXPECT_EQ(tick_label(12345), "12345");  // no exponent below 10^6; rounded to whole numbers
  EXPECT_EQ(tick_label(54269.8), "54270");
  EXPECT_EQ(tick_label(0.00015), "1.5e-4");
  EXPECT_EQ(tick_label(2e6), "2e6");
}

TEST(Legend, TheBarRunsFromTheLowColourAtTheBottomToTheHighAtTheTop) {
  const ColourScale scale{ScaleKind::Log, 10, 10000};
  const std::vector<std::string> title = legend_title("Illuminance", "lx", ScaleKind::Log);
  EXPECT_EQ(title, (std::vector<std::string>{"Illuminance (lx)", "log scale"}));
  Canvas c(300, 300, kWhite);
  const LegendStyle style;
  const LegendBar bar = draw_legend(c, scale, title, {290, 10}, 280, style);
  const LegendBar expected = legend_bar(scale, title, {290, 10}, 280, style);
  EXPECT_EQ(bar.top_left.x, expected.top_left.x);
  EXPECT_EQ(bar.height, expected.height);
  const Image img = c.pixels();
  const int x = static_cast<int>(bar.top_left.x + bar.width / 2);
  EXPECT_EQ(img.at(x, static_cast<int>(bar.top_left.y)), false_colour_ramp(1));
  EXPECT_EQ(img.at(x, static_cast<int>(bar.top_left.y + bar.height - 1)), false_colour_ramp(0));
  // 100 lx sits a third of the way up a 10 to 10 000 lx log scale.
  EXPECT_NEAR(bar.y_of(scale, 100), bar.top_left.y + bar.height * 2 / 3, 1e-9);
  // Labels are drawn in the panel's text colour right of the bar: some white ink there.
  int ink = 0;
  for (int y = static_cast<int>(bar.top_left.y); y < bar.top_left.y + bar.height; ++y)
    for (int xx = static_cast<int>(bar.top_left.x + bar.width + 8); xx < 290; ++xx) ink += img.at(xx, y).r > 200;
  EXPECT_GT(ink, 50);
}

TEST(BenchPlot, DecadesLandOnTheirPixels) {
  // 4 decades over 400 pixels: 100 per decade. 16 decades over 560 rows (y grows downwards): 35.
  const LogAxis x{-3, 1, 100, 500};
  const LogAxis y{-16, 0, 640, 80};
  EXPECT_DOUBLE_EQ(axis_pixel(x, 1e-3), 100);
  EXPECT_DOUBLE_EQ(axis_pixel(x, 1e-2), 200);
  EXPECT_DOUBLE_EQ(axis_pixel(x, 1), 400);
  EXPECT_DOUBLE_EQ(axis_pixel(x, 10), 500);
  EXPECT_NEAR(axis_pixel(x, std::sqrt(10.0) * 1e-3), 150, 1e-9);  // half a decade
  EXPECT_DOUBLE_EQ(axis_pixel(y, 1e-16), 640);
  EXPECT_DOUBLE_EQ(axis_pixel(y, 1e-12), 500);
  EXPECT_DOUBLE_EQ(axis_pixel(y, 1e-8), 360);
  EXPECT_DOUBLE_EQ(axis_pixel(y, 1), 80);

  const PlotFrame f{x, y};
  EXPECT_EQ(data_pixel(f, {1e-2, 1e-8}), (Pixel{200, 360}));
  EXPECT_EQ(data_pixel(f, {10, 1}), (Pixel{500, 80}));
  // At or below the floor, zero and negative errors included: the floor row.
  for (double e : {1e-16, 5e-17, 1e-20, 0.0, -1e-3, -0.0})
    EXPECT_EQ(data_pixel(f, {0.1, e}), (Pixel{300, 640})) << e;
  EXPECT_EQ(plotted_error(0), kErrorFloor);
  EXPECT_EQ(plotted_error(1e-3), 1e-3);
}

TEST(BenchPlot, AxesSpanWholeDecadesAroundTheData) {
  PlotFrame f = plot_frame({{"a", {{2e-3, 3e-9}, {0.5, 0}}}, {"b", {{0.01, 1e-11}}}});
  EXPECT_EQ(f.x.lo_decade, -3);
  EXPECT_EQ(f.x.hi_decade, 0);
  EXPECT_EQ(f.y.lo_decade, -17);  // the 0 error is drawn at the floor, 1e-16, a decade above the edge
  EXPECT_EQ(f.y.hi_decade, -8);
  EXPECT_LT(f.x.pixel_lo, f.x.pixel_hi);
  EXPECT_GT(f.y.pixel_lo, f.y.pixel_hi);

  // A value on a decade, alone or with equal ones: a decade of room each side.
  f = plot_frame({{"one", {{0.01, 1e-4}}}});
  EXPECT_EQ(f.x.lo_decade, -3);
  EXPECT_EQ(f.x.hi_decade, -1);
  EXPECT_EQ(f.y.lo_decade, -5);
  EXPECT_EQ(f.y.hi_decade, -3);
  f = plot_frame({{"same", {{0.3, 0}, {0.3, 0}, {0.3, -1}}}});
  EXPECT_EQ(f.x.lo_decade, -1);  // 0.3 lies inside (0.1, 1): no more room needed
  EXPECT_EQ(f.x.hi_decade, 0);
  EXPECT_EQ(f.y.lo_decade, -17);
  EXPECT_EQ(f.y.hi_decade, -15);

  // Nothing plottable (no series, no points, NaN, time 0): the default 1 ms..10 s, 1e-16..1.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::vector<PlotSeries>> nothing = {
      {}, {{"empty", {}}}, {{"bad", {{nan, 1e-3}, {0, 1e-3}, {1, nan}}}}};
  for (const auto& s : nothing) {
    f = plot_frame(s);
    EXPECT_EQ(f.x.lo_decade, -3);
    EXPECT_EQ(f.x.hi_decade, 1);
    EXPECT_EQ(f.y.lo_decade, -16);
    EXPECT_EQ(f.y.hi_decade, 0);
  }
}

TEST(BenchPlot, DecadeLabels) {
  EXPECT_FALSE(plain_decade_label(-16));  // drawn as 10 with a raised −16
  EXPECT_FALSE(plain_decade_label(-3));
  EXPECT_EQ(plain_decade_label(-2), "0.01");
  EXPECT_EQ(plain_decade_label(-1), "0.1");
  EXPECT_EQ(plain_decade_label(0), "1");
  EXPECT_EQ(plain_decade_label(1), "10");
  EXPECT_EQ(plain_decade_label(3), "1000");
  EXPECT_FALSE(plain_decade_label(4));
}

TEST(BenchPlot, EachPointIsDrawnInItsSeriesColourOnAWhiteBackground) {
  const std::vector<PlotSeries> series = {
      {"ladder-a", {{1e-3, 1e-2}, {1e-2, 1e-5}, {1e-1, 1e-8}}},
      {"floored-b", {{3e-3, 0}, {3e-1, 1e-12}}},
      {"single-c", {{5, 1e-6}}},
  };
  TempFile file("known.png");
  plot_speed_against_error(series, file.path());
  const Decoded png = read_png(file.path());
  ASSERT_EQ(png.width, 1200);
  ASSERT_EQ(png.height, 720);

  const PlotFrame f = plot_frame(series);
  EXPECT_EQ(data_pixel(f, series[1].points[0]).y, std::lround(axis_pixel(f.y, kErrorFloor)));  // 0 error
  for (std::size_t i = 0; i < series.size(); ++i) {
    for (const PlotPoint& p : series[i].points) {
      const Pixel px = data_pixel(f, p);
      EXPECT_EQ(png.at(px.x, px.y), series_colour(i))
          << series[i].name << " at (" << p.time_s << ", " << p.error << "): " << describe(png.at(px.x, px.y));
    }
    // The legend, right of the axes box, shows each series' colour.
    bool in_legend = false;
    for (int y = 0; y < png.height && !in_legend; ++y)
      for (int x = f.x.pixel_hi + 1; x < png.width && !in_legend; ++x) in_legend = png.at(x, y) == series_colour(i);
    EXPECT_TRUE(in_legend) << series[i].name;
  }
  // Half-decade spots well away from every point and line (no grid line there either): background.
  for (const PlotPoint& empty : {PlotPoint{std::pow(10.0, -2.5), std::pow(10.0, -13.5)},
                                 PlotPoint{std::pow(10.0, -0.5), std::pow(10.0, -2.5)}}) {
    const Pixel px = data_pixel(f, empty);
    EXPECT_EQ(png.at(px.x, px.y), kWhite) << px.x << ", " << px.y << ": " << describe(png.at(px.x, px.y));
  }
}

TEST(BenchPlot, DegenerateSeriesStillGiveAPlot) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  TempFile file("degenerate.png");
  for (const auto& s : std::vector<std::vector<PlotSeries>>{
           {}, {{"empty", {}}}, {{"one", {{0.2, 0.01}}}}, {{"equal", {{1, 1e-20}, {1, 1e-20}}}},
           {{"nan", {{nan, nan}, {0, 1}}}, {"ok", {{1e-3, 1}}}},
           {{std::string(80, 'n'), {{0.5, 1e-9}}}}}) {
    ASSERT_NO_THROW(plot_speed_against_error(s, file.path()));
    const Decoded png = read_png(file.path());
    EXPECT_EQ(png.width, 1200);
    EXPECT_EQ(png.height, 720);
  }
}

}  // namespace
}  // namespace lambert
