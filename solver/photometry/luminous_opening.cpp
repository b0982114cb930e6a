// The luminous opening's faces, projected area and solid angle (luminous_opening.h).
#include "solver/photometry/luminous_opening.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "solver/form_factor.h"
#include "solver/spectrum.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

// Gauss–Legendre nodes and weights on [0, 1] (6 points), for the opening's moments.
constexpr std::array<double, 6> kGaussX = {0.033765242898423975, 0.16939530676686776, 0.38069040695840156,
                                           0.61930959304159844, 0.83060469323313224, 0.96623475710157603};
constexpr std::array<double, 6> kGaussW = {0.085662246189585178, 0.18038078652406930, 0.23395696728634552,
                                           0.23395696728634552, 0.18038078652406930, 0.085662246189585178};

}  // namespace

Point3 LuminousFace::point(double s, double t) const {
  switch (kind) {
    case Kind::kParallelogram: return origin + u * s + v * t;
    case Kind::kEllipse: return origin + (u * std::cos(2 * kPi * t) + v * std::sin(2 * kPi * t)) * s;
    case Kind::kCylinderSide: return origin + axis * t + u * std::cos(2 * kPi * s) + v * std::sin(2 * kPi * s);
    case Kind::kSphere: {
      const double polar = kPi * s, azimuth = 2 * kPi * t;
      return origin + (normalize(u) * (std::sin(polar) * std::cos(azimuth)) +
                       normalize(v) * (std::sin(polar) * std::sin(azimuth)) + normalize(axis) * std::cos(polar)) *
                          radius;
    }
  }
  return origin;
}

Vector3 LuminousFace::normal(double s, double t) const {
  switch (kind) {
    case Kind::kParallelogram:
    case Kind::kEllipse: return normalize(cross(u, v));
    case Kind::kCylinderSide: return normalize(u * std::cos(2 * kPi * s) + v * std::sin(2 * kPi * s));
    case Kind::kSphere: return (point(s, t) - origin) / radius;
  }
  return {0, 0, 1};
}

double LuminousFace::jacobian(double s, double t) const {
  switch (kind) {
    case Kind::kParallelogram: return length(cross(u, v));
    case Kind::kEllipse: return 2 * kPi * s * length(cross(u, v));
    case Kind::kCylinderSide: return 2 * kPi * length(u) * length(axis);
    case Kind::kSphere: return 2 * kPi * kPi * radius * radius * std::sin(kPi * s);
  }
  return 0;
}

double LuminousFace::area() const {
  switch (kind) {
    case Kind::kParallelogram: return length(cross(u, v));
    case Kind::kEllipse: return kPi * length(cross(u, v));
    case Kind::kCylinderSide: return 2 * kPi * length(u) * length(axis);
    case Kind::kSphere: return 4 * kPi * radius * radius;
  }
  return 0;
}

double LuminousFace::projected_area(const Vector3& w) const {
  switch (kind) {
    case Kind::kParallelogram:
    case Kind::kEllipse: {
      const double c = dot(normalize(cross(u, v)), w);
      return area() * (two_sided ? std::abs(c) : std::max(0.0, c));
    }
    case Kind::kCylinderSide: {  // the lit half of a circular cylinder's side: 2 R ℓ sin(axis, w)
      const double c = dot(normalize(axis), w);
      return 2 * length(u) * length(axis) * std::sqrt(std::max(0.0, 1 - c * c));
    }
    case Kind::kSphere: return kPi * radius * radius;
  }
  return 0;
}

double LuminousFace::facing(double s, double t, const Vector3& w) const {
  const double c = dot(normal(s, t), w);
  return two_sided ? std::abs(c) : std::max(0.0, c);
}

