// The sky and the ground seen from a point, with the scene's own geometry as the occluder, exactly.
//
// A sky is an area source at infinity: at a point p with unit normal n
//   E(p, n) = L_z ∫_{visible sky} (L/L_z)(ω) (n·ω) dω + L_g ∫_{visible ground} (n·ω) dω,
// the sky the directions above the horizon (ω·up > 0), the ground, of uniform luminance L_g, the
// directions below. Both integrals run over the directions from p that leave the scene. They are
// taken over a box centred on p, beyond the scene (half-size 1.5 × the distance from p to the
// farthest corner of the scene's bounds; a box centred on p has no parallax: a direction from p meets
// the box in one point): the top face and the upper halves of the four sides are the sky, the lower
// halves and the bottom the ground, twenty triangles in all. For each, ExactVisibility projects the
// occluders between p and the triangle onto its plane and subtracts them (clipped at p's horizon),
// leaving the visible part as disjoint convex pieces in the triangle's plane (exact_visibility.h).
//  - A uniform luminance (the ground; the uniform sky, general type 5) needs only the contour
//    integral of those loops: ∫ (n·ω) dω = π F(visible part), exact to round-off.
//  - A graded sky is integrated over the loops in the triangle's plane: with y a point of the plane,
//    d = y − p, r = |d| and h the distance from p to the plane, dω = h dA_y / r³, so
//      ∫ (L/L_z)(ω) (n·ω) dω = ∫ (L/L_z)(d/r) (n·d) h / r⁴ dA_y.
//    Each loop is fanned into triangles from one point, signed by their orientation (the signed fan
//    of any closed loop sums to its winding number, so a hole subtracts), and each triangle is
//    integrated by the adaptive degree-5 rule (solver/cubature.h) to kRelTolerance of the sky's
//    horizontal factor K. Where the sun's direction crosses a loop the fan starts there, so that
//    the indicatrix's kink (exp(d χ), χ the angle to the sun) lies at a vertex of every triangle.
//    The integrand is smooth elsewhere: the plane's gnomonic map is analytic, and the horizon and
//    p's own horizon are edges of the loops, not lines across them.
// Clear glass (solver/glazing.h) is a window onto the sky: through the panes of channel c (one clear
// material, its panes parallel, normal n_c) the dome gives
//   ∫ (L/L_z)(ω) g(ω·n_c) (n·ω) dω  over  V_c − V,
// V the visible part with every occluder, V_c with every occluder but the panes of c (V ⊆ V_c: the
// difference is what those panes alone hide), each integral by the cubature above (the ground's
// with L/L_z ≡ 1). A direction that crosses two panes stays hidden in V_c unless both are of c,
// where it counts once.
// Tests: the cubature with L/L_z ≡ 1 against the contour integral over the same loops, and the
// unobstructed sums against sky_horizontal_integral (another quadrature, about the sun).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "mesh/geometry.h"
#include "solver/exact_visibility.h"
#include "solver/lights/sky_luminance.h"

namespace lambert {

// [sr]: E_sky = L_z · sky, E_ground = L_g · ground.
struct SkyFactors {
  double sky = 0;     // ∫_{visible sky} (L/L_z)(ω) (n·ω) dω
  double ground = 0;  // ∫_{visible ground} (n·ω) dω
};

class SkyDome {
 public:
  // The occluders: the scene's triangles in metres (the input triangles, as for the probes' exact
  // visibility), with the solids they bound if known (ExactVisibility's arguments); the dome keeps its
  // own ExactVisibility over them, set to peel the visible part into disjoint convex pieces
  // (inclusion–exclusion's signed loops cover far more than the visible part and cancel, and the
  // cubature's error grows with the area it covers). No occluders: the unobstructed sky.
  // pane_channel (per occluder, or empty): the clear-glass channel of each occluder, or −1. Throws
  // std::invalid_argument where the panes of a channel are not parallel.
  SkyDome(std::span<const Triangle> occluders, const SkyDistribution& sky, std::span<const int> solid = {},
          std::span<const char> convex = {}, std::span<const SolidCap> caps = {},
          std::span<const int> pane_channel = {});
  ~SkyDome();

  SkyFactors at(const Point3& p, const Vector3& n) const;
  // The area average over triangle t (its front side) by the degree-5 rule of its points' exact values.
  SkyFactors average(const Triangle& t) const;
  // The same through the clear panes of `channel` alone, each direction weighted by g (above).
  SkyFactors through(int channel, const Point3& p, const Vector3& n) const;
  SkyFactors average_through(int channel, const Triangle& t) const;

  const SkyDistribution& sky() const { return sky_; }
  // The relative tolerance of a graded sky's cubature, of the sky's horizontal factor K.
  static constexpr double kRelTolerance = 1e-9;

 private:
  // The visible parts of the dome's twenty triangles from p with exact_, or with a window's.
  template <class Visit>
  void visit_box(const Point3& p, const Vector3& n, const ExactVisibility& exact, Visit&& visit) const;
  template <class PointFactors>
  SkyFactors average_of(const Triangle& t, PointFactors&& at) const;

  struct Window;  // a channel's occluders without its panes, and the panes' normal
  ExactVisibility exact_;
  Bounds3 scene_;
  SkyDistribution sky_;
  std::vector<std::unique_ptr<Window>> windows_;
};

// ∫ (L/L_z)(ω) (n·ω) dω over the part of a region's loops, by the fan cubature above (exposed for the
// tests, which run it with a uniform sky against region.factor_of).
double sky_integral_over_region(const ExactVisibility::VisibleRegion& region, const Point3& p, const Vector3& n,
                                const SkyDistribution& sky, double abs_tolerance);
// The same with the luminance times weight(ω) (ω the unit direction from p); `ground`: L/L_z ≡ 1.
double weighted_integral_over_region(const ExactVisibility::VisibleRegion& region, const Point3& p, const Vector3& n,
                                     const SkyDistribution& sky, bool ground, const std::function<double(const Vector3&)>& weight,
                                     double abs_tolerance);

}  // namespace lambert
