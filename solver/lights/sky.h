// The sky light's quantities beyond its LightModel (sky.cpp), for the decoder (normalisation) and the
// result (the unobstructed illuminances it states).
#pragma once

#include <memory>
#include <vector>

#include "solver/light_model.h"
#include "solver/lights/sky_dome.h"
#include "solver/lights/sky_luminance.h"
#include "solver/scene.h"

namespace lambert {

// The relative distribution of a SkyLight (throws std::invalid_argument where a sun is needed and
// missing or below the horizon).
SkyDistribution sky_distribution(const SkyLight& light);

// What the sky gives an unobstructed horizontal plane: E_h(λ) = K L_z(λ) from the sky above (facing
// up), and the ground's radiance L_g(λ) = ρ_g E_h(λ)/π, whose irradiance on a plane facing down is
// π L_g = ρ_g E_h.
struct SkySummary {
  double horizontal_factor_sr = 0;                   // K
  std::vector<double> horizontal_irradiance_W_m2_nm;  // E_h(λ)
  std::vector<double> ground_radiance_W_m2_sr_nm;     // L_g(λ)
};
SkySummary summarize_sky(const SkyLight& light);

// The sky and the ground as the scene of `context` hides them from a point (sky_dome.h): the light's
// dome, which the LightModel integrates, for measures of its own (the vertical sky component).
// Throws std::invalid_argument as make_sky_light does.
std::unique_ptr<SkyDome> make_sky_dome(const SkyLight& light, const LightContext& context);

}  // namespace lambert
