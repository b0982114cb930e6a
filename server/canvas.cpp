// The only user of cairo (and of fontconfig, to check the font): see canvas.h. Text uses cairo's
// simple text API with the family fixed to DejaVu Sans, which is enough for labels in Latin script.
#include "server/canvas.h"

#include <cairo.h>
#include <fontconfig/fontconfig.h>

#include <cmath>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace lambert {
namespace {

constexpr const char* kFamily = "DejaVu Sans";
constexpr double kExponentScale = 0.7;  // the exponent's size against the base's
constexpr double kExponentRise = 0.45;  // its baseline raised by this many ems

void set_colour(cairo_t* cr, Rgb c) { cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

void set_font(cairo_t* cr, const TextStyle& style) {
  cairo_select_font_face(cr, kFamily, CAIRO_FONT_SLANT_NORMAL,
                         style.weight == Weight::Bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, style.size_px);
}

// A 1 × 1 surface to measure text on.
struct Measure {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
  cairo_t* cr = cairo_create(surface);
  ~Measure() {
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
  }
};

double advance(cairo_t* cr, std::string_view utf8, const TextStyle& style) {
  set_font(cr, style);
  cairo_text_extents_t e;
  const std::string s(utf8);
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

// How far below `at` the baseline goes for the style's vertical alignment.
double baseline_offset(cairo_t* cr, const TextStyle& style) {
  set_font(cr, style);
  if (style.v == VAlign::Baseline) return 0;
  if (style.v == VAlign::Top) {
    cairo_font_extents_t f;
    cairo_font_extents(cr, &f);
    return f.ascent;
  }
  cairo_text_extents_t digit;
  cairo_text_extents(cr, "0", &digit);
  return -digit.y_bearing / 2;  // y_bearing is minus the digit's height above the baseline
}

double start_x(double x, double width, HAlign h) {
  return h == HAlign::Left ? x : h == HAlign::Centre ? x - width / 2 : x - width;
}

std::string exponent_text(int exponent) {
  // U+2212 MINUS SIGN: a hyphen is too short to read as minus at this size.
  return exponent < 0 ? "\u2212" + std::to_string(-exponent) : std::to_string(exponent);
}

void check(cairo_status_t status, const std::string& what) {
  if (status != CAIRO_STATUS_SUCCESS) throw std::runtime_error(what + ": " + cairo_status_to_string(status));
}

}  // namespace

struct Canvas::Impl {
  cairo_surface_t* surface = nullptr;
  cairo_t* cr = nullptr;
  int width = 0, height = 0;

  Impl(int w, int h) : width(w), height(h) {
    if (w <= 0 || h <= 0) throw std::invalid_argument("canvas: " + std::to_string(w) + "x" + std::to_string(h) + " has no pixels");
    picture_font_family();  // refuse to draw labels in a substitute font
    surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    check(cairo_surface_status(surface), "canvas");
    cr = cairo_create(surface);
  }
  ~Impl() {
    cairo_destroy(cr);
    cairo_surface_destroy(surface);
  }

  // CAIRO_FORMAT_RGB24: one native-endian 32-bit word per pixel, 0x00RRGGBB.
  std::uint32_t* row(int y) {
    return reinterpret_cast<std::uint32_t*>(cairo_image_surface_get_data(surface) + y * cairo_image_surface_get_stride(surface));
  }
};

Canvas::Canvas(int width, int height, Rgb background) : impl_(std::make_unique<Impl>(width, height)) {
  set_colour(impl_->cr, background);
  cairo_paint(impl_->cr);
}

Canvas::Canvas(const Image& image) : impl_(std::make_unique<Impl>(image.width, image.height)) {
  cairo_surface_flush(impl_->surface);
  for (int y = 0; y < image.height; ++y) {
    std::uint32_t* out = impl_->row(y);
    for (int x = 0; x < image.width; ++x) {
      const Rgb c = image.at(x, y);
      out[x] = (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | c.b;
    }
  }
  cairo_surface_mark_dirty(impl_->surface);
}

Canvas::~Canvas() = default;

int Canvas::width() const { return impl_->width; }
int Canvas::height() const { return impl_->height; }

void Canvas::line(Point2 a, Point2 b, Rgb colour, double width_px) { polyline({a, b}, colour, width_px); }

void Canvas::polyline(const std::vector<Point2>& points, Rgb colour, double width_px) {
  if (points.size() < 2) return;
  cairo_t* cr = impl_->cr;
  cairo_move_to(cr, points[0].x, points[0].y);
  for (std::size_t k = 1; k < points.size(); ++k) cairo_line_to(cr, points[k].x, points[k].y);
  cairo_set_line_width(cr, width_px);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  set_colour(cr, colour);
  cairo_stroke(cr);
}

void Canvas::fill_rect(Point2 a, Point2 b, Rgb colour) {
  cairo_t* cr = impl_->cr;
  cairo_rectangle(cr, std::min(a.x, b.x), std::min(a.y, b.y), std::abs(b.x - a.x), std::abs(b.y - a.y));
  set_colour(cr, colour);
  cairo_fill(cr);
}

void Canvas::stroke_rect(Point2 a, Point2 b, Rgb colour, double width_px) {
  cairo_t* cr = impl_->cr;
  cairo_rectangle(cr, std::min(a.x, b.x), std::min(a.y, b.y), std::abs(b.x - a.x), std::abs(b.y - a.y));
  cairo_set_line_width(cr, width_px);
  set_colour(cr, colour);
  cairo_stroke(cr);
}

void Canvas::marker(Point2 c, double r, Marker shape, Rgb colour) {
  cairo_t* cr = impl_->cr;
  switch (shape) {
    case Marker::Circle: cairo_arc(cr, c.x, c.y, r, 0, 2 * std::numbers::pi); break;
    case Marker::Square: cairo_rectangle(cr, c.x - r / std::sqrt(2.0), c.y - r / std::sqrt(2.0), r * std::sqrt(2.0), r * std::sqrt(2.0)); break;
    case Marker::Diamond:
      cairo_move_to(cr, c.x, c.y - r);
      cairo_line_to(cr, c.x + r, c.y);
      cairo_line_to(cr, c.x, c.y + r);
      cairo_line_to(cr, c.x - r, c.y);
      cairo_close_path(cr);
      break;
    case Marker::Triangle:  // pointing up, centred on its circumcentre
      cairo_move_to(cr, c.x, c.y - r);
      cairo_line_to(cr, c.x + r * std::sqrt(3.0) / 2, c.y + r / 2);
      cairo_line_to(cr, c.x - r * std::sqrt(3.0) / 2, c.y + r / 2);
      cairo_close_path(cr);
      break;
  }
  set_colour(cr, colour);
  cairo_fill(cr);
}

void Canvas::text(Point2 at, std::string_view utf8, const TextStyle& style) {
  cairo_t* cr = impl_->cr;
  const double width = advance(cr, utf8, style);
  const double baseline = at.y + baseline_offset(cr, style);
  set_font(cr, style);
  set_colour(cr, style.colour);
  cairo_move_to(cr, start_x(at.x, width, style.h), baseline);
  const std::string s(utf8);
  cairo_show_text(cr, s.c_str());
  cairo_new_path(cr);
}

void Canvas::power_of_ten(Point2 at, int exponent, const TextStyle& style) {
  cairo_t* cr = impl_->cr;
  TextStyle small = style;
  small.size_px = style.size_px * kExponentScale;
  const double base = advance(cr, "10", style);
  const double left = start_x(at.x, power_of_ten_width(exponent, style), style.h);
  const double baseline = at.y + baseline_offset(cr, style);
  TextStyle plain = style;
  plain.h = HAlign::Left;
  plain.v = VAlign::Baseline;
  text({left, baseline}, "10", plain);
  small.h = HAlign::Left;
  small.v = VAlign::Baseline;
  text({left + base, baseline - kExponentRise * style.size_px}, exponent_text(exponent), small);
}

Image Canvas::pixels() const {
  cairo_surface_flush(impl_->surface);
  Image out(impl_->width, impl_->height);
  for (int y = 0; y < impl_->height; ++y) {
    const std::uint32_t* in = impl_->row(y);
    for (int x = 0; x < impl_->width; ++x)
      out.set(x, y, {static_cast<std::uint8_t>(in[x] >> 16), static_cast<std::uint8_t>(in[x] >> 8), static_cast<std::uint8_t>(in[x])});
  }
  return out;
}

void Canvas::write_png(const std::string& path) const {
  cairo_surface_flush(impl_->surface);
  check(cairo_surface_write_to_png(impl_->surface, path.c_str()), "cannot write " + path);
}

double text_width(std::string_view utf8, const TextStyle& style) {
  Measure m;
  return advance(m.cr, utf8, style);
}

double power_of_ten_width(int exponent, const TextStyle& style) {
  Measure m;
  TextStyle small = style;
  small.size_px = style.size_px * kExponentScale;
  return advance(m.cr, "10", style) + advance(m.cr, exponent_text(exponent), small);
}

std::string picture_font_family() {
  static std::once_flag once;
  static std::string family;
  std::call_once(once, [] {
    FcPattern* pattern = FcNameParse(reinterpret_cast<const FcChar8*>(kFamily));
    FcConfigSubstitute(nullptr, pattern, FcMatchPattern);
    FcDefaultSubstitute(pattern);
    FcResult result = FcResultNoMatch;
    FcPattern* match = FcFontMatch(nullptr, pattern, &result);
    FcChar8* name = nullptr;
    if (match && FcPatternGetString(match, FC_FAMILY, 0, &name) == FcResultMatch) family = reinterpret_cast<const char*>(name);
    if (match) FcPatternDestroy(match);
    FcPatternDestroy(pattern);
  });
  if (family != kFamily)
    throw std::runtime_error(std::string("pictures are drawn in ") + kFamily + ", which fontconfig does not find (it offers '" +
                             family + "'): install fonts-dejavu-core");
  return family;
}

void write_png(const Image& image, const std::string& path) { Canvas(image).write_png(path); }

}  // namespace lambert
