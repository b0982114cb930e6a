// Discomfort glare: the Unified Glare Rating of CIE 117-1995 ("Discomfort glare in interior
// lighting"), for an observer at a point looking along `view` with `up` the vertical of the field:
//
//   UGR = 8 log10( (0.25 / L_b) Σ L² ω / p² )
//
//   L    luminance of the luminous parts of a luminaire in the direction of the eye [cd m^-2]
//   ω    solid angle of those parts at the eye [sr]
//   p    Guth position index of the luminaire (its direction relative to the line of sight)
//   L_b  background luminance [cd m^-2]: the indirect illuminance at the eye on the plane facing
//        the view, over π (CIE 117 §4.2)
//
// Small sources (projected area A_p < 0.005 m², and every point source) take CIE 147:2002's form
// of the term, 200 I² / (r² p²) with I the intensity towards the eye [cd] and r the distance [m];
// for a uniform source L² ω = L² A_p / r² = I² / (A_p r²), which equals 200 I² / r² at
// A_p = 0.005 m²: the two forms meet at the threshold.
//
// The position index p: CIE 117 §4.5 gives Guth's index as a table (Table 4.1) of H/R and T/R, for a
// source at R along the line of sight, H above it and T beside it; Lambert interpolates that table
// bilinearly (ugr_table.h uses the same table for CIE 190's standard tables). The table runs over
// H/R 0 … 1.9 and T/R 0 … 3.0 in steps of 0.1, and leaves blank the cells above the field of view
// (H/R 1.8 and 1.9 where T/R ≤ 0.3, H/R 1.9 where T/R ≤ 0.8): a source in a cell with a blank corner,
// beyond the table, or at R ≤ 0 (beside or behind the eye) does not count. It is applied below the
// line of sight as well (|H|). Levin's analytic fit of the same data (J. IES 4 (1975) 99–105, which
// Radiance's glarendx uses) follows every tabulated value to 11 % (tests/glare_test.cpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mesh/geometry.h"

namespace lambert {

// CIE 117 Table 4.1 at (|H|/R, |T|/R), bilinear between its nodes; nullopt outside the table or in a
// cell with a blank corner.
std::optional<double> guth_position_index_table(double h_over_r, double t_over_r);
// The index for a unit direction towards the source from an eye looking along the unit `view`, with
// `up` the vertical of the field (its part across `view` is used).
std::optional<double> guth_position_index(const Vector3& view, const Vector3& up, const Vector3& to_source);

// CIE 147's bound below which a source is small [m²].
inline constexpr double kSmallSourceArea_m2 = 0.005;

// One luminaire's share of an observer's glare.
struct GlareSource {
  std::string source;          // "/lights/i" or "/surfaces/i"
  bool small = false;          // a point, or projected area < 0.005 m²: CIE 147's term
  double luminance_cd_m2 = 0;  // ω-weighted mean over its luminous parts (0 for a point)
  double solid_angle_sr = 0;   // of its visible luminous parts
  double intensity_cd = 0;     // towards the eye (small sources)
  double distance_m = 0;       // to its centre (small sources)
  double position_index = 1;   // p (effective: the term's, Σ L²ω / Σ L²ω/p², for extended sources)
  double term = 0;             // L² ω / p², or 200 I² / (r² p²)
};

struct GlareResult {
  std::string name;
  double indirect_illuminance_lx = 0;     // E_ind at the eye on the plane facing the view
  double background_luminance_cd_m2 = 0;  // L_b = E_ind / π
  std::optional<double> ugr;              // absent where L_b or Σ is 0 (undefined)
  std::vector<GlareSource> sources;       // the luminaires in the field (σ < 90°, some part visible)
};

// UGR from L_b and the sources' terms (or their sum Σ L² ω / p²); nullopt where either is 0.
std::optional<double> unified_glare_rating(double background_luminance_cd_m2, const std::vector<GlareSource>& sources);
std::optional<double> unified_glare_rating(double background_luminance_cd_m2, double sum);

}  // namespace lambert
