// Relative sky luminance distributions L(ω)/L_z (the sky's luminance over its zenith luminance):
//  - the ISO 15469:2004 / CIE S 011/E:2003 general skies, types 1–15:
//      L/L_z = φ(Z) f(χ) / (φ(0) f(Z_s)),
//      gradation  φ(Z) = 1 + a exp(b / cos Z)   (φ(π/2) = 1),
//      indicatrix f(χ) = 1 + c [exp(d χ) − exp(d π/2)] + e cos² χ,
//    Z the zenith angle of the sky element, Z_s the sun's, χ the angle between the element and the
//    sun; a–e from the standard's six gradation and six indicatrix groups (cie_general_sky);
//  - the traditional CIE overcast sky (Moon & Spencer 1942, CIE 1955; "type 16" here):
//      L/L_z = (1 + 2 sin γ)/3, γ = π/2 − Z the elevation;
//  - the uniform sky, L/L_z = 1.
// The horizontal factor K = ∫_{upper hemisphere} (L/L_z) cos Z dω [sr] is the unobstructed
// horizontal illuminance per unit zenith luminance: π for the uniform sky, 7π/9 for the overcast
// sky (∫ (1 + 2 cos Z) cos Z sin Z dZ dα / 3 = 2π (1/2 + 2/3)/3), a quadrature for the others.
#pragma once

#include "mesh/geometry.h"
#include "solver/spectrum.h"

namespace lambert {

// One row of the ISO 15469 table.
struct CieSkyParameters {
  int gradation_group = 1;   // I–VI as 1–6
  int indicatrix_group = 1;  // 1–6
  double a = 0, b = 0, c = 0, d = 0, e = 0;
};
inline constexpr int kCieGeneralSkyTypes = 15;
inline constexpr int kCieOvercastSkyType = 16;  // the traditional overcast sky in the scene format

// The parameters of general sky type 1–15 (throws std::out_of_range otherwise).
const CieSkyParameters& cie_general_sky(int type);
// Whether the distribution of general sky type 1–15 depends on the sun (indicatrix group > 1).
bool cie_sky_depends_on_sun(int type);

enum class SkyKind { kGeneral, kCieOvercast, kUniform };

class SkyDistribution {
 public:
  // General sky `type` (1–15). `up` unit; `sun` unit with sun·up > 0 (ignored, and may be anything,
  // for the types whose distribution does not depend on the sun). Throws std::invalid_argument.
  static SkyDistribution general(int type, const Vector3& up, const Vector3& sun);
  static SkyDistribution cie_overcast(const Vector3& up);
  static SkyDistribution uniform(const Vector3& up);

  SkyKind kind() const { return kind_; }
  int type() const { return type_; }  // 1–15, 16 for the overcast sky, 0 for the uniform sky
  const Vector3& up() const { return up_; }
  const Vector3& sun() const { return sun_; }
  // Whether L/L_z varies with the direction at all (the uniform sky and type 5 do not), and whether it
  // has the indicatrix's kink at the sun (c ≠ 0: exp(d χ) is not smooth at χ = 0).
  bool is_uniform() const { return uniform_; }
  bool has_sun_kink() const { return kind_ == SkyKind::kGeneral && params_.c != 0; }

  // L/L_z towards the unit direction ω; 0 at and below the horizon (ω·up ≤ 0).
  double relative_luminance(const Vector3& omega) const;
  // K [sr], see above.
  double horizontal_factor() const { return horizontal_factor_; }

 private:
  SkyDistribution(SkyKind kind, int type, const Vector3& up, const Vector3& sun);
  double gradation(double cos_Z) const;
  double indicatrix(double chi) const;

  SkyKind kind_;
  int type_ = 0;
  Vector3 up_, sun_;
  CieSkyParameters params_;
  bool uniform_ = false;
  double normalisation_ = 1;  // 1 / (φ(0) f(Z_s))
  double horizontal_factor_ = kPi;
};

// ∫_{upper hemisphere} (L/L_z)(ω) (ω·up) dω by Gauss–Legendre quadrature in polar coordinates about
// the sun (χ, ψ): the indicatrix's kink at the sun is the pole, where exp(d χ) is smooth in χ; for
// each azimuth ψ about the sun, χ runs to the horizon, χ_h(ψ) = atan2(cos Z_s, −sin Z_s cos ψ), in
// panels graded towards it (the gradation exp(b / cos Z) changes fastest there); ψ by the periodic
// trapezoid rule. Converged to about 1e-13 (tests, by another method).
double sky_horizontal_integral(const SkyDistribution& sky);

}  // namespace lambert
