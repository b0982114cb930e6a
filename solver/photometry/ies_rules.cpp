// LM-63's rules on what a file's numbers may be: the luminous opening's shape from the signs of its
// dimensions, and the angle ranges of each photometric type (photometric_text.h). Also the names
// photometric_data.h gives the types and shapes.
#include <cmath>

#include "solver/photometry/photometric_text.h"

namespace lambert {

const char* photometry_type_name(PhotometryType type) {
  switch (type) {
    case PhotometryType::kC: return "C";
    case PhotometryType::kB: return "B";
    case PhotometryType::kA: return "A";
  }
  return "C";
}

const char* luminous_shape_name(LuminousShape shape) {
  switch (shape) {
    case LuminousShape::kPoint: return "point";
    case LuminousShape::kRectangle: return "rectangle";
    case LuminousShape::kBox: return "box";
    case LuminousShape::kDisk: return "disk";
    case LuminousShape::kEllipse: return "ellipse";
    case LuminousShape::kVerticalCylinder: return "vertical cylinder";
    case LuminousShape::kSphere: return "sphere";
    case LuminousShape::kHorizontalCylinderAlongC0: return "horizontal cylinder along C0-C180";
    case LuminousShape::kHorizontalCylinderAlongC90: return "horizontal cylinder along C90-C270";
    case LuminousShape::kSideFaces: return "luminous area with sides";
    case LuminousShape::kUnsupported: return "unsupported";
  }
  return "point";
}

namespace photometry_io {
namespace {

int sign(double v) { return v < 0 ? -1 : v > 0 ? 1 : 0; }

// Relative equality of two dimensions (the same diameter written twice).
bool same(double a, double b) { return std::abs(std::abs(a) - std::abs(b)) <= 1e-9 * (std::abs(a) + std::abs(b)); }

LuminousDimensions shape(LuminousShape s, double length, double width, double height, std::string description) {
  LuminousDimensions d;
  d.shape = s;
  d.length_m = std::abs(length);
  d.width_m = std::abs(width);
  d.height_m = std::abs(height);
  d.description = std::move(description);
  return d;
}

LuminousDimensions unsupported(const std::string& what, double width, double length, double height) {
  LuminousDimensions d = shape(LuminousShape::kUnsupported, length, width, height, what);
  d.description = what;
  return d;
}

// LM-63-2002 and LM-63-2019, Table 1.
std::optional<LuminousDimensions> table_2002(double w, double l, double h) {
  const int sw = sign(w), sl = sign(l), sh = sign(h);
  if (sw > 0 && sl > 0 && sh == 0) return shape(LuminousShape::kRectangle, l, w, 0, "rectangle");
  if (sw >= 0 && sl >= 0 && sh > 0 && (sw > 0 || sl > 0)) return shape(LuminousShape::kBox, l, w, h, "rectangle with luminous sides");
  if (sw < 0 && sl < 0 && sh == 0)
    return same(w, l) ? shape(LuminousShape::kDisk, l, w, 0, "circle") : shape(LuminousShape::kEllipse, l, w, 0, "ellipse");
  if (sw < 0 && sl < 0 && sh > 0)
    return same(w, l) ? shape(LuminousShape::kVerticalCylinder, l, w, h, "vertical cylinder")
                      : unsupported("vertical ellipsoidal cylinder", w, l, h);
  if (sw < 0 && sl < 0 && sh < 0)
    return same(w, l) && same(l, h) ? shape(LuminousShape::kSphere, l, w, h, "sphere") : unsupported("ellipsoidal spheroid", w, l, h);
  if (sw < 0 && sl > 0 && sh < 0)
    return same(w, h) ? shape(LuminousShape::kHorizontalCylinderAlongC0, l, w, h, "horizontal cylinder along photometric horizontal")
                      : unsupported("horizontal ellipsoidal cylinder along photometric horizontal", w, l, h);
  if (sw > 0 && sl < 0 && sh < 0)
    return same(l, h) ? shape(LuminousShape::kHorizontalCylinderAlongC90, l, w, h,
                              "horizontal cylinder perpendicular to photometric horizontal")
                      : unsupported("horizontal ellipsoidal cylinder perpendicular to photometric horizontal", w, l, h);
  if (sw == 0 && sl < 0 && sh < 0) return unsupported("vertical circle or ellipse facing photometric horizontal", w, l, h);
  return std::nullopt;
}

// LM-63-1995 (and, where they agree, 1986 and 1991): a negative width with length 0 is a circle's
// diameter.
std::optional<LuminousDimensions> table_1995(int year, double w, double l, double h) {
  const int sw = sign(w), sl = sign(l), sh = sign(h);
  if (sw > 0 && sl > 0 && sh == 0) return shape(LuminousShape::kRectangle, l, w, 0, "rectangle");
  if (sw >= 0 && sl >= 0 && sh > 0 && (sw > 0 || sl > 0)) return shape(LuminousShape::kBox, l, w, h, "rectangle with luminous sides");
  if (sw < 0 && sl == 0 && sh == 0) return shape(LuminousShape::kDisk, w, w, 0, "circle");
  if (sw < 0 && sl == 0 && sh > 0) return shape(LuminousShape::kVerticalCylinder, w, w, h, "vertical cylinder");
  if (year == 1995) {
    if (sw < 0 && sl == 0 && sh < 0)
      return same(w, h) ? shape(LuminousShape::kSphere, w, w, h, "sphere") : unsupported("ellipsoid", w, l, h);
    if (sw < 0 && sl > 0 && sh < 0)
      return same(w, h) ? shape(LuminousShape::kHorizontalCylinderAlongC0, l, w, h, "horizontal cylinder along photometric horizontal")
                        : unsupported("horizontal ellipsoidal cylinder", w, l, h);
    if (sw > 0 && sl == 0 && sh < 0) return shape(LuminousShape::kHorizontalCylinderAlongC90, h, w, h,
                                                  "horizontal cylinder perpendicular to photometric horizontal");
    if ((sl < 0) != (sw < 0) && sh >= 0) return unsupported("vertical ellipsoidal cylinder", w, l, h);
    if ((sl < 0 || sw < 0) && sh < 0) return unsupported("ellipsoid", w, l, h);
  } else {
    if (sw < 0 && sl > 0 && sh == 0) return shape(LuminousShape::kEllipse, l, w, 0, "ellipse");
    if (sw < 0 && sl > 0 && sh > 0) return unsupported("ellipsoid", w, l, h);
  }
  return std::nullopt;
}

}  // namespace

LuminousDimensions ies_opening(int year, double width, double length, double height, std::size_t line) {
  if (width == 0 && length == 0 && height == 0) return shape(LuminousShape::kPoint, 0, 0, 0, "point");
  auto d = year >= 2002 ? table_2002(width, length, height) : table_1995(year, width, length, height);
  if (!d)
    fail(line, "luminous dimensions: width " + number_text(width) + ", length " + number_text(length) + ", height " +
                   number_text(height) + " (m) match no luminous shape of LM-63-" + std::to_string(year));
  return *d;
}

namespace {

// An axis a file lists symmetric (first −last) or mirrored (first 0, last within `most`).
void check_mirror_or_full(const std::vector<double>& a, std::size_t line, std::string_view what, double most,
                          std::string_view type) {
  const double first = a.front(), last = a.back();
  const bool ok = last > 0 && last <= most && (first == 0 || first == -last);
  if (!ok)
    fail(line, std::string(what) + ": " + number_text(first) + " to " + number_text(last) + "; type " +
                   std::string(type) + " takes 0 to a last angle in (0, " + number_text(most) +
                   "] (mirrored) or -a to a");
}

}  // namespace

void check_ies_ranges(PhotometryType type, const std::vector<double>& v, const std::vector<double>& h,
                      std::size_t v_line, std::size_t h_line) {
  switch (type) {
    case PhotometryType::kC: {
      if (!((v.front() == 0 || v.front() == 90) && (v.back() == 90 || v.back() == 180)))
        fail(v_line, "vertical angles: " + number_text(v.front()) + " to " + number_text(v.back()) +
                         "; type C takes 0 or 90 to 90 or 180");
      const double first = h.front(), last = h.back();
      const bool ok = h.size() == 1 ? first == 0
                                    : (first == 0 && (last == 90 || last == 180 || (last > 180 && last <= 360))) ||
                                          (first == 90 && last == 270);
      if (!ok)
        fail(h_line, "horizontal angles: " + number_text(first) + " to " + number_text(last) +
                         "; type C takes 0 alone, 0 to 90, 0 to 180, 0 to more than 180 and at most 360, or 90 to 270");
      return;
    }
    case PhotometryType::kB:
      if (h.size() < 2) fail(h_line, "horizontal angles: type B needs at least two");
      check_mirror_or_full(h, h_line, "horizontal angles", 90, "B");
      check_mirror_or_full(v, v_line, "vertical angles", 180, "B");
      return;
    case PhotometryType::kA:
      if (h.size() < 2) fail(h_line, "horizontal angles: type A needs at least two");
      check_mirror_or_full(h, h_line, "horizontal angles", 180, "A");
      check_mirror_or_full(v, v_line, "vertical angles", 90, "A");
      return;
  }
}

}  // namespace photometry_io
}  // namespace lambert
