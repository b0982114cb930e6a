// A small RGB8 raster with the drawing `lambert bench --plot` needs (lines, rectangles, markers,
// text in a built-in 5×7 bitmap font) and PNG output through libpng. Drawing clips at the image
// edges, so callers may place shapes partly outside.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace lambert {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

enum class Marker { Circle, Square, Diamond, Triangle };

// Text metrics of the built-in font at scale 1: glyphs are 5 pixels wide and 7 tall above the
// baseline (g, j, p, q, y and ',' descend 2 more); every character advances 6 pixels.
inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = 6;

// True when the font has a glyph of its own for c; any other character is drawn as '?'.
bool has_glyph(char c);

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, top row first, 3 bytes (r, g, b) per pixel

  Image(int width, int height, Rgb background = {255, 255, 255});

  Rgb at(int x, int y) const;  // throws std::out_of_range outside the image
  void set(int x, int y, Rgb c);
  // From (x0, y0) to (x1, y1), both ends included, as a square pen `thickness` pixels wide.
  void line(int x0, int y0, int x1, int y1, Rgb c, int thickness = 1);
  void fill_rect(int x0, int y0, int x1, int y1, Rgb c);  // corners included, in any order
  void fill_circle(int cx, int cy, int radius, Rgb c);
  void marker(int cx, int cy, int radius, Marker shape, Rgb c);  // filled, centred on (cx, cy)
  // Top-left corner of the first glyph cell at (x, y); each font pixel becomes scale × scale.
  void text(int x, int y, std::string_view s, Rgb c, int scale = 1);

  // Throws std::runtime_error naming the path and libpng's reason when the file cannot be written.
  void write_png(const std::string& path) const;
};

inline int text_width(std::string_view s, int scale = 1) {
  return s.empty() ? 0 : static_cast<int>(s.size() * kGlyphAdvance - (kGlyphAdvance - kGlyphWidth)) * scale;
}

}  // namespace lambert
