// Phong-lobed emitting patch (SPEC §1 "Light models"): intensity per unit area
//   dI/dA(ψ) = R (n+1)/(2π ω0) cos^n ψ,   ψ from the patch's normal, n ≥ 1,
// so that the patch emits exactly R [W m^-2] (∫ (n+1)/(2π) cos^n ψ dω over the hemisphere is 1).
// Its irradiance at a receiving point p (normal n_p):
//   E(p) = R (n+1)/(2π) ∫_{emitter} cos^n ψ cos α / r² dA_q.
// - At a point: in p's directions ω the emitter is a spherical polygon and ψ is the angle between −ω
//   and the emitter's normal; with dω = cos ψ dA/r², E(p) = R (n+1)/(2π) ∫_{Ω(emitter)} cos^{n−1} ψ
//   (n_p·ω) dω: the cone integral about −normal with the receiver's cosine as the weight, after
//   clipping the emitter at p's horizon.
//   For a whole n that integral is Arvo's double-axis moment τ^{n−1,1}(emitter; −normal, n_p), exact
//   in O(n) operations (solver/lights/axial_moments.h); for other n the polar integral about −normal
//   (cone_integral) evaluates it numerically.
// - Over a receiving patch, for a whole n: the point value integrated over the receiver by the
//   adaptive cubature of the Lambertian form factors (solver/form_factor.cpp), so a lobed emitter
//   costs what a Lambertian one does. For other n: each emitter point q is a cos^n point source
//   aimed along the normal, the flux it sends into the patch is the exact cone integral, and the
//   emitter's area is integrated by adaptive cubature. For n = 1 either is A_i F_ij, the Lambertian
//   form factor, computed by another route.
#include <algorithm>
#include <array>
#include <cmath>

#include "solver/cubature.h"
#include "solver/form_factor.h"
#include "solver/lights/axial_moments.h"
#include "solver/lights/point_like.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

// Accuracy of a receiving patch's average: the cubature over the emitter refines 1:4 (to
// kEmitterCubatureDepth levels) until children and parent agree within kRelTolerance; each node's
// cone integral is computed to kConeTolerance.
constexpr double kRelTolerance = 1e-5;
constexpr int kEmitterCubatureDepth = 8;
constexpr double kConeTolerance = 1e-7;
// Whole exponents up to this take the double-axis moments: O(n) per point, against the polar
// integral's cost, which does not grow with n (a lobe of n = 10⁴ is 4 × 10⁴ recurrence steps).
constexpr double kMaxMomentExponent = 10000;

// The part of triangle t with (X − p)·n ≥ 0 (Sutherland–Hodgman); at most 4 vertices.
int clip_above(const Triangle& t, const Point3& p, const Vector3& n, std::array<Point3, 4>& out) {
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const Point3& a = t.v[i];
    const Point3& b = t.v[(i + 1) % 3];
    const double da = dot(a - p, n), db = dot(b - p, n);
    if (da >= 0) out[count++] = a;
    if ((da >= 0) != (db >= 0)) out[count++] = a + (b - a) * (da / (da - db));
  }
  return count;
}

// ∫_t f dA refined uniformly to min_depth levels (so that no sub-triangle is much larger than the
// receiver, whose beam footprint a narrow lobe draws on the emitter), then adaptively.
template <class F>
double integrate_graded(const Triangle& t, F& f, int min_depth, double rel_tolerance, double abs_tolerance) {
  if (min_depth > 0) {
    double sum = 0;
    for (const Triangle& c : split4(t)) sum += integrate_graded(c, f, min_depth - 1, rel_tolerance, abs_tolerance / 4);
    return sum;
  }
  const double coarse = apply_rule(triangle_rule_degree5(), t, f);
  return integrate_adaptive(t, f, coarse, std::max(abs_tolerance, rel_tolerance * std::abs(coarse)),
                            kEmitterCubatureDepth);
}

class PhongEmitterModel final : public LightModel {
 public:
  PhongEmitterModel(const Triangle& t, double n, std::vector<double> exitance)
      : emitter_(t), lobe_{t.normal(), n, kPi / 2}, area_(t.area()), exitance_(std::move(exitance)) {}

  const std::vector<double>& spectrum() const override { return exitance_; }

  double unshadowed_factor(const Point3& p, const Vector3& n) const override {
    if (dot(p - emitter_.v[0], lobe_.axis) <= 0) return 0;  // behind the emitter or in its plane
    std::array<Point3, 4> visible_part;
    const int count = clip_above(emitter_, p, n, visible_part);
    if (count < 3) return 0;
    const std::span<const Point3> part(visible_part.data(), count);
    if (by_moments()) return normalisation() * moment_at(p, n, part);
    // dA at the emitter subtends dω = cos ψ dA / r² at p, so the lobe in p's solid angle is cos^{n−1}.
    const ConeLobe seen_from_p{-lobe_.axis, lobe_.exponent - 1, kPi / 2};
    return normalisation() * cone_integral(p, seen_from_p, part, [&](const Vector3& w) { return std::max(0.0, dot(n, w)); });
  }

