// CIELAB and the CIEDE2000 colour difference, for comparing two solutions of one scene
// (lambert compare-rgb). Plain formulas on XYZ values; no spectral data involved.
#pragma once

#include "solver/spectrum.h"

namespace lambert {

struct Lab { double L, a, b; };

// CIE 1976 L*a*b* of `c` relative to the reference white `white` (CIE 15:2018 §8.2.1). Any common
// scale of c and white cancels (photometric XYZ in cd m^-2 is fine); white.Y must be > 0.
Lab cielab(const Xyz& c, const Xyz& white);

// XYZ of the white with luminance Y and chromaticity (x, y).
Xyz white_from_chromaticity(double Y, double x, double y);

// CIEDE2000 total colour difference ΔE00 with k_L = k_C = k_H = 1 (CIE 142-2001; the equations as
// numbered in G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula: implementation
// notes, supplementary test data, and mathematical observations", Color Res. Appl. 30(1), 2005).
// Symmetric in its arguments.
double ciede2000(const Lab& first, const Lab& second);

}  // namespace lambert
