// View3D's input files (.vs3): the geometry description of G. N. Walton's View3D 3.2/3.3 (NIST; the
// View3D user manual, "Input File Format"), read strictly. Both 3-D geometries: F 3 (numbered vertices,
// then surfaces that name four of them, the fourth 0 for a triangle) and F 3a (BLAST surfaces: a shape
// R, Q or T placed by an origin, an azimuth and a tilt). Surfaces are radiating (S), masks (M), null
// surfaces (N) or obstructions only (O); a radiating surface with a base is a subsurface (a window in
// a wall), a combination number merges it into an earlier surface in the output. The control line (C),
// the title (T), comments (a word starting with ! or /) and the end of data (a line starting with E or
// *) are read as View3D reads them.
//
// Strict where View3D is lenient: an unknown line type or control word, a field that is not a number,
// a value out of range, text after a record that is not a comment, a surface out of sequence, a quad
// that is not planar and convex, a subsurface that is not inside its base's plane and polygon: each is
// an error "NAME:LINE: message". Nothing is clamped (View3D clamps emissivities into [0.001, 0.999]);
// View3D's own integration controls (eps, maxU, ...) are read and checked, and do not apply here.
// Reads are bounded: the text's size, every line's length and every name's are limited, and nothing is
// allocated from a count written in the file.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/geometry.h"

namespace lambert::vs3 {

inline constexpr std::size_t kMaxBytes = std::size_t{256} << 20;  // 256 MiB of text
inline constexpr std::size_t kMaxLineBytes = 4096;
inline constexpr std::size_t kMaxNameBytes = 100;  // EnergyPlus's limit on an object's name
inline constexpr std::size_t kMaxErrors = 100;     // beyond this only a count is reported

enum class Geometry { Vertices, Blast };  // "F 3", "F 3a"

enum class SurfaceKind {
  Radiating,    // S: has factors to every other radiating surface
  Mask,         // M: in its base's plane, facing the base; the masked part of the base sees only it
  Null,         // N: in its base's plane, facing the base; removes the covered part of the base
  Obstruction,  // O: blocks views, has no factors
};

struct Surface {
  int number = 0;  // 1-based, as in the file
  SurfaceKind kind = SurfaceKind::Radiating;
  std::vector<Point3> polygon;  // 3 or 4 corners, counter-clockwise seen from the front (active) side
  int base = 0;                 // the surface it lies in (subsurface, mask, null surface), or 0
  int combine = 0;              // the earlier surface it joins in the output, or 0
  std::optional<double> emissivity;  // in [0, 1]; absent for an obstruction
  std::string name;             // as written; an obstruction without one is "obstruction-N"
  int line = 0;                 // the line that defines it
};

// The control line's parameters (View3D's defaults). Only `enclosure` and `emittances` concern the
// factors; the others steer View3D's own integration and output and are kept for what they say.
struct Controls {
  double eps = 1e-4;
  int max_u = 12, max_o = 8, min_o = 0;
  int row = 0, col = 0;  // View3D computes only this row (and column) when they are not 0
  int out = 0, list = 0, max_v = 0;
  bool enclosure = false;   // encl=1: the surfaces form an enclosure
  bool emittances = false;  // emit=1: report Hottel's total exchange factors ("script F")
  bool prj_reverse = false;
};

struct Input {
  std::string title;  // the last T line's text
  Controls controls;
  Geometry geometry = Geometry::Vertices;
  std::vector<Point3> vertices;   // F 3: vertex n of the file is vertices[n − 1]
  std::vector<Surface> surfaces;  // in file order: S, M and N surfaces, then obstructions
  std::vector<std::string> warnings;  // "NAME:LINE: message"
};

struct ReadResult {
  std::optional<Input> input;       // present iff errors is empty
  std::vector<std::string> errors;  // "NAME:LINE: message" (LINE 0: the whole file)
  bool ok() const { return errors.empty(); }
};

// The text of a .vs3 file; `name` (a path, say) starts every message.
ReadResult read_vs3(std::string_view text, std::string_view name);

}  // namespace lambert::vs3
