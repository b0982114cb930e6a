// The decoded, validated scene: plain C++ values in SI units (metres, radians, W, nm), every spectrum
// already sampled on the scene's wavelength grid and every photometric total already applied.
// Produced by the JSON codec (server/scene_codec.*); consumed by the solver. A Scene that exists is
// valid: the codec returns errors instead of a half-filled Scene.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "mesh/geometry.h"
#include "solver/spectrum.h"

namespace lambert {

// Rgb: the three-sample model (solver/rgb_model.h). The grid then has three channels R, G, B, and
// every per-"wavelength" vector below holds channel values instead: O_c for a reflectance (which may
// leave [0, 1]), I_c for an emission or light (which may be negative).
enum class SpectrumMode { Spectral, Rgb };

// A Phong lobe (SPEC §1): reflected radiance E k_s ρ_s(λ) (n+1)/(2π ω0) cos^n α about the mirror
// direction, from the light arriving from a direction with irradiance E. Only rendered images use it;
// the radiosity solve is diffuse.
struct SpecularLobe {
  double coefficient = 0;           // k_s in [0, 1]
  double exponent = 1;              // n > 0
  std::vector<double> reflectance;  // ρ_s(λ) per grid wavelength (1 when not given)
};

// How a pane of zero thickness passes the light it does not reflect or absorb (SPEC §5 "Glazing",
// solver/pipeline/panes.h). Diffuse: each face re-emits, as a Lambertian emitter, τ(λ) times the
// irradiance of the other face (opal glass); rays do not cross it. Specular (clear glass,
// solver/glazing.h): the sources' rays cross it, τ(λ) g(θ) of each arriving beyond; the light of
// other patches crosses it as for opal glass, with τ(λ) ḡ (the hemispherical mean of g).
enum class Transmission { kNone, kDiffuse, kSpecular };

struct Material {
  std::string name;
  std::vector<double> reflectance;  // β(λ) per grid wavelength, each in [0, 1]
  std::optional<SpecularLobe> specular;
  Transmission transmission = Transmission::kNone;
  std::vector<double> transmittance;  // τ(λ) at normal incidence per grid wavelength, β + τ ≤ 1; empty: opaque
};

// Emission of a surface: exitance R(λ) [W m^-2 nm^-1] leaving the front side, distributed as
// dI/dA(ψ) = R (n+1)/(2π ω0) cos^n ψ; n = 1 is the Lambertian emitter (L = R/π).
struct Emission {
  std::vector<double> exitance_W_m2_nm;
  double lobe_exponent = 1.0;
};

// What a surface is in a room (SPEC §5 "role"): the task-area summary's walls, ceiling and floor.
enum class SurfaceRole { None, Wall, Ceiling, Floor };

// Total, grey thermal radiation of a surface (radiant exchange, solver/thermal/): the emissivity ε
// (equal to its absorptance; the rest, 1 − ε, is reflected diffusely) and exactly one of its
// temperature (it emits ε σ T⁴) or the net radiative flux it must have (emitted − absorbed, W/m²; 0 for
// a reradiating, adiabatic surface, whose radiosity then equals its irradiance).
struct SurfaceThermal {
  double emissivity = 1;                  // in [0, 1]; > 0 with a net flux
  std::optional<double> temperature_K;    // > 0
  std::optional<double> net_flux_W_m2;
};

struct Surface {
  std::string name;
  SurfaceRole role = SurfaceRole::None;
  int material = 0;                 // index into Scene::materials
  TriangleMesh mesh;                // metres; counter-clockwise = front (lit) side
  std::optional<Emission> emission;
  std::optional<SurfaceThermal> thermal;  // on every surface or on none
  std::string pointer;              // JSON pointer of the surface in the scene, for messages
  // Set by solve(), not by the decoder: per triangle of `mesh`, 1 where it lies back to back on a
  // triangle of another surface (the two faces of a sheet of zero thickness). A ray meets either
  // face there, so meeting one from behind is not a light leak. Empty: none.
  std::vector<char> two_sided;
  // Set by solve(), not by the decoder: a surface whose material transmits is a pane of zero
  // thickness, and its back face is added to its mesh: triangles [pane_triangles, 2 pane_triangles)
  // are the first pane_triangles reversed, in order (solver/pipeline/panes.h). 0: not a pane.
  std::size_t pane_triangles = 0;
};

// Where a sun placed by place and time stands (solver/lights/solar_position.h: NOAA's algorithm), as
// the decoder found it: kept for the result, which states the sun a light was given.
struct SunPlacement {
  double latitude_deg = 0, longitude_deg = 0;
  std::string time;                 // ISO 8601, as given
  double elevation_deg = 0;         // above the horizon, with refraction
  double azimuth_deg = 0;           // clockwise from north
  // Whether the normal illuminance came from the clear-sky model (clear_sky_normal_illuminance_lx)
  // rather than from the scene (a directional light only).
  bool clear_sky_illuminance = false;
};

// Light sources (SPEC §1 "Light models"). Spectra are absolute after photometric scaling.
struct AmbientLight { std::vector<double> irradiance_W_m2_nm; };
struct DirectionalLight {
  Vector3 direction;                // unit, the direction the light travels
  std::vector<double> irradiance_W_m2_nm;  // on a plane perpendicular to the beam
  std::optional<SunPlacement> sun;  // where the direction came from "sun"
};
struct Attenuation { double c1 = 0, c2 = 0, c3 = 1; };  // E = I cos α / (c1 + c2 r + c3 r²); default 1/r²
// Point-like sources: isotropic point (exponent 0, no axis), goniometric cos^m (Warn: m = 1),
// spot (cos^m inside cutoff, zero beyond). I(ψ) = I_0 cos^m ψ, zero for ψ > 90° when m > 0.
struct PointLight {
  enum class Kind { Point, Goniometric, Spot, Warn } kind = Kind::Point;
  Point3 position;
  Vector3 axis{0, 0, -1};           // unit; unused for Kind::Point
  double exponent = 0;              // m
  double cutoff_rad = kPi;          // spot only; pi means no cutoff
  std::vector<double> intensity_W_sr_nm;  // I_0(λ), on the axis
  Attenuation attenuation;
  bool inverse_square = true;       // false: use attenuation polynomial
};
// A sky (solver/lights/sky_luminance.h, sky_dome.h): an area source at infinity whose luminance over
// the directions above the horizon is L_z(λ) (L/L_z)(ω), with the ground below the horizon a uniform
// Lambertian hemisphere of luminance L_g = ρ_g E_h / π (E_h: the sky's unobstructed horizontal
// illuminance), reaching every point by exact integration over the part of the sky it sees.
struct SkyLight {
  enum class Model { kGeneral, kCieOvercast, kUniform } model = Model::kCieOvercast;
  int cie_type = 16;                // 1–15 for kGeneral
  Vector3 up{0, 0, 1};              // unit
  std::optional<Vector3> sun;       // unit, towards the sun (the skies whose distribution depends on it)
  double ground_reflectance = 0.2;  // ρ_g in [0, 1]
  std::vector<double> zenith_radiance_W_m2_sr_nm;  // L_z(λ)
  std::optional<SunPlacement> sun_placement;       // where `sun` came from "sun" (for the result)
};
// A luminaire from a photometric file (SPEC §1 "luminaire"; solver/lights/luminaire.h): the file's
// intensity distribution I(ω) [cd] about its photometric centre, turned into the scene by the
// direction of γ = 0 (nadir) and of the C0 half-plane, and, where the file gives luminous
// dimensions, an area source whose radiance is I(ω) / A_proj(ω).
struct LuminairePhotometry;  // solver/photometry/distribution.h
struct LuminaireLight {
  std::string name;
  std::string source;                  // the file as the scene names it ("luminaires/a.ies", "inline IES text")
  std::shared_ptr<const LuminairePhotometry> photometry;
  Point3 position;                     // metres: the photometric centre
  Vector3 nadir{0, 0, -1};             // unit: the direction of γ = 0
  Vector3 c0{1, 0, 0};                 // unit, perpendicular to nadir: the C0 half-plane
  double maintenance_factor = 1;
  std::optional<double> luminous_flux_lm;  // the output asked for (a rescale of the file), before the maintenance factor
  double tilt_deg = 0;                 // TILT=INCLUDE: the luminaire's tilt from its measured position
  double tilt_factor = 1;              // the file's tilt multiplier at tilt_deg (1 without tilt data)
  double candela_scale = 1;            // × the file's candela: rescale × tilt factor × maintenance factor
  std::vector<double> intensity_W_sr_nm;  // spectral intensity per candela of the file, candela_scale included
};
using Light = std::variant<AmbientLight, DirectionalLight, PointLight, SkyLight, LuminaireLight>;

// EN 17037's recommendation for daylight provision through a daylight factor (its Annex A): a target
// illuminance E_T over 50 % of the reference plane and a minimum target E_TM over 95 %, here as the
// daylight factors D = E / E_v,d,med for the site's median external diffuse illuminance.
struct En17037Request {
  enum class Level { kMinimum, kMedium, kHigh } level = Level::kMinimum;
  double median_external_diffuse_illuminance_lx = 0;  // E_v,d,med > 0
};

// Daylight metrics a probe asks for (SPEC §5 "Daylight"); each needs the scene's one sky.
struct DaylightRequest {
  bool daylight_factor = false;      // DF = E / E_h per point, with statistics
  double target_pct = 2;             // the share of points with DF at or above it is reported
  std::optional<En17037Request> en17037;  // with daylight_factor, on a grid
  bool vertical_sky_component = false;    // the direct sky's share of E_h on a vertical plane
};

// What a probe measures (SPEC §5 "quantity", solver/receiver.h): planar (the default) and vertical
// are the illuminance of a plane facing `normal` (vertical names the check, with `normal` usually
// horizontal); cylindrical and hemispherical the mean over the curved surface of a small vertical
// cylinder (axis `normal`) or hemisphere (pole `normal`); semicylindrical over a half cylinder (axis
// `normal`) facing `facing`.
enum class ProbeQuantity { Planar, Vertical, Cylindrical, Semicylindrical, Hemispherical };
// The quantity's name in the scene and the result ("planar", "cylindrical", ...).
inline const char* quantity_name(ProbeQuantity q) {
  switch (q) {
    case ProbeQuantity::Planar: return "planar";
    case ProbeQuantity::Vertical: return "vertical";
    case ProbeQuantity::Cylindrical: return "cylindrical";
    case ProbeQuantity::Semicylindrical: return "semicylindrical";
    case ProbeQuantity::Hemispherical: return "hemispherical";
  }
  return "planar";
}

struct Probe {
  std::string name;
  std::vector<Point3> points;       // one point, or nu*nv grid points (u fastest)
  Vector3 normal;                   // unit
  bool is_grid = false;
  int nu = 1, nv = 1;
  ProbeQuantity quantity = ProbeQuantity::Planar;
  Vector3 facing;                   // unit, perpendicular to normal: semicylindrical only
  DaylightRequest daylight;
};

// The task-area summary (SPEC §5 "task_summary", solver/task_summary.h): EN 12464-1's checks of
// named grids and of the room's walls and ceiling.
struct TaskSummaryOptions {
  double maintenance_factor = 1;  // in (0, 1]: multiplies every illuminance of the summary
  std::optional<Vector3> up;      // unit: the orientation rule's up, where no surface has a role
  std::vector<int> grids;         // indices into Scene::probes (grid probes), in the order given
};

// An observer of the glare evaluation (SPEC §5 "glare", solver/glare.h).
struct GlareObserver {
  std::string name;
  Point3 position;                // metres: the eye
  Vector3 view, up;               // unit; up perpendicular to view (the codec makes it so)
};

struct MeshingOptions {
  std::optional<double> max_patch_area_m2;  // absent: chosen from the scene's size
  bool adaptive = false;
  // Split patches where the direct light jumps, and next to probe points, before the solve
  // (patch_refinement.h); both methods.
  bool refine_direct = true;
};

// Dense: every patch pair (N² factors, exact up to ray noise; memory 8 N² bytes).
// Hierarchical: links between elements and clusters refined to `accuracy` (solver/hierarchical/),
// cost about linear in N. Auto picks by cost: on the benchmark room (docs/BENCHMARKS.md, "Which
// method auto picks") the dense method costs about 1e-7 N² s and the hierarchical one 2.5e-4 N s,
// equal near 2 500 patches; up to twice that the dense method, exact, is taken at a small premium.
enum class SolverMethod { Auto, Dense, Hierarchical };
inline constexpr std::size_t kDenseAutoPatches = 5000;

struct SolverOptions {
  double tolerance = 1e-4;          // relative residual of the radiosity system
  int max_iterations = 10000;
  SolverMethod method = SolverMethod::Auto;
  // Hierarchical only: the share of the scene's power a link may carry as error (BF refinement
  // threshold, times a fixed calibration), which also sets the rays per link and the probes' depth.
  double accuracy = 1e-3;
  // Hierarchical only: the final gather at the leaves re-traces every link whose visibility is not
  // proven, at each leaf, with the exact visible part where its rays disagree (hierarchical.cpp,
  // LeafGather). Slower; closer row sums near occluders.
  bool exact_visibility = false;
  // Hierarchical only, not part of the scene format: the final gather at the leaves can be turned off
  // to measure what it does (tests, benchmarks).
  bool leaf_gather = true;
  // Hierarchical only, not part of the scene format: the final gather's budget of leaf links, where
  // not 0 (otherwise its own, solver/hierarchical/final_gather.h), to measure what a gather that
  // does not fit does (tests).
  std::size_t leaf_link_budget = 0;
};

struct OutputOptions {
  bool spectral = true;
  bool per_source = false;  // also return each source's contribution (the solution is linear in them)
  // The surface-to-surface view factors (solver/thermal/view_factors.h). The patch-to-patch matrix,
  // which can outgrow any result, is `lambert viewfactors --patches`'s alone.
  bool view_factors = false;
  // stats.error_estimate: the change from a second solve on patches four times larger
  // (solver/pipeline/error_estimate.h); it costs that solve, about a quarter (hierarchical) or a
  // sixteenth (dense) of the first.
  bool error_estimate = false;
  // Each luminaire's standard UGR table by CIE 190 (solver/ugr_table.h), in the result's "luminaires".
  bool ugr_tables = false;
};

struct Scene {
  int format_version = 1;
  std::string name;
  double unit_m = 1.0;              // metres per scene unit (results are per m²; positions in scene units)
  SpectrumMode mode = SpectrumMode::Spectral;
  WavelengthGrid grid;
  std::vector<Material> materials;
  std::vector<Surface> surfaces;
  std::vector<Light> lights;
  std::vector<std::string> light_pointers;  // JSON pointer per light, for messages
  std::vector<Probe> probes;
  std::optional<TaskSummaryOptions> task_summary;
  std::vector<GlareObserver> glare;
  MeshingOptions meshing;
  SolverOptions solver;
  OutputOptions output;
  std::vector<std::string> warnings;  // decoder warnings (e.g. mesh health), carried into the result
};

}  // namespace lambert
