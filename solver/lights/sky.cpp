// The sky as a light (SPEC §1 "sky"): an area source at infinity. Its irradiance at a point p with
// unit normal n, per unit of its zenith radiance L_z(λ), is
//   g(p, n) = ∫_{visible sky} (L/L_z)(ω) (n·ω) dω + (ρ_g K / π) ∫_{visible ground} (n·ω) dω     [sr]
// (the ground's luminance L_g = ρ_g E_h / π = ρ_g K L_z / π), both integrals exact over what the scene
// leaves visible (sky_dome.h): at probes with no ray traced, over patches by the degree-5 rule of
// exact point values. Its flux depends on the scene it falls on (flux_factor 0, as for directional
// light): the energy certificate counts what reaches the patches as emitted.
#include "solver/lights/sky.h"

#include <stdexcept>
#include <string>

#include "solver/light_model.h"
#include "solver/lights/sky_dome.h"

namespace lambert {

SkyDistribution sky_distribution(const SkyLight& light) {
  switch (light.model) {
    case SkyLight::Model::kUniform: return SkyDistribution::uniform(light.up);
    case SkyLight::Model::kCieOvercast: return SkyDistribution::cie_overcast(light.up);
    case SkyLight::Model::kGeneral: break;
  }
  if (cie_sky_depends_on_sun(light.cie_type) && !light.sun)
    throw std::invalid_argument("CIE general sky type " + std::to_string(light.cie_type) + " needs the sun's direction");
  return SkyDistribution::general(light.cie_type, light.up, light.sun.value_or(light.up));
}

SkySummary summarize_sky(const SkyLight& light) {
  SkySummary out;
  out.horizontal_factor_sr = sky_distribution(light).horizontal_factor();
  for (double L : light.zenith_radiance_W_m2_sr_nm) {
    out.horizontal_irradiance_W_m2_nm.push_back(out.horizontal_factor_sr * L);
    out.ground_radiance_W_m2_sr_nm.push_back(light.ground_reflectance * out.horizontal_factor_sr * L / kPi);
  }
  return out;
}

namespace {

class SkyLightModel final : public LightModel {
 public:
  SkyLightModel(const SkyLight& light, const LightContext& context)
      : light_(light),
        dome_(make_sky_dome(light, context)),
        open_({}, dome_->sky()),
        ground_weight_(light.ground_reflectance * dome_->sky().horizontal_factor() / kPi) {}

  const std::vector<double>& spectrum() const override { return light_.zenith_radiance_W_m2_sr_nm; }

  double unshadowed_factor(const Point3& p, const Vector3& n) const override { return combine(open_.at(p, n)); }
  // A view through clear panes (Visibility::through_panes) asks for the sky its channel's panes show.
  double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const override {
    return combine(vis.channel() < 0 ? dome_->at(p, n) : dome_->through(vis.channel(), p, n));
  }
  double patch_factor(const Triangle& t, const Visibility& vis) const override {
    return combine(vis.channel() < 0 ? dome_->average(t) : dome_->average_through(vis.channel(), t));
  }
  double flux_factor() const override { return 0; }
  std::string_view kind() const override { return "sky"; }

 private:
  double combine(const SkyFactors& f) const { return f.sky + ground_weight_ * f.ground; }

  SkyLight light_;
  std::unique_ptr<SkyDome> dome_;  // the scene's occluders
  SkyDome open_;  // none
  double ground_weight_;  // ρ_g K / π
};

}  // namespace

std::unique_ptr<SkyDome> make_sky_dome(const SkyLight& light, const LightContext& context) {
  if (!context.has_scene)
    throw std::invalid_argument("a sky light needs the scene's geometry (LightContext) to see what it hides of the sky");
  const OutwardSolids* solids = context.solids;
  return std::make_unique<SkyDome>(context.occluders, sky_distribution(light),
                                   solids ? std::span<const int>(solids->solid) : std::span<const int>{},
                                   solids ? std::span<const char>(solids->convex) : std::span<const char>{},
                                   solids ? std::span<const SolidCap>(solids->cap) : std::span<const SolidCap>{},
                                   context.pane_channel);
}

std::unique_ptr<LightModel> make_sky_light(const SkyLight& light, const LightContext& context) {
  return std::make_unique<SkyLightModel>(light, context);
}

}  // namespace lambert
