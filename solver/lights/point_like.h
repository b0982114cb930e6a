// The geometry shared by every source that radiates from a point with a rotationally symmetric lobe
// I(ψ) = I_0 cos^m ψ (ψ ≤ ψ_max, zero beyond) about an axis: the isotropic point (m = 0, ψ_max = π),
// the goniometric and Warn sources (ψ_max = π/2), the spot (ψ_max = cutoff), and the differential
// element of a Phong-lobed emitting patch.
//
// The flux through a planar polygon is integrated in solid angle, in polar coordinates (ψ, φ) about
// the lobe's axis (measure dω = sin ψ dψ dφ):
//
//   ∫_{Ω(P)} cos^m ψ w(ω) dω = ∫_0^{2π} dφ ∫_{ψ1(φ)}^{ψ2(φ)} cos^m ψ sin ψ w dψ,
//
// where [ψ1, ψ2] is the section of the polygon by the half-plane of azimuth φ (an interval, since
// the polygon is convex). With w ≡ 1 (inverse-square sources) the inner integral is exact,
// (cos^{m+1}ψ1 − cos^{m+1}ψ2)/(m+1), evaluated without cancellation or overflow for any m. This is
// what makes the narrow lobes (m up to 10⁶, a footprint far smaller than the patch) and the near
// sources (1 µm above a patch) exact: neither the lobe's peak nor the foot of the perpendicular is a
// point a cubature rule can miss. Otherwise (attenuation polynomials, a receiver's cos α) the inner
// integral is done numerically in the variable v = cos^{m+1} ψ, which absorbs the lobe into the
// measure. The outer integral is adaptive Gauss–Kronrod in φ, broken at the azimuths where the
// integrand has kinks or its narrowest features: polygon vertices, the points of each edge nearest to
// and farthest from the axis, and the crossings of the edges with the cone ψ = ψ_max (a spot's cutoff
// edge across a patch).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "mesh/geometry.h"
#include "solver/light_model.h"
#include "solver/spectrum.h"

namespace lambert {

// cos^m ψ about `axis` for ψ ≤ max_angle_rad, zero beyond. max_angle_rad ≤ π/2 when m > 0.
struct ConeLobe {
  Vector3 axis{0, 0, -1};       // unit
  double exponent = 0;          // m ≥ 0
  double max_angle_rad = kPi;
};

// The lobe's value for a direction with cos ψ = cos_psi: exp(m ln cos ψ), never pow overflow.
double cone_lobe_value(const ConeLobe& lobe, double cos_psi);

// ∫_{ψ1}^{ψ2} cos^m ψ sin ψ dψ for 0 ≤ ψ1, ψ2 ≤ π (≤ π/2 when m > 0); 0 when ψ2 ≤ ψ1. Exact and
// free of cancellation: (cos^{m+1}ψ1 − cos^{m+1}ψ2)/(m+1) written as a product with expm1/log1p.
double cone_band(double m, double psi1, double psi2);

// ∫ lobe(ψ) dω over all directions [sr]: the flux of a unit-I_0 source, 2π cone_band(m, 0, ψ_max).
double cone_lobe_flux(const ConeLobe& lobe);

// Weight w(ω) of a direction (unit vector from the origin); empty means w ≡ 1.
using DirectionWeight = std::function<double(const Vector3& unit_direction)>;

// ∫ lobe(ψ(ω)) w(ω) dω [sr] over the directions from `origin` that pass through the convex planar
// polygon (≤ 8 vertices, either orientation). 0 if the origin lies in the polygon's plane.
// rel_tolerance bounds the adaptive outer integral's error estimate (the inner one gets a tenth).
double cone_integral(const Point3& origin, const ConeLobe& lobe, std::span<const Point3> polygon,
                     const DirectionWeight& weight = {}, double rel_tolerance = 1e-9);

// Base of the point-like sources: I(ψ) = I_0 lobe(ψ) at `position`, E = I cos α / att(r) with
// att = r² or c1 + c2 r + c3 r², shadowed by one ray to the source (points) or kernel-weighted rays
// (patches). The derived models (point.cpp, goniometric.cpp, spot.cpp) set the lobe and the flux.
class PointLikeLight : public LightModel {
 public:
  const std::vector<double>& spectrum() const final { return light_.intensity_W_sr_nm; }
  double unshadowed_factor(const Point3& p, const Vector3& n) const final;
  double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const final;
  // I(ψ) w(ω) / att(r), ω towards the source (receiver.h): for a cylinder about a,
  // E_z = I sin ε / (π d²) with ε the angle between the light's direction and the axis.
  double receiver_factor(const Receiver& receiver, const Visibility& vis) const final;
  double patch_factor(const Triangle& t, const Visibility& vis) const final;
  // A point of intensity I(ψ) towards the eye (the attenuation polynomial shapes the light's
  // irradiance, not what the eye sees of the source: not applied).
  GlareView glare_view(const Point3& eye, const Visibility& vis) const final;
  std::string_view kind() const final {
    switch (light_.kind) {
      case PointLight::Kind::Point: return "point";
      case PointLight::Kind::Spot: return "spot";
      case PointLight::Kind::Warn: return "warn";
      case PointLight::Kind::Goniometric: break;
    }
    return "goniometric";
  }

 protected:
  PointLikeLight(const PointLight& light, const ConeLobe& lobe) : light_(light), lobe_(lobe) {}
  const PointLight& light() const { return light_; }
  const ConeLobe& lobe() const { return lobe_; }

  // ∫_t lobe(ψ) cos α / att(r) dA for a triangle whose front faces the source [sr for att = r²].
  // By default the cone integral about the lobe's own axis.
  virtual double patch_integral(const Triangle& t) const { return attenuated_cone_integral(t, lobe_); }
  // The same integral, in polar coordinates about `lobe`'s axis: cos α dA / att(r) = (r²/att(r)) dω.
  double attenuated_cone_integral(const Triangle& t, const ConeLobe& lobe) const;

 private:
  PointLight light_;
  ConeLobe lobe_;
};

}  // namespace lambert
