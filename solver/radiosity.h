// The radiosity solver: scene in, per-patch spectral radiosity and irradiance out.
//
//   B_i(λ) = M_i(λ) + ρ_i(λ) H_i(λ),   H_i = Σ_j F_ij B_j + E_i^direct          (constant elements)
//
// F_ij from the exact point-to-polygon kernel integrated over patch i (solver/form_factor.h) times a
// kernel-weighted ray-traced visible fraction (solver/visible_fraction.h); rows of closed patches are
// balanced to sum to 1 by a symmetric scaling that keeps reciprocity exact. The system (I − ρF) B = M + ρE is solved once per distinct spectral system
// with restarted GMRES, which converges in O(sqrt(1/(1−ρ))) iterations even for ρ → 1.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/glare.h"
#include "solver/scene.h"

namespace lambert {

struct Patch {
  int surface = 0;          // index into Scene::surfaces
  Triangle triangle;        // metres
  double area_m2 = 0;
  Vector3 normal;
  int input_triangle = -1;  // the input triangle it was cut from, counted over all surfaces in order
};

struct ProbeResult {
  std::vector<double> irradiance;  // [point][λ] flat, W m^-2 nm^-1
  // Per point, where the probe asks for the vertical sky component (Probe::daylight): the part of the
  // sky's unobstructed horizontal illuminance that reaches the point straight from the sky it sees,
  // ∫_{visible sky} (L/L_z)(ω) (n·ω) dω / K (solver/pipeline/daylight.h). Empty otherwise.
  std::vector<double> sky_component;
};

// What a solve measured: the fields every method fills, then each method's own (stats.dense,
// stats.hierarchical; SPEC §5).
struct SolveStats {
  SolverMethod method = SolverMethod::Dense;  // the method that ran (never Auto)
  std::size_t patches = 0;
  std::size_t links = 0;               // dense: patch pairs with a non-zero factor; hierarchical: every link
  std::uint64_t rays = 0;
  std::uint64_t exact_visibility_evaluations = 0;  // exact Boolean evaluations (probe point × input triangle)
  std::uint64_t links_clear = 0;       // links wholly visible by the occluder planes (occluder_planes.h) or,
                                       // hierarchical, the solids' shafts (solid_shafts.h): no rays
  std::uint64_t link_rays = 0;         // rays traced for links
  int iterations = 0;                  // largest over the spectral systems
  double residual = 0;                 // largest final relative residual
  int spectral_systems_solved = 0;
  double emitted_W = 0, absorbed_W = 0, escaped_W = 0, relative_imbalance = 0;
  double max_closure_error = 0;        // max |1 − Σ_j F_ij| over closed patches, before their rows
                                       // were scaled to 1 (the visible-fraction estimates' error)
  double closure_residual = 0;         // what the closure balance left: max |1 − sum| over the rows (and,
                                       // hierarchical, the columns) it holds at 1, after it
  double max_reciprocity_error = 0;    // max |A_i F_ij − A_j F_ji| / max(A_i F_ij, A_j F_ji)
  double mean_reciprocity_error = 0;   // Σ |A_i F_ij − A_j F_ji| / Σ max(A_i F_ij, A_j F_ji), same pairs
  double time_meshing_s = 0, time_visibility_s = 0, time_form_factors_s = 0, time_solve_s = 0,
         time_probes_s = 0, time_total_s = 0;
  double max_patch_area_m2 = 0;
  std::size_t contact_triangles_cut = 0;  // input triangles cut along other surfaces' contact lines
  std::size_t sliver_regions_remeshed = 0;  // planar regions of slivers joined and triangulated again
  double contact_area_m2 = 0;            // face-to-face contact area removed (both faces counted)
  std::size_t enclosed_patches = 0;      // patches inside closed solids, left out of the result
  std::size_t direct_refinement_patches = 0;  // meshing.refine_direct: patches added before the solve
  std::size_t fine_regions_remeshed = 0;  // over-tessellated planar regions joined before meshing

  struct Dense {
    int adaptive_rounds = 0;        // meshing.adaptive: how many refine-and-solve rounds ran
    double link_ray_thread_s = 0;   // thread time spent on link rays, summed over threads: sample
                                    // points, kernel weights, Embree and the votes (the per-ray cost)
  } dense;
  struct Hierarchical {
    std::size_t element_links = 0;  // links into elements (from elements or clusters) after the gather
    std::size_t cluster_links = 0;  // links into clusters
    std::size_t leaf_links = 0;          // links formed at the leaves by the final gather
    std::size_t leaf_links_traced = 0;   // of which needed the leaf's own visibility
    std::size_t leaf_links_exact = 0;    // of which were partly visible, with the exact visible part
    std::size_t crowded_links = 0;  // exact visibility: links that kept their rays' estimate (or stayed
                                    // hidden), their pair's box holding too many occluders
    int refine_rounds = 0;          // refinement rounds that changed the links
  } hierarchical;

