// An RGB8 raster: what `lambert render` traces into, pixel by pixel, before server/canvas.h draws
// the scale and labels on it and writes it as a PNG.
#pragma once

#include <cstdint>
#include <vector>

namespace lambert {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};
inline constexpr Rgb kBlack{0, 0, 0}, kWhite{255, 255, 255};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, top row first, 3 bytes (r, g, b) per pixel

  Image(int width, int height, Rgb background = {255, 255, 255});

  Rgb at(int x, int y) const;  // throws std::out_of_range outside the image
  void set(int x, int y, Rgb c);
};

}  // namespace lambert
