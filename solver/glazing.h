// The angular factor of clear glass (SPEC §5 "Glazing", docs/METHOD.md "Clear glass"): a pane of
// "transmission": "specular" passes τ(λ, θ) = τ(λ) g(θ) of a ray that meets it at θ from its normal,
// τ(λ) the normal-incidence transmittance the material gives and g the pane's angular dependence,
// normalised to g(0) = 1.
//
// g is that of a clear, non-absorbing slab of refractive index n = 1.52 (soda-lime float glass) in
// air, unpolarised light, with the multiple reflections between its two faces summed: per
// polarisation the slab passes (1 − r)/(1 + r) of a ray, r the Fresnel reflectance of one face
// (Duffie & Beckman, Solar Engineering of Thermal Processes, 4th ed. 2013, eq. 5.1.8 with N = 1; the
// Fresnel amplitudes as in Hecht, Optics, §4.6), and unpolarised light is the mean of the s and p
// parts:
//   τ_r(θ) = ½ [(1 − r_s)/(1 + r_s) + (1 − r_p)/(1 + r_p)],   g(θ) = τ_r(θ) / τ_r(0),
//   τ_r(0) = 2n / (n² + 1) = 0.91839 for n = 1.52.
// A pane's absorption lengthens with the path in the glass (1/cos θ_t) and steepens g; it is not
// modelled (it would make g depend on τ(λ)). For the absorbing slab whose τ(0) is the material's,
// g is lower than this one's by 0.5 % at 60° and 1.5 % at 80° where τ(0) = 0.9 (clear float glass),
// by 3.3 % at 60° and 8.8 % at 80° where τ(0) = 0.8.
#pragma once

#include <vector>

namespace lambert {

struct Scene;

inline constexpr double kPaneRefractiveIndex = 1.52;

// τ_r(θ) of a non-absorbing slab of index n in air at the incidence cosine c (above).
double slab_transmittance(double cos_theta, double n);

// Clear glass's channels (solver/pipeline/clear_panes.h): per material of the scene, its index among
// the clear ("transmission": "specular") materials in order, or −1.
std::vector<int> clear_glass_channels(const Scene& scene);

// g at the cosine of the angle of incidence (either side of the pane: |cos θ| is used): 1 at
// normal incidence, falling to 0 at grazing incidence.
double pane_angular_factor(double cos_theta);

// The hemispherical (cosine-weighted) mean of g, ḡ = 2 ∫₀^{π/2} g(θ) cos θ sin θ dθ = ∫₀¹ 2 c g(c) dc:
// what a pane passes of Lambertian (diffuse) light per unit of τ(λ). 0.92171 for n = 1.52.
double pane_hemispherical_factor();

}  // namespace lambert
