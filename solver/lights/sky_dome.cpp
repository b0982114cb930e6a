// The sky and the ground seen from a point (see sky_dome.h).
#include "solver/lights/sky_dome.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "mesh/convex2d.h"
#include "solver/cubature.h"
#include "solver/glazing.h"

namespace lambert {
namespace {

// Refinement depth of a fan triangle's cubature (1:4 splits; about the sun, where the kink sits at a
// vertex, every level removes a quarter of the error's support).
constexpr int kSkyCubatureDepth = 10;

// The twenty triangles of the box about p, each facing p: sky first (kSkyTriangles), then ground.
constexpr int kSkyTriangles = 10, kBoxTriangles = 20;
std::array<Triangle, kBoxTriangles> box_about(const Point3& p, const Vector3& up, double R) {
  const Vector3 e1 = perpendicular(up), e2 = cross(up, e1);
  auto corner = [&](double i, double j, double k) { return p + (e1 * i + e2 * j + up * k) * R; };
  std::array<Triangle, kBoxTriangles> out;
  int count = 0;
  auto quad = [&](const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    for (Triangle t : {Triangle{{a, b, c}}, Triangle{{a, c, d}}}) {
      if (dot(t.area_vector(), p - t.v[0]) < 0) std::swap(t.v[1], t.v[2]);  // front towards p
      out[count++] = t;
    }
  };
  // Sky: the top, then the upper halves of the sides (k from 0 to 1).
  quad(corner(-1, -1, 1), corner(1, -1, 1), corner(1, 1, 1), corner(-1, 1, 1));
  const double sides[4][4] = {{1, -1, 1, 1}, {-1, -1, -1, 1}, {-1, 1, 1, 1}, {-1, -1, 1, -1}};
  for (const auto& s : sides)  // from (s0, s1) to (s2, s3) along the side
    quad(corner(s[0], s[1], 0), corner(s[2], s[3], 0), corner(s[2], s[3], 1), corner(s[0], s[1], 1));
  // Ground: the lower halves of the sides, then the bottom.
  for (const auto& s : sides)
    quad(corner(s[0], s[1], -1), corner(s[2], s[3], -1), corner(s[2], s[3], 0), corner(s[0], s[1], 0));
  quad(corner(-1, -1, -1), corner(1, -1, -1), corner(1, 1, -1), corner(-1, 1, -1));
  return out;
}

// Whether the 2D point q lies in the closed convex loop (either orientation).
bool inside_convex(const Loop2d& loop, const Point2d& q) {
  bool left = true, right = true;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const double c = cross2(loop[i], loop[(i + 1) % loop.size()], q);
    left = left && c >= 0;
    right = right && c <= 0;
  }
  return left || right;
}

// ∫ f(ω) (n·ω) dω over the region's loops by the fan cubature (sky_dome.h); `sun`: the direction
// of f's kink, or null.
template <class Luminance>
double region_integral(const ExactVisibility::VisibleRegion& region, const Point3& p, const Vector3& n,
                       Luminance&& f, const Vector3* sun_kink, double abs_tolerance) {
  const Point3& o = region.origin();
  const Vector3 &e1 = region.e1(), &e2 = region.e2();
  const Vector3 normal = cross(e1, e2);
  const double h = std::abs(dot(normal, p - o));
  if (!(h > 0)) return 0;
  auto to_space = [&](const Point2d& y) { return o + e1 * y[0] + e2 * y[1]; };
  // The integrand per unit area of the plane: (L/L_z)(d/r) (n·d) h / r⁴.
  auto integrand = [&](const Point3& y) {
    const Vector3 d = y - p;
    const double r2 = length_squared(d), r = std::sqrt(r2);
    return f(d / r) * std::max(0.0, dot(n, d)) * h / (r2 * r2);
  };
  // Where the sun's direction meets the plane (in front of p), in the plane's coordinates.
  bool sun_on_plane = false;
  Point2d sun{0, 0};
  if (sun_kink) {
    const double towards = dot(*sun_kink, normal), height = dot(o - p, normal);
    if (towards * height > 0) {
      const Point3 y = p + *sun_kink * (height / towards);
      sun = {dot(y - o, e1), dot(y - o, e2)};
      sun_on_plane = true;
    }
  }
  const TriangleRule rule = triangle_rule_degree5();
  double total = 0;
  for (const Loop2d& loop : region.loops()) {
    if (loop.size() < 3) continue;
    const Point2d apex = sun_on_plane && inside_convex(loop, sun) ? sun : loop[0];
    const Point3 a = to_space(apex);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point2d &b2 = loop[i], &c2 = loop[(i + 1) % loop.size()];
      const double orientation = cross2(apex, b2, c2);
      if (orientation == 0) continue;  // the fan's degenerate triangles (apex on the edge)
      const Triangle t{{a, to_space(b2), to_space(c2)}};
      const double coarse = apply_rule(rule, t, integrand);
      const double value = integrate_adaptive(t, integrand, coarse, abs_tolerance, kSkyCubatureDepth);
      total += orientation > 0 ? value : -value;
    }
  }
  return total;
}

}  // namespace

double sky_integral_over_region(const ExactVisibility::VisibleRegion& region, const Point3& p, const Vector3& n,
                                const SkyDistribution& sky, double abs_tolerance) {
  const Vector3 sun = sky.has_sun_kink() ? sky.sun() : Vector3{};
  return region_integral(
      region, p, n, [&](const Vector3& w) { return sky.relative_luminance(w); }, sky.has_sun_kink() ? &sun : nullptr,
      abs_tolerance);
}

