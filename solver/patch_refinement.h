// Splitting patches where the light varies: the rules shared by the dense solver's meshing
// (meshing.refine_direct before the solve, meshing.adaptive after it) and the hierarchical solver's
// element trees (meshing.refine_direct).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "solver/radiosity.h"
#include "solver/scene.h"
#include "solver/visibility.h"

namespace lambert {

// meshing.refine_direct splits where a patch's direct irradiance is more than this many times a
// neighbour's: a jump, not a gradient. Measured on the Cornell box (docs/BENCHMARKS.md): a ratio of
// 1.22 quadrupled the walls under the light and gained nothing over 5, which refines only the
// blocks' penumbrae on the floor and walls.
inline constexpr double kDirectRatio = 5;

// The visibility samples of every patch, lifted off its surface (Visibility::lift): patch i's sample
// k (visible_fraction.h, visibility_sample) at [i * kMaxVisibilitySamples + k]. Computed once, they
// serve every link of the patch.
std::vector<Point3> lifted_visibility_samples(const std::vector<Patch>& patches, const Visibility& vis);

// Visible fractions between patch a (index into `patches`) and each of `partners`, from rays weighted
// by the differential kernel (visible_fraction.h) between the patches' lifted samples; also the dense
// solve's link visibility. Returns the rays traced.
std::size_t patch_visible_fractions(std::size_t a, std::span<const std::size_t> partners,
                                    const std::vector<Patch>& patches, std::span<const Point3> samples,
                                    const Visibility& vis, std::span<double> fractions);

// Marks patches whose quantity q (radiometric total Σ_λ w_λ H(λ)) is more than `ratio` times a
// neighbour's on the same surface and plane (sharing a vertex; not across a crease), or less than
// 1/ratio of it, and differs by more than 0.1 % of the area-weighted mean of q.
std::vector<char> where_varies(const std::vector<Patch>& patches, const std::vector<double>& q, double ratio);

// The marked patches split 1:4, except those that would fall below min_area.
std::vector<Patch> split_marked(const std::vector<Patch>& patches, const std::vector<char>& marked, double min_area);

// Marks the patches that a probe point sees from closer than 0.55 times their longest edge.
void mark_near_probes(const std::vector<Patch>& patches, const std::vector<Probe>& probes, std::vector<char>& marked);

// Whether the scene has anything that lights patches directly (a light or an emitting surface).
bool has_direct_light(const Scene& scene);

// Each patch's direct irradiance, radiometric total: lights and Phong emitters (patch_factor),
// Lambertian emitting patches (exact factor times ray visibility; left out where more than an eighth
// of the patches emit). Throws SolveCancelled when control.cancel is set.
std::vector<double> direct_irradiance_totals(const Scene& scene, const std::vector<Patch>& patches,
                                             const Visibility& vis, const SolveControl& control);

}  // namespace lambert
