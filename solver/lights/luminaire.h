// Luminaires from photometric files (SPEC §1 "luminaire"): the placed luminaire — its frame, its
// maintained intensity and, where the file gives luminous dimensions, its opening as an area source —
// for the light model (luminaire.cpp, behind LightModel) and for anything else that needs a
// luminaire's geometry and luminance (glare: the opening seen from an observer).
//
// Frame: up = −nadir, C0 = c0, C90 = up × c0 (counter-clockwise from C0 seen from above); a scene
// direction ω has luminaire coordinates (ω·C0, ω·C90, ω·up), in which photometric_data.h states
// where each photometry type's angles point.
//
// Near and far. An opening radiates L(ω) = I(ω)/A_proj(ω) from every point q, so that, for a flat
// opening, the exact irradiance at p (normal n) is E = (1/A) ∫ I(ω_qp) cos α_q / r_q² dA_q, and the
// point form is its integrand at the centre c: I(ω_cp) cos α / d². Expanding g(q) = I(ω_qp) h(q),
// h = cos α / r², to second order in q, the first-order terms cancel for a centrally symmetric
// opening and
//     E − E_point ≈ ½ <q_i q_j> (h ∂_i∂_j I + 2 ∂_i I ∂_j h + I ∂_i∂_j h),
// with <·> the mean over the opening. Moving q by δ turns ω by δ/d, so for a receiver facing the
// luminaire (h = 1/d², |∂h| ≤ 2h/d from 1/r², |∂²h| ≲ 3h/d² from 1/r², cos α and cos θ):
//     |E − E_point| / (I_max/d²) ≲ (3 + κ₂ + 4κ₁) <ρ²> / (2 d²),
// where <ρ²> is the mean of |q − c|² over the opening, κ₁ = max|∂I/∂s|/I_max and κ₂ = max|∂²I/∂s²|/I_max
// the distribution's relative slope and curvature per radian (distribution.h; 1 and 1 for
// I = I_0 cos γ). The error is measured against I_max/d², the normal illuminance of the peak
// intensity at that distance, not against the local I(ω)/d², which vanishes where the distribution
// does (near γ = 90° the point form's relative error grows as tan γ without affecting anything lit).
// So the two agree to 10⁻³ of I_max/d² beyond
//     d* = √((3 + κ₂ + 4κ₁) <ρ²> / (2 · 10⁻³))
// (a Lambertian rectangle L × W: <ρ²> = (L² + W²)/12, d* = √(4000 <ρ²>); a Lambertian disk of
// radius R: <ρ²> = R²/2, d* = 44.7 R). The point form is used from d* on (measured from the centre;
// for a patch, from its nearest possible point: its centroid's distance less its bounding radius),
// the area form nearer. tests/luminaire_test.cpp checks the worst case over directions and receiver
// orientations against the exact contour integral at d*.
#pragma once

#include <memory>

#include "mesh/geometry.h"
#include "solver/photometry/distribution.h"
#include "solver/photometry/luminous_opening.h"
#include "solver/scene.h"

namespace lambert {

// The relative agreement the near-field rule asks of the point form.
inline constexpr double kNearFieldTolerance = 1e-3;

class PlacedLuminaire {
 public:
  explicit PlacedLuminaire(const LuminaireLight& light);

  const LuminaireLight& light() const { return light_; }
  const PhotometricDistribution& distribution() const;
  const LuminousOpening& opening() const { return opening_; }
  const Point3& centre() const { return light_.position; }
  const Vector3& c0() const { return c0_; }
  const Vector3& c90() const { return c90_; }
  const Vector3& up() const { return up_; }

  Vector3 to_local(const Vector3& v) const { return {dot(v, c0_), dot(v, c90_), dot(v, up_)}; }
  Vector3 to_scene(const Vector3& v) const { return c0_ * v.x + c90_ * v.y + up_ * v.z; }

  // The file's intensity toward a unit scene direction [cd], and the luminaire's as placed
  // (× candela_scale: the rescale, the tilt factor and the maintenance factor).
  double file_intensity_cd(const Vector3& direction) const { return distribution().intensity(to_local(direction)); }
  double intensity_cd(const Vector3& direction) const { return light_.candela_scale * file_intensity_cd(direction); }
  // The opening's luminance toward a unit scene direction [cd/m²]: I / A_proj (0 where the opening
  // shows no area that way, and for a point luminaire).
  double luminance_cd_m2(const Vector3& direction) const;
  // ∫ I dω as placed [lm].
  double flux_lm() const { return light_.candela_scale * distribution().flux(); }
  // d* of the rule above [m]; 0 for a point luminaire and shapes not modelled as areas (the point
  // form everywhere).
  double near_field_distance_m() const { return near_distance_; }

 private:
  LuminaireLight light_;
  Vector3 c0_, c90_, up_;
  LuminousOpening opening_;
  double near_distance_ = 0;
};

}  // namespace lambert
