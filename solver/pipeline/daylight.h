// The daylight stage, after the solve and for either method: the vertical sky component at the probes
// that ask for it (SPEC §5 "Daylight"),
//   VSC(p) = ∫_{visible sky} (L/L_z)(ω) (n·ω) dω / K,
// the direct light of the scene's sky alone (no ground, no reflection) over the sky's unobstructed
// horizontal illuminance E_h = K L_z, integrated exactly over the part of the sky the point sees
// (solver/lights/sky_dome.h). It is geometry only: no spectrum, no solve.
#pragma once

#include "solver/radiosity.h"

namespace lambert {

// Fills sol.probes[k].sky_component for every probe of `scene` (the scene the solution was solved
// for) that asks for it; the decoder has made sure the scene has one sky then.
void measure_sky_components(const Scene& scene, Solution& sol, const SolveControl& control);

}  // namespace lambert