  double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const override {
    const double g = unshadowed_factor(p, n);
    if (g == 0) return 0;
    return g * weighted_visible_fraction(
                   vis, [&](int k) { return std::pair{p, visibility_sample(emitter_, k)}; },
                   [&](const Point3&, const Point3& q) { return kernel(q, p, n); });
  }

  // A receiver that is not planar sees the whole emitter (its weight w ≥ 0 in every direction): the
  // cone integral of cos^{n−1} ψ w(ω) over it, rays weighted by cos^n ψ w(ω) / r².
  double receiver_factor(const Receiver& r, const Visibility& vis) const override {
    if (r.kind == Receiver::Kind::Planar) return point_factor(r.point, r.normal, vis);
    const Point3& p = r.point;
    if (dot(p - emitter_.v[0], lobe_.axis) <= 0) return 0;
    const ConeLobe seen_from_p{-lobe_.axis, lobe_.exponent - 1, kPi / 2};
    const double g = normalisation() * cone_integral(p, seen_from_p, emitter_.v,
                                                     [&](const Vector3& w) { return receiver_weight(r, w); });
    if (!(g > 0)) return 0;
    return g * weighted_visible_fraction(
                   vis, [&](int k) { return std::pair{p, visibility_sample(emitter_, k)}; },
                   [&](const Point3&, const Point3& q) {
                     const Vector3 d = p - q;
                     const double r2 = length_squared(d);
                     if (r2 == 0) return 0.0;
                     const double dist = std::sqrt(r2);
                     return cone_lobe_value(lobe_, dot(lobe_.axis, d) / dist) * receiver_weight(r, -d / dist) / r2;
                   });
  }

  double patch_factor(const Triangle& t, const Visibility& vis) const override {
    const Vector3 nt = t.normal();
    if (!any_in_front(emitter_, lobe_.axis, t) || !any_in_front(t, nt, emitter_) || beyond_lobe(t)) return 0;
    const double G = by_moments() ? receiver_integral(t, nt) : emitter_integral(t, nt);
    const double average = normalisation() * G / t.area();
    if (!(average > 0)) return 0;
    return average * weighted_visible_fraction(
                         vis,
                         [&](int k) {
                           return std::pair{visibility_sample(emitter_, k),
                                            visibility_sample(t, paired_sample(k))};
                         },
                         [&](const Point3& q, const Point3& p) { return kernel(q, p, nt); });
  }

  // The piece as an area: radiance R (n+1)/(2π) cos^{n−1} ψ towards the eye (intensity per unit area
  // over the projected area), its solid angle times the visible share of 16 rays.
  GlareView glare_view(const Point3& eye, const Visibility& vis) const override {
    const Point3 c = emitter_.centroid();
    const Vector3 d = c - eye;
    const double r = length(d);
    const double cos_psi = r > 0 ? -dot(lobe_.axis, d) / r : 0;
    if (!(cos_psi > 0)) return {};
    int seen = 0;
    for (int k = 0; k < 16; ++k) seen += vis.visible(eye, visibility_sample(emitter_, k));
    if (seen == 0) return {};
    GlareView g;
    g.kind = GlareView::Kind::Area;
    g.direction = d / r;
    g.distance_m = r;
    g.luminance = normalisation() * cone_lobe_value(lobe_, cos_psi) / cos_psi;
    g.solid_angle_sr = triangle_solid_angle(eye, emitter_) * seen / 16.0;
    g.projected_area_m2 = area_ * cos_psi * seen / 16.0;
    return g;
  }

  double flux_factor() const override { return area_; }
  std::string_view kind() const override { return "phong"; }

 private:
  double normalisation() const { return (lobe_.exponent + 1) / (2 * kPi); }
  bool by_moments() const { return lobe_.exponent <= kMaxMomentExponent && std::floor(lobe_.exponent) == lobe_.exponent; }
  // Far apart, relative to the lobe's width ~ 1/sqrt(n), the degree-5 rule alone is accurate (as for
  // the Lambertian form factors, to which either integral reduces at n = 1).
  bool far_from(const Triangle& t) const {
    const double separation =
        distance(emitter_.centroid(), t.centroid()) / (emitter_.bounding_radius() + t.bounding_radius());
    return separation > 4 * std::sqrt(std::max(1.0, lobe_.exponent));
  }
  // A narrow lobe draws a beam whose footprint is about the emitter's size: the larger of two
  // triangles is first split uniformly until its pieces are no larger than the smaller one.
  int graded_depth(const Triangle& larger, const Triangle& smaller) const {
    if (lobe_.exponent <= 8) return 0;
    const double ratio = larger.max_edge_length() / smaller.max_edge_length();
    return std::clamp(static_cast<int>(std::ceil(std::log2(ratio))), 0, 4);
  }

