#include "server/image.h"

#include <stdexcept>
#include <string>

namespace lambert {

Image::Image(int w, int h, Rgb background) : width(w), height(h) {
  if (w <= 0 || h <= 0) throw std::invalid_argument("image: " + std::to_string(w) + "x" + std::to_string(h) + " has no pixels");
  pixels.resize(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < pixels.size(); i += 3) {
    pixels[i] = background.r;
    pixels[i + 1] = background.g;
    pixels[i + 2] = background.b;
  }
}

Rgb Image::at(int x, int y) const {
  if (x < 0 || y < 0 || x >= width || y >= height)
    throw std::out_of_range("image: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside");
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {pixels[i], pixels[i + 1], pixels[i + 2]};
}

void Image::set(int x, int y, Rgb c) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  pixels[i] = c.r;
  pixels[i + 1] = c.g;
  pixels[i + 2] = c.b;
}

}  // namespace lambert
