// The checks of a .vs3 file's surfaces once every line is read (vs3_parse.h): View3D's own rules
// (SetPlane, GetSrfD and TestSubSrf in its getdat.c), with its tolerances, each broken rule an error
// that names the surface's line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "mesh/vs3_parse.h"

namespace lambert::vs3 {
namespace {

// Tolerances of View3D 3.3: a quadrilateral's corner may lie 3e-5 of its radius off its plane; a
// subsurface's corners 1e-5 of its radius off its base's plane; subsurface and base face the same
// way (or, for masks and null surfaces, opposite ways) to within cos = 0.999.
constexpr double kFlatness = 3e-5;
constexpr double kCoplanar = 1e-5;
constexpr double kFacing = 0.999;

struct Plane {
  Vector3 normal;  // unit, by Newell's method (counter-clockwise = front)
  Point3 centroid;
  double area = 0;
  double radius = 0;  // largest distance from the centroid to a corner
};

Plane plane_of(const std::vector<Point3>& p) {
  Vector3 n, sum;
  for (std::size_t k = 0; k < p.size(); ++k) {
    n += cross(to_vector(p[k]), to_vector(p[(k + 1) % p.size()]));
    sum += to_vector(p[k]);
  }
  Plane plane;
  plane.centroid = to_point(sum / static_cast<double>(p.size()));
  plane.area = 0.5 * length(n);
  for (const Point3& q : p) plane.radius = std::max(plane.radius, distance(q, plane.centroid));
  plane.normal = plane.area > 0 ? normalize(n) : Vector3{};
  return plane;
}

std::string surface_text(const Surface& s) {
  return "surface " + std::to_string(s.number) + (s.name.empty() ? "" : " (" + s.name + ")");
}

// The polygon itself: distinct corners, an area, and a quadrilateral planar and convex.
bool check_polygon(const Surface& s, Messages& messages) {
  const std::vector<Point3>& p = s.polygon;
  for (std::size_t a = 0; a < p.size(); ++a)
    for (std::size_t b = a + 1; b < p.size(); ++b)
      if (p[a] == p[b]) {
        messages.error(s.line, surface_text(s) + ": corners " + std::to_string(a + 1) + " and " +
                                   std::to_string(b + 1) + " coincide");
        return false;
      }
  const Plane plane = plane_of(p);
  if (!(plane.area > 1e-12 * plane.radius * plane.radius)) {
    messages.error(s.line, surface_text(s) + " has no area (its corners are collinear)");
    return false;
  }
  if (p.size() < 4) return true;
  for (const Point3& q : p) {
    const double off = std::abs(dot(q - plane.centroid, plane.normal)) / plane.radius;
    if (off > kFlatness) {
      char text[64];
      std::snprintf(text, sizeof text, "%.2g", off);
      messages.error(s.line, surface_text(s) + ": its corners are not in one plane (one lies " + text +
                                 " of its radius off it; View3D allows 3e-5)");
      return false;
    }
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const Vector3 in = p[k] - p[(k + 3) % 4], out = p[(k + 1) % 4] - p[k];
    if (!(dot(cross(in, out), plane.normal) > 1e-12 * plane.radius * plane.radius)) {
      messages.error(s.line, surface_text(s) + " is not a convex quadrilateral (corner " + std::to_string(k + 1) +
                                 "); split it into two triangles and combine them");
      return false;
    }
  }
  return true;
}

// The references between surfaces: bases and combinations (View3D's GetSrfD).
bool check_references(const Input& input, const Surface& s, Messages& messages) {
  const int count = static_cast<int>(input.surfaces.size());
  const std::string who = surface_text(s);
  const bool mask_or_null = s.kind == SurfaceKind::Mask || s.kind == SurfaceKind::Null;
  bool ok = true;
  if (mask_or_null && s.base == 0) {
    messages.error(s.line, who + ": a mask or null surface needs a base (the surface it covers)");
    ok = false;
  }
  if (s.base > 0) {
    const Surface* b = s.base <= count ? &input.surfaces[s.base - 1] : nullptr;
    if (!b || s.base == s.number) {
      messages.error(s.line, who + ": base " + std::to_string(s.base) + " is not another surface of the file");
      ok = false;
    } else if (mask_or_null ? b->kind != SurfaceKind::Radiating
                            : b->kind == SurfaceKind::Mask || b->kind == SurfaceKind::Null) {
      messages.error(s.line, who + ": base " + std::to_string(s.base) + " must be " +
                                 (mask_or_null ? "a radiating surface (S)" : "a radiating surface or an obstruction"));
      ok = false;
    } else if (s.base > s.number && b->kind != SurfaceKind::Obstruction) {
      messages.error(s.line, who + ": base " + std::to_string(s.base) + " must come before it");
      ok = false;
    }
  }
  if (s.combine > 0) {
    const Surface* c = s.combine < s.number ? &input.surfaces[s.combine - 1] : nullptr;
    if (s.kind != SurfaceKind::Radiating) {
      messages.error(s.line, who + ": only radiating surfaces (S) combine");
      ok = false;
    } else if (!c) {
      messages.error(s.line, who + ": combination " + std::to_string(s.combine) + " must be an earlier surface");
      ok = false;
    } else if (c->kind != SurfaceKind::Radiating || c->combine != 0) {
      messages.error(s.line, who + ": combination " + std::to_string(s.combine) +
                                 (c->combine != 0 ? " is itself combined with another (combine every part with the "
                                                    "lowest-numbered one; View3D does not chain them)"
                                                  : " must be a radiating surface (S)"));
      ok = false;
    }
  }
  return ok;
}

// A subsurface, mask or null surface in its base's plane, facing as its kind requires, and inside
// the base (View3D's TestSubSrf). The base is convex (check_polygon), so the part lies inside it
// when every corner of the part does.
void check_inside_base(const Surface& s, const Surface& base, Messages& messages) {
  const Plane sp = plane_of(s.polygon), bp = plane_of(base.polygon);
  const std::string who = surface_text(s), base_text = "base " + std::to_string(base.number);
  for (const Point3& q : s.polygon)
    if (std::abs(dot(q - bp.centroid, bp.normal)) > kCoplanar * sp.radius) {
      messages.error(s.line, who + " does not lie in the plane of its " + base_text);
      return;
    }
  const double facing = dot(sp.normal, bp.normal);
  if (s.kind == SurfaceKind::Radiating ? facing < kFacing : facing > -kFacing) {
    messages.error(s.line, who + (s.kind == SurfaceKind::Radiating ? " must face the way its " + base_text + " faces"
                                                                   : " must face its " + base_text +
                                                                         " (the opposite way)"));
    return;
  }
  const double tolerance = 1e-6 * std::sqrt(sp.area);
  for (const Point3& q : s.polygon)
    for (std::size_t k = 0; k < base.polygon.size(); ++k) {
      const Point3& a = base.polygon[k];
      const Vector3 edge = base.polygon[(k + 1) % base.polygon.size()] - a;
      if (dot(cross(edge, q - a), bp.normal) < -tolerance * length(edge)) {
        messages.error(s.line, who + " is not inside its " + base_text);
        return;
      }
    }
}

}  // namespace

void check_surfaces(const Input& input, Messages& messages) {
  std::vector<char> sound(input.surfaces.size(), 0);
  for (std::size_t i = 0; i < input.surfaces.size(); ++i) sound[i] = check_polygon(input.surfaces[i], messages);
  for (std::size_t i = 0; i < input.surfaces.size(); ++i) {
    const Surface& s = input.surfaces[i];
    if (!check_references(input, s, messages) || s.base == 0) continue;
    if (sound[i] && sound[s.base - 1]) check_inside_base(s, input.surfaces[s.base - 1], messages);
  }
}

}  // namespace lambert::vs3
