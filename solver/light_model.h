// The light interface (pbrt/Mitsuba style): one model per file under solver/lights/, built from the
// scene's Light by make_light_model. Every model is linear in its spectrum S(λ): E(λ) = g · S(λ), with
// a purely geometric factor g computed here.
//   - point-like sources (point, goniometric, spot, Warn): S = I_0(λ) [W sr^-1 nm^-1], g in sr m^-2;
//   - directional and ambient light: S = irradiance [W m^-2 nm^-1], g dimensionless;
//   - a Phong-lobed emitting patch: S = exitance R(λ) [W m^-2 nm^-1], g dimensionless;
//   - a sky: S = its zenith radiance L_z(λ) [W m^-2 sr^-1 nm^-1], g in sr;
//   - a luminaire from a photometric file: S = the spectral intensity of one candela of the file
//     [W sr^-1 nm^-1 per cd], g in cd sr m^-2 (the file's candela, cos α / r²).
// Measures: point_factor is per unit area at a point; receiver_factor is the mean over a receiver's
// surface at a point (solver/receiver.h: g = ∫ S-normalised radiance × w(ω) dω); patch_factor is the
// area average over a triangle (the flux onto it per unit S, divided by its area); flux_factor is the flux the source
// emits per unit S (sr for intensity sources, m² for an emitting patch).
#pragma once

#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "mesh/geometry.h"
#include "solver/receiver.h"
#include "solver/scene.h"
#include "solver/solids.h"
#include "solver/visibility.h"

namespace lambert {

// What an observer at a point sees of a source, for glare (solver/glare.h): its luminous parts as a
// point (the intensity towards the eye) or as an area (the luminance towards the eye and the solid
// angle of the part the eye sees), each per unit of the source's S(λ). Where a light has luminous
// openings (a luminaire from a photometric file), they are the area.
struct GlareView {
  enum class Kind { None, Point, Area };
  Kind kind = Kind::None;     // None: nothing to see (ambient, directional, sky, hidden, behind)
  Vector3 direction;          // unit, from the eye towards the centre of what it sees
  double distance_m = 0;      // to that centre
  double intensity = 0;       // Point: I towards the eye per unit S (point-like: the lobe, 1 on the axis)
  double luminance = 0;       // Area: L towards the eye per unit S [sr^-1 for an exitance]
  double solid_angle_sr = 0;  // Area: of the visible luminous part
  double projected_area_m2 = 0;  // Area: the visible part's area seen from the eye (ω r²)
};

class LightModel {
 public:
  virtual ~LightModel() = default;

  // S(λ) on the scene's wavelength grid.
  virtual const std::vector<double>& spectrum() const = 0;

  // g at a point p with unit normal n, unshadowed (no ray): the model's closed form.
  virtual double unshadowed_factor(const Point3& p, const Vector3& n) const = 0;

  // g at p, shadowed with rays where the model says so (a probe).
  virtual double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const = 0;

  // g for a receiver (planar, cylindrical, semicylindrical, hemispherical), shadowed as point_factor:
  // the light's weight w(ω) over its directions. A planar receiver gives point_factor. By default
  // the planar decomposition (receiver_by_planes, solver/receiver_kernel.h: point_factor over the
  // receiver's normals, integrated), exact for any light but costing hundreds to thousands of
  // point_factor calls; the models with a closed form (point-like, directional, ambient, Phong
  // emitter) override it.
  virtual double receiver_factor(const Receiver& receiver, const Visibility& vis) const;

  // Area average of g over triangle t (front side counter-clockwise), times the kernel-weighted visible
  // fraction of the source seen from t.
  virtual double patch_factor(const Triangle& t, const Visibility& vis) const = 0;

  // What an observer at `eye` sees of the source (one ray for a point; rays to the part for an
  // area). Default: nothing.
  virtual GlareView glare_view(const Point3& eye, const Visibility& vis) const { return {}; }

  // Flux emitted per unit of S. Zero for directional and ambient light, whose flux depends on the
  // scene they fall on; positive for every source whose emitted flux is known (the energy balance
  // counts what such a source delivers to no patch as escaped).
  virtual double flux_factor() const = 0;

  // What the source is, as output.per_source names a light ("point", "spot", "ambient", ...).
  virtual std::string_view kind() const = 0;

  // Whether the light is the same on every receiver and comes from no direction (ambient): no ray
  // carries it, so no pane transmits it and no observer sees it as a source, but an eye receives it.
  virtual bool directionless() const { return false; }
};

// What a light may ask of the scene it lights, beyond rays: the sources stage fills it once per solve,
// after the scene is prepared (re-centred, contacts cut). The point-like, directional and ambient
// lights ignore it.
struct LightContext {
  // The scene's input triangles in metres (the occluders of exact visibility), and the solids they
  // bound if known (solver/solids.h; null: none taken for solids).
  std::span<const Triangle> occluders;
  const OutwardSolids* solids = nullptr;
  // Whether the context describes the scene (false: the default, for callers that have no scene;
  // a light that needs one then refuses to be made).
  bool has_scene = false;
  // Per occluder its clear-glass channel (solver/glazing.h: clear_glass_channels), or −1; empty where
  // no pane is clear.
  std::span<const int> pane_channel;
};

std::unique_ptr<LightModel> make_light_model(const Light& light, const LightContext& context = {});

// A scene's LightContext with the storage it points into: the scene's input triangles in metres and
// the solids they bound, gathered only where one of its lights needs them (a sky), else empty (but
// has_scene: every light can be made). Pointers into itself: neither copied nor moved.
class SceneLightContext {
 public:
  explicit SceneLightContext(const Scene& scene);
  SceneLightContext(const SceneLightContext&) = delete;
  SceneLightContext& operator=(const SceneLightContext&) = delete;
  const LightContext& context() const { return context_; }

 private:
  std::vector<Triangle> triangles_;
  std::vector<int> pane_channel_;
  OutwardSolids solids_;
  LightContext context_;
};

// Every light of the scene as its model, in order.
std::vector<std::unique_ptr<LightModel>> make_scene_light_models(const Scene& scene);

// The factories behind make_light_model, one per model file in solver/lights/.
std::unique_ptr<LightModel> make_ambient_light(const AmbientLight& light);          // ambient.cpp
std::unique_ptr<LightModel> make_directional_light(const DirectionalLight& light);  // directional.cpp
std::unique_ptr<LightModel> make_point_light(const PointLight& light);        // point.cpp: Kind::Point
std::unique_ptr<LightModel> make_goniometric_light(const PointLight& light);  // goniometric.cpp: also Warn
std::unique_ptr<LightModel> make_spot_light(const PointLight& light);         // spot.cpp
std::unique_ptr<LightModel> make_luminaire_light(const LuminaireLight& light);  // luminaire.cpp
// sky.cpp: throws std::invalid_argument without a scene in the context (its light depends on what
// the scene hides of the sky).
std::unique_ptr<LightModel> make_sky_light(const SkyLight& light, const LightContext& context);

// A Phong-lobed emitting patch (SPEC §1): dI/dA(ψ) = R (n+1)/(2π ω0) cos^n ψ, ψ from the patch's
// normal, n ≥ 1, so that it emits exactly R [W m^-2]. Used by the solve for lobe exponents ≠ 1: its
// emission reaches other patches and probes as direct irradiance.
std::unique_ptr<LightModel> make_phong_emitter(const Triangle& emitter, double lobe_exponent,
                                               std::vector<double> exitance_W_m2_nm);

}  // namespace lambert
