// The hemisphere stage of the solve, shared by both methods: what each patch's hemisphere holds
// (Hemisphere, solver/visible_fraction.h), found by the probe below or from exact factors, and what
// the solve does with the verdicts: the row closure holds closed rows at 1, patches inside closed
// solids take no part and are left out of the result, and leaks are reported.
#pragma once

#include <cstddef>
#include <vector>

#include "solver/radiosity.h"
#include "solver/visibility.h"
#include "solver/visible_fraction.h"

namespace lambert {

// The hemisphere probe over one visibility scene: `normals` and `two_sided` per occluder of `vis`
// (a two-sided occluder is one face of a sheet of zero thickness, Surface::two_sided, whose other
// face, coincident, faces the ray whichever is hit: never a back face).
class HemisphereProbe {
 public:
  HemisphereProbe(const Visibility& vis, std::vector<Vector3> normals, std::vector<char> two_sided);

  // probe_hemisphere (visible_fraction.h) of triangle t with unit normal n; `seed` decorrelates
  // neighbouring patches' directions (their index).
  Hemisphere classify(const Triangle& t, const Vector3& n, std::size_t seed, int rays) const;

 private:
  const Visibility& vis_;
  std::vector<Vector3> normals_;
  std::vector<char> two_sided_;
};

// 1024 rays: an opening of 1 % of the projected hemisphere goes unseen with probability 3e-5.
inline constexpr int kHemisphereRays = 1024;

// A patch whose exact unoccluded factors (no occluder can hide one surface from it) cover its
// hemisphere to within 1e-3 is closed; finer than the probe's rays resolve.
Hemisphere hemisphere_from_coverage(double covered);

// Warnings naming the surfaces of leaking patches and of patches inside closed solids.
void report_hemisphere_findings(Solution& sol, const Scene& scene, const std::vector<Hemisphere>& hemisphere);

// Removes patches inside closed solids from the solution (patches, radiosity, irradiance and every
// source's contribution) and counts them in stats.enclosed_patches.
void leave_out_enclosed(Solution& sol, const std::vector<Hemisphere>& hemisphere);

}  // namespace lambert