void LuminousOpening::add(LuminousFace f) {
  if (!(f.area() > 0)) return;
  int cells_s = 1, cells_t = 1;
  switch (f.kind) {
    case LuminousFace::Kind::kParallelogram: break;
    case LuminousFace::Kind::kEllipse: cells_t = 4; break;
    case LuminousFace::Kind::kCylinderSide: cells_s = 4; break;
    case LuminousFace::Kind::kSphere: cells_s = 2, cells_t = 4; break;
  }
  for (int i = 0; i < cells_s; ++i)
    for (int j = 0; j < cells_t; ++j) {
      const double s0 = static_cast<double>(i) / cells_s, s1 = static_cast<double>(i + 1) / cells_s;
      const double t0 = static_cast<double>(j) / cells_t, t1 = static_cast<double>(j + 1) / cells_t;
      f.cells.push_back(Triangle{{Point3{s0, t0, 0}, Point3{s1, t0, 0}, Point3{s1, t1, 0}}});
      f.cells.push_back(Triangle{{Point3{s0, t0, 0}, Point3{s1, t1, 0}, Point3{s0, t1, 0}}});
    }
  faces_.push_back(std::move(f));
}

LuminousOpening::LuminousOpening(const LuminousDimensions& d, const Point3& centre, const Vector3& c0,
                                 const Vector3& c90, const Vector3& up)
    : shape_(d.shape), centre_(centre), c0_(c0), c90_(c90), up_(up), length_(d.length_m), width_(d.width_m),
      height_(d.height_m) {
  auto at = [&](double x, double y, double z) { return centre + c0 * x + c90 * y + up * z; };
  auto vec = [&](double x, double y, double z) { return c0 * x + c90 * y + up * z; };
  using Kind = LuminousFace::Kind;
  auto face = [&](Kind kind, const Point3& o, const Vector3& u, const Vector3& v, const Vector3& axis, double radius,
                  bool two_sided) {
    LuminousFace f;
    f.kind = kind, f.origin = o, f.u = u, f.v = v, f.axis = axis, f.radius = radius, f.two_sided = two_sided;
    add(std::move(f));
  };
  auto quad = [&](const Point3& o, const Vector3& u, const Vector3& v, bool two_sided = false) {
    face(Kind::kParallelogram, o, u, v, {}, 0, two_sided);
  };
  auto ellipse = [&](const Point3& o, const Vector3& u, const Vector3& v, bool two_sided = false) {
    face(Kind::kEllipse, o, u, v, {}, 0, two_sided);
  };
  // A circular cylinder from `base` along `axis`, radius vectors u ⟂ v, with its two end disks.
  auto cylinder = [&](const Point3& base, const Vector3& axis, const Vector3& u, const Vector3& v) {
    face(Kind::kCylinderSide, base, u, v, axis, 0, false);
    ellipse(base, v, u);         // normal −axis
    ellipse(base + axis, u, v);  // normal +axis
  };
  const double l = length_, w = width_, h = height_;
  const double z0 = d.sides_rise_from_centre ? 0 : -h / 2;
  switch (d.shape) {
    case LuminousShape::kPoint:
    case LuminousShape::kUnsupported: break;
    case LuminousShape::kRectangle: quad(at(-l / 2, -w / 2, 0), vec(l, 0, 0), vec(0, w, 0), true); break;
    case LuminousShape::kDisk:
    case LuminousShape::kEllipse: ellipse(at(0, 0, 0), vec(l / 2, 0, 0), vec(0, w / 2, 0), true); break;
    case LuminousShape::kBox:
    case LuminousShape::kSideFaces: {
      // Side heights: LM-63's box has one height, EULUMDAT's sides their own (C0, C90, C180, C270).
      const std::array<double, 4> hs = d.shape == LuminousShape::kBox ? std::array<double, 4>{h, h, h, h} : d.side_height_m;
      quad(at(-l / 2, -w / 2, z0), vec(0, w, 0), vec(l, 0, 0));        // bottom, facing down
      quad(at(-l / 2, -w / 2, z0 + h), vec(l, 0, 0), vec(0, w, 0));    // top, facing up
      quad(at(l / 2, -w / 2, z0), vec(0, w, 0), vec(0, 0, hs[0]));     // facing C0
      quad(at(-l / 2, w / 2, z0), vec(0, 0, hs[1]), vec(l, 0, 0));     // facing C90
      quad(at(-l / 2, -w / 2, z0), vec(0, 0, hs[2]), vec(0, w, 0));    // facing C180
      quad(at(-l / 2, -w / 2, z0), vec(l, 0, 0), vec(0, 0, hs[3]));    // facing C270
      break;
    }
    case LuminousShape::kVerticalCylinder:
      cylinder(at(0, 0, z0), vec(0, 0, h), vec(l / 2, 0, 0), vec(0, l / 2, 0));
      break;
    case LuminousShape::kHorizontalCylinderAlongC0:
      cylinder(at(-l / 2, 0, 0), vec(l, 0, 0), vec(0, w / 2, 0), vec(0, 0, w / 2));
      break;
    case LuminousShape::kHorizontalCylinderAlongC90:
      cylinder(at(0, -w / 2, 0), vec(0, w, 0), vec(0, 0, l / 2), vec(l / 2, 0, 0));
      break;
    case LuminousShape::kSphere:
      face(Kind::kSphere, centre, c0, c90, up, l / 2, false);
      break;
  }
  // Area, <|q − centre|²> and the largest radius, by a 6 × 6 Gauss rule over each face.
  double moment = 0;
  for (const LuminousFace& f : faces_) {
    area_ += f.area();
    for (std::size_t i = 0; i < kGaussX.size(); ++i)
      for (std::size_t j = 0; j < kGaussX.size(); ++j) {
        const Point3 q = f.point(kGaussX[i], kGaussX[j]);
        moment += kGaussW[i] * kGaussW[j] * f.jacobian(kGaussX[i], kGaussX[j]) * length_squared(q - centre);
      }
    for (double s : {0.0, 0.25, 0.5, 0.75, 1.0})
      for (double t : {0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0})
        radius_ = std::max(radius_, distance(f.point(s, t), centre));
  }
  if (area_ > 0) mean_square_radius_ = moment / area_;
  const int F = static_cast<int>(faces_.size());
  for (int k = 0; F > 0 && k < kMaxVisibilitySamples; ++k) {
    const LuminousFace& f = faces_[k % F];
    const Point3 st = visibility_sample(f.cells[static_cast<std::size_t>(k / F) % f.cells.size()], k);
    samples_.push_back({f.point(st.x, st.y), k % F, st.x, st.y});
  }
}

