// The progress line of `lambert solve` and the other solving commands: on a terminal, stderr shows
// "links: 42 % (about 8 s left)", redrawn in place: the stage the solver reports (SolveControl::stage:
// meshing, visibility, links, solve, probes; "solving" before the first) and the overall fraction.
#pragma once

#include <string>
#include <string_view>

#include "solver/radiosity.h"

namespace lambert {

// The line's text for `fraction` of the work done after `elapsed_s` seconds. The time left is the
// linear extrapolation elapsed × (1 − f) / f, shown once f ≥ 2 % and a second has passed (before
// that the rate says little).
std::string progress_text(std::string_view stage, double fraction, double elapsed_s);

// Installs the terminal display on `control` when stderr is a terminal; otherwise leaves it alone.
void show_progress_on_terminal(SolveControl& control);

}  // namespace lambert
