// The PNG raster and the `lambert bench --plot` figure. Written files are read back with libpng's own
// reader (its simplified read API), so the test sees what an image viewer sees; the data-to-pixel
// mapping is checked against pixel positions worked out by hand.
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
#include "server/png_image.h"

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

TEST(PngImage, WrittenFileReadsBackPixelForPixel) {
  // Distinct values in each channel, so swapped channels, a wrong row stride or a flipped image show.
  Image img(37, 23);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      img.set(x, y, {static_cast<std::uint8_t>(7 * x), static_cast<std::uint8_t>(11 * y),
                     static_cast<std::uint8_t>((x * y) % 256)});
  img.line(0, 22, 36, 0, {1, 2, 3}, 2);
  img.text(2, 2, "1e-3", {250, 0, 9}, 1);
  ASSERT_EQ(img.at(3, 5), (Rgb{21, 55, 15}));  // the pattern, by hand: 7·3, 11·5, 3·5

  TempFile file("roundtrip.png");
  img.write_png(file.path());
  const Decoded back = read_png(file.path());
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  ASSERT_EQ(back.rgb.size(), img.pixels.size());
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      ASSERT_EQ(back.at(x, y), img.at(x, y)) << "pixel (" << x << ", " << y << ")";
}

TEST(PngImage, UnwritablePathThrowsNamingThePath) {
  const std::string path = testing::TempDir() + "lambert-no-such-dir-" + std::to_string(getpid()) + "/out.png";
  ASSERT_FALSE(std::filesystem::exists(std::filesystem::path(path).parent_path()));
  try {
    Image(4, 4).write_png(path);
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

TEST(PngImage, LinesRectanglesAndCirclesCoverTheirPixels) {
  Image img(20, 20);
  img.line(2, 3, 10, 3, kRed);
  for (int x = 2; x <= 10; ++x) EXPECT_EQ(img.at(x, 3), kRed) << x;
  EXPECT_EQ(img.at(1, 3), kWhite);
  EXPECT_EQ(img.at(11, 3), kWhite);
  EXPECT_EQ(img.at(6, 2), kWhite);

  Image diag(10, 10);
  diag.line(8, 8, 0, 0, kRed);  // drawn backwards: still every (k, k) and nothing else on row 4
  for (int k = 0; k <= 8; ++k) EXPECT_EQ(diag.at(k, k), kRed) << k;
  EXPECT_EQ(diag.at(5, 4), kWhite);

  Image thick(10, 10);
  thick.line(5, 1, 5, 8, kRed, 3);  // a 3-pixel pen covers columns 4..6
  for (int x = 4; x <= 6; ++x) EXPECT_EQ(thick.at(x, 5), kRed) << x;
  EXPECT_EQ(thick.at(3, 5), kWhite);
  EXPECT_EQ(thick.at(7, 5), kWhite);

  Image rect(10, 10);
  rect.fill_rect(6, 7, 2, 3, kRed);  // corners in either order
  EXPECT_EQ(rect.at(2, 3), kRed);
  EXPECT_EQ(rect.at(6, 7), kRed);
  EXPECT_EQ(rect.at(1, 3), kWhite);
  EXPECT_EQ(rect.at(7, 7), kWhite);

  Image circle(20, 20);
  circle.fill_circle(10, 10, 4, kRed);
  EXPECT_EQ(circle.at(10, 10), kRed);
  EXPECT_EQ(circle.at(14, 10), kRed);
  EXPECT_EQ(circle.at(10, 6), kRed);
  EXPECT_EQ(circle.at(14, 14), kWhite);  // the corner of the bounding square: 32 > 4² + 4
  EXPECT_EQ(circle.at(15, 10), kWhite);

  Image edge(5, 5);
  edge.fill_circle(0, 0, 3, kRed);  // partly outside: clipped, no throw
  EXPECT_EQ(edge.at(0, 0), kRed);
}

TEST(PngImage, FontHasDistinctGlyphsForEveryCharacterThePlotUses) {
  const std::string needed =
      "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz.-+()/,:=%_? ";
  std::vector<std::vector<std::uint8_t>> drawn;
  for (char c : needed) {
    EXPECT_TRUE(has_glyph(c)) << "'" << c << "'";
    Image img(kGlyphWidth, kGlyphHeight + 2);
    img.text(0, 0, std::string(1, c), kRed);
    for (const auto& other : drawn) EXPECT_FALSE(img.pixels == other) << "'" << c << "' looks like an earlier glyph";
    drawn.push_back(img.pixels);
  }
  // A character without a glyph is drawn as '?'.
  EXPECT_FALSE(has_glyph('~'));
  Image unknown(12, 9), question(12, 9);
  unknown.text(0, 0, "~", kRed);
  question.text(0, 0, "?", kRed);
  EXPECT_EQ(unknown.pixels, question.pixels);
  // Scale 2 doubles each font pixel: the 'i' dot (row 0, column 2) becomes columns 4-5 of rows 0-1.
  Image big(12, 18);
  big.text(0, 0, "i", kRed, 2);
  EXPECT_EQ(big.at(4, 0), kRed);
  EXPECT_EQ(big.at(5, 1), kRed);
  EXPECT_EQ(big.at(3, 0), kWhite);
  EXPECT_EQ(big.at(4, 2), kWhite);  // row 1 of the glyph is blank
  EXPECT_EQ(text_width("abc", 2), 34);  // 3 advances of 6 less the trailing blank column, doubled
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
  EXPECT_EQ(decade_label(-16), "1e-16");
  EXPECT_EQ(decade_label(-3), "1e-3");
  EXPECT_EQ(decade_label(-2), "0.01");
  EXPECT_EQ(decade_label(-1), "0.1");
  EXPECT_EQ(decade_label(0), "1");
  EXPECT_EQ(decade_label(1), "10");
  EXPECT_EQ(decade_label(3), "1000");
  EXPECT_EQ(decade_label(4), "1e4");
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