  // output.error_estimate (solver/pipeline/error_estimate.h): the change from a solve on patches four
  // times larger, relative to this solve's values (totals over λ). Absent unless asked.
  struct ErrorEstimate {
    std::size_t coarse_patches = 0;
    double coarse_max_patch_area_m2 = 0;
    double surface_irradiance_max = 0;  // max over surfaces of |Ē_h − Ē_2h| / Ē_h
    double probe_irradiance_rms = 0;    // over every probe point, |E_h − E_2h| / E_h
    double probe_irradiance_max = 0;
    double time_s = 0;                  // the coarser solve and the comparison
  };
  std::optional<ErrorEstimate> error_estimate;
};

// One source's share of the solution (output.per_source). The radiosity equation is linear in the
// sources, so the contributions add up to the joint solution: a client can dim or recolour a source
// by scaling its contribution, without solving again.
struct SourceContribution {
  std::string pointer;              // "/lights/2" or "/surfaces/5" (an emitting surface)
  std::string name;                 // the surface's name, or the light's type
  std::vector<double> radiosity;    // [patch][λ] flat, like Solution::radiosity
  std::vector<double> irradiance;   // [patch][λ] flat
  std::vector<ProbeResult> probes;  // parallel to Scene::probes
};

struct RadiantExchange;  // solver/thermal/radiant.h

struct Solution {
  WavelengthGrid grid;
  std::vector<Patch> patches;
  std::vector<double> radiosity;    // [patch][λ] flat, W m^-2 nm^-1 (B)
  std::vector<double> irradiance;   // [patch][λ] flat, W m^-2 nm^-1 (H)
  std::vector<ProbeResult> probes;  // parallel to Scene::probes
  std::vector<SourceContribution> contributions;  // with output.per_source: lights, then emitters
  std::vector<GlareResult> glare;   // parallel to Scene::glare
  // With output.view_factors or "thermal" surfaces: the view factors and the radiant exchange, on
  // patches of their own (the geometry's, not refined by the light).
  std::shared_ptr<const RadiantExchange> radiant;
  SolveStats stats;
  std::vector<std::string> warnings;
  std::size_t wavelengths() const { return grid.size(); }
};

// The stages of a solve, in the order they begin (SolveControl::stage); the refine–solve rounds of
// the hierarchical method go from Links to Solve and back.
//   Meshing: the scene prepared and meshed (contacts, merges, patches or element trees)
//   Visibility: the visibility scene and the patches' hemispheres
//   Links: form factors (dense) or the links' refinement (hierarchical)
//   Solve: the linear systems and the outputs
//   Probes: the probe points
enum class SolveStage { Meshing, Visibility, Links, Solve, Probes };
const char* stage_name(SolveStage stage);      // "meshing", "visibility", "links", "solve", "probes"
const char* method_name(SolverMethod method);  // "auto", "dense", "hierarchical" (the scene's words)

// Progress in [0, 1] and cooperative cancellation (checked between work items).
struct SolveControl {
  std::function<void(double)> progress;
  std::function<void(SolveStage)> stage;  // called as each stage begins (may be empty)
  const std::atomic<bool>* cancel = nullptr;
  std::size_t max_patches = 0;  // a service's limit on the patch count (0: only the solver's own);
                                // exceeding it throws SolveError, before the form factors
  // What sets max_patches, for that message ("the 4166 patches that max_result_bytes = ... allows");
  // empty: "this server's limit of N (max_patches)".
  std::string max_patches_reason;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
  void check_cancel() const;  // throws SolveCancelled where cancel is set
};

class SolveCancelled : public std::runtime_error {
 public:
  SolveCancelled() : std::runtime_error("solve cancelled") {}
};
inline void SolveControl::check_cancel() const {
  if (cancelled()) throw SolveCancelled();
}

// A scene that is valid JSON but cannot be solved (e.g. a closed room with ρ = 1 everywhere).
class SolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// min(solver_limit, control.max_patches), or solver_limit where the service sets no limit.
std::size_t patch_limit(std::size_t solver_limit, const SolveControl& control);

// Throws SolveError, naming meshing.max_patch_area, when a meshing gives (or, with `estimate`, would
// give at least) more patches than patch_limit(solver_limit, control): called before the subdivision
// is allocated, so that a patch size in the wrong unit fails at once instead of exhausting memory,
// and again with the real count.
void check_patch_count(double patches, bool estimate, std::size_t solver_limit, const SolveControl& control);


Solution solve(const Scene& scene, const SolveControl& control = {});

// The default patch size when the scene does not set meshing.max_patch_area: total area / 1200,
// which keeps the Cornell box near 1500 patches.
double default_max_patch_area(const Scene& scene);
// The patch count meshing will give, estimated from the triangles' areas and the patch size (what
// solver.method "auto" decides by, before meshing).
double estimated_patch_count(const Scene& scene);

// The scene's input triangles (metres), every surface's in order: the occluders of exact visibility
// and of the occluder planes, and what Patch::input_triangle counts.
std::vector<Triangle> input_triangles(const Scene& scene);
// Surface::two_sided of each input triangle, in the same order.
std::vector<char> input_two_sided(const Scene& scene);
// The total area of the input triangles (m²).
double scene_area(const Scene& scene);

}  // namespace lambert