double LuminousOpening::projected_area_m2(const Vector3& w) const {
  double a = 0;
  for (const LuminousFace& f : faces_) a += f.projected_area(w);
  return a;
}

double LuminousOpening::solid_angle_sr(const Point3& eye) const {
  double omega = 0;
  for (const LuminousFace& f : faces_) {
    switch (f.kind) {
      case LuminousFace::Kind::kParallelogram:
      case LuminousFace::Kind::kEllipse: {
        const Vector3 n = f.normal(0, 0);
        const double side = dot(eye - f.origin, n);
        if (side == 0 || (!f.two_sided && side < 0)) break;
        const int sides = f.kind == LuminousFace::Kind::kEllipse ? 64 : 4;
        std::vector<Point3> rim;
        for (int k = 0; k < sides; ++k)
          rim.push_back(f.kind == LuminousFace::Kind::kEllipse ? f.point(1, static_cast<double>(k) / sides)
                                                               : f.point(k == 1 || k == 2, k >= 2));
        const Point3 hub = f.kind == LuminousFace::Kind::kEllipse ? f.origin : rim[0];
        for (int k = 0; k < sides; ++k) {
          if (f.kind == LuminousFace::Kind::kParallelogram && (k == 0 || k == sides - 1)) continue;
          omega += triangle_solid_angle(eye, Triangle{{hub, rim[k], rim[(k + 1) % sides]}});
        }
        break;
      }
      case LuminousFace::Kind::kCylinderSide:
      case LuminousFace::Kind::kSphere: {
        const Vector3 d = eye - centre_;
        const double r2 = length_squared(d);
        if (r2 > 0) omega += f.projected_area(d / std::sqrt(r2)) / r2;
        break;
      }
    }
  }
  return omega;
}

}  // namespace lambert