  // τ^{n−1,1}(part; −normal, np) at p: ∫ cos^{n−1} ψ (np·ω) dω over the emitter's part above p's
  // horizon.
  double moment_at(const Point3& p, const Vector3& np, std::span<const Point3> part) const {
    return double_axis_moment(p, part, -lobe_.axis, np, static_cast<int>(lobe_.exponent) - 1);
  }

  // ∫_t τ^{n−1,1} dA (= ∫∫ cos^n ψ cos α / r² dA_q dA_p, as emitter_integral) over the receiver's part
  // in front of the emitter (where that plane cuts t, the pieces in front: the integrand has no kink
  // inside them), by the form factors' adaptive cubature.
  double receiver_integral(const Triangle& t, const Vector3& nt) const {
    auto f = [&](const Point3& p) {
      std::array<Point3, 4> part;
      const int count = clip_above(emitter_, p, nt, part);
      return count < 3 ? 0.0 : moment_at(p, nt, std::span<const Point3>(part.data(), count));
    };
    const FrontPart front = front_part(t, emitter_.v[0], lobe_.axis);
    const bool far = far_from(t);
    double G = 0;
    for (int k = 0; k < front.count; ++k) {
      const Triangle& piece = front.pieces[k];
      G += far ? apply_rule(triangle_rule_degree5(), piece, f)
               : integrate_graded(piece, f, graded_depth(piece, emitter_), kRelTolerance, 1e-12 * piece.area());
    }
    return G;
  }

  // The same flux from the emitter's side: ∫_emitter (flux into t from the cos^n point source at q)
  // dA_q, in units of (n+1)/(2π) R, for exponents the moments do not take.
  double emitter_integral(const Triangle& t, const Vector3& nt) const {
    auto flux_from = [&](const Point3& q) {
      return dot(q - t.v[0], nt) > 0 ? cone_integral(q, lobe_, t.v, {}, kConeTolerance) : 0.0;
    };
    // flux_from vanishes behind t's plane: where that plane cuts the emitter, integrate over the part
    // in front (cubature.h, front_part), on which the integrand has no kink.
    const FrontPart part = front_part(emitter_, t.v[0], nt);
    const bool far = far_from(t);
    double G = 0;
    for (int k = 0; k < part.count; ++k) {
      const Triangle& piece = part.pieces[k];
      G += far ? apply_rule(triangle_rule_degree5(), piece, flux_from)
               : integrate_graded(piece, flux_from, graded_depth(piece, t), kRelTolerance, 1e-12 * area_);
    }
    return G;
  }

  // Every direction from the emitter to t lies within asin(R/d) of the centroids' direction (R: the
  // sum of the bounding radii, d: the centroids' distance), so it makes at least ψ_min with the
  // normal. A narrow lobe with cos^n ψ_min < e^-70 sends t nothing measurable.
  bool beyond_lobe(const Triangle& t) const {
    const Vector3 d = t.centroid() - emitter_.centroid();
    const double dist = length(d), R = emitter_.bounding_radius() + t.bounding_radius();
    if (dist <= R) return false;
    const double psi_min = std::acos(std::clamp(dot(lobe_.axis, d) / dist, -1.0, 1.0)) - std::asin(R / dist);
    return psi_min > 0 && (psi_min >= kPi / 2 || lobe_.exponent * std::log(std::cos(psi_min)) < -70);
  }

  // cos^n ψ cos α / r² between the emitter's point q and a receiving point p (normal np): the weight
  // of a visibility ray.
  double kernel(const Point3& q, const Point3& p, const Vector3& np) const {
    const Vector3 d = p - q;
    const double r2 = length_squared(d), r = std::sqrt(r2);
    if (r == 0) return 0;
    return cone_lobe_value(lobe_, dot(lobe_.axis, d) / r) * std::max(0.0, -dot(np, d)) / (r * r2);
  }

  Triangle emitter_;
  ConeLobe lobe_;  // about the emitter's normal
  double area_;
  std::vector<double> exitance_;
};

}  // namespace

std::unique_ptr<LightModel> make_phong_emitter(const Triangle& emitter, double lobe_exponent,
                                               std::vector<double> exitance_W_m2_nm) {
  return std::make_unique<PhongEmitterModel>(emitter, lobe_exponent, std::move(exitance_W_m2_nm));
}

}  // namespace lambert