double weighted_integral_over_region(const ExactVisibility::VisibleRegion& region, const Point3& p, const Vector3& n,
                                     const SkyDistribution& sky, bool ground,
                                     const std::function<double(const Vector3&)>& weight, double abs_tolerance) {
  const Vector3 sun = sky.has_sun_kink() ? sky.sun() : Vector3{};
  auto f = [&](const Vector3& w) { return (ground ? 1.0 : sky.relative_luminance(w)) * weight(w); };
  return region_integral(region, p, n, f, !ground && sky.has_sun_kink() ? &sun : nullptr, abs_tolerance);
}

struct SkyDome::Window {
  std::unique_ptr<ExactVisibility> open;  // every occluder but the channel's panes
  Vector3 normal;                         // the panes' (up to sign)
};

SkyDome::SkyDome(std::span<const Triangle> occluders, const SkyDistribution& sky, std::span<const int> solid,
                 std::span<const char> convex, std::span<const SolidCap> caps, std::span<const int> pane_channel)
    : exact_(occluders, solid, convex, caps), sky_(sky) {
  exact_.set_inclusion_exclusion_limit(0);
  for (const Triangle& t : occluders)
    for (const Point3& v : t.v) scene_.add(v);
  int channels = 0;
  for (int c : pane_channel) channels = std::max(channels, c + 1);
  for (int c = 0; c < channels; ++c) {
    std::vector<Triangle> others;
    auto window = std::make_unique<Window>();
    bool first = true;
    for (std::size_t t = 0; t < occluders.size(); ++t) {
      if (pane_channel[t] != c) {
        others.push_back(occluders[t]);
        continue;
      }
      const Vector3 m = occluders[t].normal();
      if (first) window->normal = m, first = false;
      // g depends on the angle to the pane's normal: one normal per channel (either sign).
      if (std::abs(dot(m, window->normal)) < 1 - 1e-9)
        throw std::invalid_argument(
            "the sky through clear glass needs the panes of one material parallel (give panes of another "
            "orientation a material of their own)");
    }
    window->open = std::make_unique<ExactVisibility>(others);  // no solids: they may hold the panes
    window->open->set_inclusion_exclusion_limit(0);
    windows_.push_back(std::move(window));
  }
}

SkyDome::~SkyDome() = default;

template <class Visit>
void SkyDome::visit_box(const Point3& p, const Vector3& n, const ExactVisibility& exact, Visit&& visit) const {
  double reach = 0;
  if (!scene_.empty())
    for (int k = 0; k < 8; ++k) reach = std::max(reach, distance(scene_.corner(k), p));
  // Every occluder lies within `reach` of p, so inside the box; beyond it by half as much again.
  const double R = 1.5 * std::max(reach, 1e-3 * (1 + length(to_vector(p))));
  const std::array<Triangle, kBoxTriangles> box = box_about(p, sky_.up(), R);
  for (int k = 0; k < kBoxTriangles; ++k) {
    const ExactVisibility::VisibleRegion region = exact.visible_region(p, n, box[k]);
    if (!region.loops().empty()) visit(k >= kSkyTriangles, box[k], region);
  }
}

SkyFactors SkyDome::at(const Point3& p, const Vector3& n) const {
  const double abs_tolerance = kRelTolerance * sky_.horizontal_factor();
  SkyFactors out;
  visit_box(p, n, exact_, [&](bool ground, const Triangle& tri, const ExactVisibility::VisibleRegion& region) {
    if (ground) {
      out.ground += kPi * region.factor_of(tri);
    } else if (sky_.is_uniform()) {
      out.sky += kPi * region.factor_of(tri);
    } else {
      out.sky += sky_integral_over_region(region, p, n, sky_, abs_tolerance);
    }
  });
  return out;
}

SkyFactors SkyDome::through(int channel, const Point3& p, const Vector3& n) const {
  const Window& window = *windows_[static_cast<std::size_t>(channel)];
  const double abs_tolerance = kRelTolerance * sky_.horizontal_factor();
  const std::function<double(const Vector3&)> g = [&](const Vector3& w) {
    return pane_angular_factor(dot(w, window.normal));
  };
  SkyFactors out;
  // ∫ over V_c minus ∫ over V (sky_dome.h).
  for (const double sign : {1.0, -1.0})
    visit_box(p, n, sign > 0 ? *window.open : exact_,
              [&](bool ground, const Triangle&, const ExactVisibility::VisibleRegion& region) {
                const double v = weighted_integral_over_region(region, p, n, sky_, ground, g, abs_tolerance);
                (ground ? out.ground : out.sky) += sign * v;
              });
  return out;
}

template <class PointFactors>
SkyFactors SkyDome::average_of(const Triangle& t, PointFactors&& at) const {
  const TriangleRule rule = triangle_rule_degree5();
  const Vector3 n = t.normal();
  SkyFactors out;
  for (int q = 0; q < rule.size; ++q) {
    const auto& w = rule.nodes[q];
    const SkyFactors f = at(barycentric(t.v[0], t.v[1], t.v[2], w[0], w[1], w[2]), n);
    out.sky += rule.weights[q] * f.sky;
    out.ground += rule.weights[q] * f.ground;
  }
  return out;
}

SkyFactors SkyDome::average(const Triangle& t) const {
  return average_of(t, [&](const Point3& p, const Vector3& n) { return at(p, n); });
}

SkyFactors SkyDome::average_through(int channel, const Triangle& t) const {
  return average_of(t, [&](const Point3& p, const Vector3& n) { return through(channel, p, n); });
}

}  // namespace lambert
