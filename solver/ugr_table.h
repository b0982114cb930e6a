// A luminaire's standard UGR table by the tabular method of CIE 190:2010 ("Calculation and
// presentation of unified glare rating tables for indoor lighting luminaires"), the table makers
// publish beside a photometric file: CIE 117's UGR = 8 log10((0.25 / L_b) Σ L² ω / p²) for an
// observer at the middle of one wall of a room of the luminaire, looking horizontally along the room.
//
// The rooms. X across the line of sight and Y along it, in units of H = 2 m, the height of the
// luminaires above the eye: the 19 rooms X × Y = 2H × (2H, 3H, 4H, 6H, 8H, 12H), 4H × (the same),
// 8H × (4H, 6H, 8H, 12H), 12H × (4H, 6H, 8H). The luminaires fill the room's plane on a square grid of
// spacing S = 0.25 H, half a spacing from the walls: at T = (i + ½) S − X/2 beside the line of sight
// and R = (j + ½) S along it, N = (X/S)(Y/S) of them. Crosswise, the luminaire's C0 half-plane faces
// the observer (the line of sight lies in the C0–C180 plane); endwise, the C90 half-plane does.
//
// The sum. Each luminaire adds L² ω / p² with L = I / A_p, ω = A_p / r² (so I² / (A_p r²)): I the
// intensity towards the eye, A_p the projected luminous area that way (the file's luminous
// dimensions, luminous_opening.h), r² = R² + T² + H², and p Guth's index at (H/R, T/R) from CIE 117
// Table 4.1 (glare.h). Luminaires beyond the table, or seen at γ > 85° from nadir, do not count
// (the reading of CIE 117 §4.5 in eulumdat-ugr, below).
//
// The background. L_b = E_WID / π, E_WID the indirect illuminance of the walls between the eye and
// the luminaires' plane by CIE 190's flux-transfer formulas (its §4.2, eqs. 7–12):
//   Φ_zLn  the luminaire's flux into the cones about nadir with cos γ = 0.75, 0.5, 0.25, 0 (CIE 190
//          sums 10° zonal fluxes, with 0.130 of the 40–50° zone and 0.547 of the 70–80° zone: the
//          solid-angle shares of those zones inside the cones; here the cones are integrated
//          exactly, distribution.h);
//   Φ_DF = Σ F_GLn Φ_zLn   the flux falling directly on the plane of the eye (F_GL by room index
//          k = XY / (H (X + Y)), CIE 190 Table 4);
//   Φ_DW = Φ_zL4 − Φ_DF    the downward flux falling directly on the walls;  Φ_DC the upward flux;
//   E_WID = (N / A_w) (Φ_DF F_T,FW + Φ_DW F_T,WW−1 + Φ_DC F_T,CW),   A_w = 2 H (X + Y),
// with the transfer factors F_T per room and reflectances (ceiling / walls / plane of the eye
// 0.7/0.5/0.2, 0.7/0.3/0.2, 0.5/0.5/0.2, 0.5/0.3/0.2, 0.3/0.3/0.2) of CIE 190 Table 5.
// The factors of Tables 4 and 5 are CIE 190's as transcribed in eulumdat-ugr
// (github.com/123VincentB/eulumdat-ugr, background.py, MIT); docs/METHOD.md compares the tables
// this gives with those DIALux and Relux publish for its sample files.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "solver/photometry/distribution.h"
#include "solver/photometry/luminous_opening.h"

namespace lambert {

inline constexpr std::size_t kUgrRooms = 19, kUgrReflectances = 5;
inline constexpr double kUgrHeight_m = 2.0;          // H: the luminaires above the eye
inline constexpr double kUgrSpacingToHeight = 0.25;  // S / H
inline constexpr double kUgrMaxGamma_deg = 85;       // luminaires seen farther from nadir do not count

enum class UgrViewing { kCrosswise, kEndwise };

struct UgrRoom {
  int x_h = 0, y_h = 0;  // X (across the line of sight) and Y (along it) in units of H
};
struct UgrReflectances {
  double ceiling = 0, walls = 0, plane = 0;
};
const std::array<UgrRoom, kUgrRooms>& ugr_rooms();
const std::array<UgrReflectances, kUgrReflectances>& ugr_reflectances();

// The fluxes of CIE 190's background: Φ_zL1 … Φ_zL4 and the upward flux [lm].
struct UgrZonalFlux {
  std::array<double, 4> cumulative{};
  double upward = 0;
};
// For the file's distribution × candela_scale: exact where the web's polar axis is nadir (types C
// and A), by a 400 × 720 midpoint rule in (cos γ, C) otherwise (type B).
UgrZonalFlux ugr_zonal_flux(const PhotometricDistribution& d, double candela_scale);

// L_b [cd/m²] of room `room` (an index into ugr_rooms()) with reflectances `reflectance`.
double ugr_background_luminance(const UgrZonalFlux& flux, std::size_t room, std::size_t reflectance);

// Σ L² ω / p² over the room's luminaires. `opening` is the file's, placed at the origin of the
// luminaire's own frame (x C0, y C90, z up).
double ugr_glare_sum(const PhotometricDistribution& d, const LuminousOpening& opening, double candela_scale,
                     std::size_t room, UgrViewing viewing);

struct UgrTable {
  double luminous_flux_lm = 0;  // ∫ I dω of the luminaire the table is for
  // [room][reflectance]; nullopt where L_b or the sum is 0 (UGR undefined).
  std::array<std::array<std::optional<double>, kUgrReflectances>, kUgrRooms> crosswise, endwise;
};

// The table for the file's distribution × candela_scale; nullopt where the file gives no luminous
// area (a point, or a shape not modelled as one): L = I / A_p needs it.
std::optional<UgrTable> standard_ugr_table(const PhotometricData& file, const PhotometricDistribution& d,
                                           double candela_scale);

}  // namespace lambert
