// A photometric file as its maker wrote it: IES LM-63 (1986, 1991, 1995, 2002, 2019) or EULUMDAT
// (.ldt), read into one type. The readers are Lambert's own and strict, written for files from
// strangers: every count is checked against the limits and against the bytes that follow before
// anything is allocated, every number must be one (NaN, infinities, negative candela, angles out of
// order or out of range are refused), and every error names the file, the line and the field:
//   "downlight.ies: line 14: candela value 3 of horizontal angle 45: -2 is negative".
// Nothing is read but the text given: TILT=<file> (tilt data in another file) is refused.
//
// The type keeps the file's own angles and table (after the multipliers that scale every value:
// the candela multiplier and ballast factor of LM-63, the conversion factor and lamp flux of
// EULUMDAT); unfolding the symmetry, interpolating and integrating are distribution.h's.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lambert {

enum class PhotometricFormat { kIes, kEulumdat };

// The goniometer's coordinate system. LM-63 numbers them 1 = C, 2 = B, 3 = A; EULUMDAT is always C.
// Frames (docs/SPEC.md, "luminaire"): with x the C0 direction, y the C90 direction and z up (nadir −z):
//   C: polar axis z; C counter-clockwise from x seen from above, γ from nadir:
//      (sin γ cos C, sin γ sin C, −cos γ).
//   B: polar axis y; the vertical angle V turns a plane about y from nadir towards x, the
//      horizontal angle H leaves it towards −y (clockwise seen from above when aimed):
//      (cos H sin V, −sin H, −cos H cos V).
//   A: polar axis z; H clockwise from x seen from above, V the elevation (V = −90° is nadir):
//      (cos V cos H, −cos V sin H, sin V).
enum class PhotometryType { kC, kB, kA };

// The luminous opening's shape (LM-63-2002/2019 Table 1 by the signs of width, length and height;
// LM-63-1995 and earlier by their own encodings; EULUMDAT: a rectangle or circle, with luminous side
// faces where the side heights are not 0).
enum class LuminousShape {
  kPoint,
  kRectangle,          // length × width, horizontal
  kBox,                // length × width × height, every face luminous
  kDisk,               // diameter length (= width), horizontal
  kEllipse,            // axes length and width, horizontal
  kVerticalCylinder,   // diameter length (= width), height
  kSphere,             // diameter length (= width = height)
  kHorizontalCylinderAlongC0,   // axis along C0–C180, length; diameter width (= height)
  kHorizontalCylinderAlongC90,  // axis along C90–C270, width; diameter length (= height)
  kSideFaces,          // EULUMDAT: a rectangle or circle with luminous sides of their own heights
  kUnsupported,        // a shape of the table not modelled as an area (elliptic cylinders,
                       // ellipsoids, vertical disks): the point form is used, with a warning
};

struct LuminousDimensions {
  LuminousShape shape = LuminousShape::kPoint;
  double length_m = 0;  // along the C0–C180 axis (LM-63's "length"; EULUMDAT line 16)
  double width_m = 0;   // along the C90–C270 axis (LM-63's "width"; EULUMDAT line 17)
  double height_m = 0;  // vertical
  // EULUMDAT lines 18–21: heights of the luminous sides facing C0, C90, C180 and C270.
  std::array<double, 4> side_height_m{0, 0, 0, 0};
  bool circular = false;  // EULUMDAT: width 0, a circle of diameter length_m
  // EULUMDAT: the luminous area lies at the photometric centre and its sides rise above it; LM-63's
  // shapes with a height are centred on the photometric centre.
  bool sides_rise_from_centre = false;
  std::string description;  // the shape as the file states it, for messages ("disk 0.2 m", ...)
};

// TILT=INCLUDE: the lamp's output against the luminaire's tilt from its measured position.
struct TiltTable {
  int lamp_to_luminaire_geometry = 1;  // LM-63: 1 vertical lamp, 2 horizontal lamp that stays
                                       // horizontal, 3 horizontal lamp that tilts with the luminaire
  std::vector<double> angles_deg;      // ascending, in [0, 180]
  std::vector<double> factors;         // ≥ 0, one per angle
};

struct PhotometricData {
  PhotometricFormat format = PhotometricFormat::kIes;
  std::string version;  // "LM-63-2002", "EULUMDAT", ...
  PhotometryType type = PhotometryType::kC;

  // The web as the file lists it. IES: its vertical and horizontal angles, candela[h][v]. EULUMDAT:
  // γ as vertical angles, and as horizontal angles the C angles of the planes the file stores for
  // its symmetry (Isym 1: C0; 2: C0–C180; 3: C90–C270; 4: C0–C90; 0: every plane), so that the
  // horizontal angles say the symmetry the way LM-63's do.
  std::vector<double> vertical_deg;
  std::vector<double> horizontal_deg;
  std::vector<double> candela;  // [h][v], cd, every multiplier but the tilt factor applied
  // Where each angle and candela row came from (line numbers), for later messages.
  std::size_t table_line = 0;

  bool absolute_photometry = false;            // LM-63: lumens per lamp −1; EULUMDAT: lamps < 0
  std::optional<double> declared_lamp_flux_lm;  // the lamps' rated flux (relative photometry)
  std::optional<double> declared_output_lm;     // the luminaire's flux the file states (EULUMDAT:
                                                // LORL × lamp flux, or the absolute flux)
  int lamp_count = 1;
  double input_watts = 0;
  double ballast_factor = 1;                    // LM-63 (already applied to candela)
  double multiplier = 1;                        // LM-63 candela multiplier / EULUMDAT conversion
                                                // factor (already applied)
  std::optional<TiltTable> tilt;                // TILT=INCLUDE
  LuminousDimensions opening;
  std::string luminaire;                        // [LUMINAIRE] or EULUMDAT line 9
  std::string manufacturer;                     // [MANUFAC] or EULUMDAT line 1
  std::vector<std::string> warnings;            // "NAME: line N: ..." (missing required keywords, ...)
};

// Bounds on what one file may make a reader allocate.
struct PhotometricLimits {
  std::uint64_t max_bytes = std::uint64_t{16} << 20;  // 16 MiB
  std::size_t max_vertical_angles = 3601;              // 0.05° steps over 180°
  std::size_t max_horizontal_angles = 7201;            // 0.05° steps over 360°
  std::size_t max_values = 4'000'000;                  // candela values in all
  std::size_t max_tilt_angles = 3601;
  std::size_t max_lines_before_data = 100'000;         // keyword or label lines
};

struct PhotometricParse {
  std::optional<PhotometricData> data;
  std::string error;  // "NAME: line N: field: why" when data is empty
  bool ok() const { return data.has_value(); }
};

// The entry points (one per format): text is the whole file, name what messages call it (the scene's
// relative path, or "inline IES text"). Never throws on bad input; safe for any bytes.
PhotometricParse parse_ies(std::string_view text, std::string_view name, const PhotometricLimits& limits = {});
PhotometricParse parse_ldt(std::string_view text, std::string_view name, const PhotometricLimits& limits = {});

// "C", "B" or "A".
const char* photometry_type_name(PhotometryType type);
// "point", "rectangle", "box", "disk", ... (as SPEC and the result name them).
const char* luminous_shape_name(LuminousShape shape);

}  // namespace lambert
