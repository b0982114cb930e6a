// Antialiased drawing for Lambert's pictures (the bench plot, the false-colour scale, the probe-grid
// map): lines, rectangles, markers and text in DejaVu Sans (Debian fonts-dejavu-core), drawn with
// cairo and written as PNG. cairo is used only in canvas.cpp; coordinates are pixels with (0, 0) at
// the top-left corner of the top-left pixel, so pixel (x, y) is centred on (x + ½, y + ½).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/image.h"

namespace lambert {

struct Point2 {
  double x = 0, y = 0;
};

enum class Marker { Circle, Square, Diamond, Triangle };
enum class HAlign { Left, Centre, Right };
// Where `at` lies on the text: its top (the font's ascent), the middle of a digit's height, or the
// baseline.
enum class VAlign { Top, Middle, Baseline };
enum class Weight { Normal, Bold };

struct TextStyle {
  double size_px = 14;  // the font's em
  Rgb colour{0, 0, 0};
  HAlign h = HAlign::Left;
  VAlign v = VAlign::Baseline;
  Weight weight = Weight::Normal;
};

class Canvas {
 public:
  Canvas(int width, int height, Rgb background);
  explicit Canvas(const Image& image);  // starts from these pixels
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const;
  int height() const;

  void line(Point2 a, Point2 b, Rgb colour, double width_px = 1);
  void polyline(const std::vector<Point2>& points, Rgb colour, double width_px = 1);
  void fill_rect(Point2 corner, Point2 opposite, Rgb colour);
  void stroke_rect(Point2 corner, Point2 opposite, Rgb colour, double width_px = 1);
  // Filled, centred on `centre`; `radius` is the circumscribed circle's.
  void marker(Point2 centre, double radius, Marker shape, Rgb colour);
  void text(Point2 at, std::string_view utf8, const TextStyle& style);
  // A power of ten as "10" with a raised exponent ("10⁻³"), aligned as one piece of text.
  void power_of_ten(Point2 at, int exponent, const TextStyle& style);

  Image pixels() const;
  // Throws std::runtime_error naming the path and cairo's reason when the file cannot be written.
  void write_png(const std::string& path) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The advance width of `utf8` in pixels at `style`'s size and weight.
double text_width(std::string_view utf8, const TextStyle& style);
double power_of_ten_width(int exponent, const TextStyle& style);

// The family fontconfig gives for "DejaVu Sans" (what the pictures are drawn in). Throws
// std::runtime_error when it is another family: fonts-dejavu-core is not installed.
std::string picture_font_family();

// Writes an image as PNG through cairo; errors as Canvas::write_png.
void write_png(const Image& image, const std::string& path);

}  // namespace lambert
