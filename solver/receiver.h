// What a probe point measures: irradiance on a receiver at a point. Only the planar receiver exists
// (a plane with unit normal n: E = ∫ L (n·ω)⁺ dω, the illuminance of a horizontal or vertical plane).
// A receiver of another shape (cylindrical, semicylindrical, hemispherical) weighs directions by its
// own w(ω) instead of (n·ω)⁺: it adds a Kind and the fields it needs (an axis, a facing), and the
// kernels that take a Receiver (the operators' gather_at_point, solver/pipeline/transport_operator.h,
// and the lights' point factors) handle it.
#pragma once

#include <cstdint>

#include "mesh/geometry.h"

namespace lambert {

struct Receiver {
  enum class Kind : std::uint8_t { Planar };
  Kind kind = Kind::Planar;
  Point3 point;   // metres
  Vector3 normal;  // unit: the side the plane receives on
};

}  // namespace lambert
