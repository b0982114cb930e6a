// A luminaire's luminous opening placed in the scene: the surfaces that emit, as parametric faces,
// and the projected area that turns the file's intensity into radiance, L(ω) = I(ω) / A_proj(ω)
// (each point of the opening radiates the same L toward ω; photometric_data.h lists the shapes).
//
// Faces are parametrised over (s, t) ∈ [0, 1]² by smooth maps with a known area element
// dA = J(s, t) ds dt, so that a triangle rule in (s, t) integrates over them exactly as it would over
// a flat triangle: a rectangle (two-sided when it is the whole opening), an ellipse in polar form
// (q = c + s (cos 2πt a + sin 2πt b), J = 2π s |a||b|), a cylinder's side, a sphere
// (q = c + R (sin πs cos 2πt, sin πs sin 2πt, cos πs), J = 2π² R² sin πs).
//
// The local frame is the luminaire's: length along C0 (x), width along C90 (y), height up (z, the
// side opposite nadir). LM-63 shapes with a height are centred on the photometric centre; an
// EULUMDAT luminous area lies at the centre with its sides rising above it (to the tallest side,
// closed by a top).
#pragma once

#include <array>
#include <vector>

#include "mesh/geometry.h"
#include "solver/photometry/photometric_data.h"

namespace lambert {

struct LuminousFace {
  enum class Kind { kParallelogram, kEllipse, kCylinderSide, kSphere } kind = Kind::kParallelogram;
  Point3 origin;    // parallelogram: a corner; ellipse, sphere: the centre; cylinder: its base centre
  Vector3 u, v;     // parallelogram: its edges; ellipse, cylinder: the semi-axes of the section
  Vector3 axis;     // cylinder: base to top (its length); sphere: the polar radius vector
  double radius = 0;  // sphere
  bool two_sided = false;  // a flat opening radiates from both sides (whichever faces ω)
  // The (s, t) square cut into triangles (s, t, 0) for the rules: a quarter turn of an azimuth per
  // cell at most (an ellipse's t, a cylinder's s, a sphere's t; a sphere's polar s in halves), so
  // that a degree-5 rule integrates cos 2πt over a cell to about 10⁻⁵.
  std::vector<Triangle> cells;

  Point3 point(double s, double t) const;
  Vector3 normal(double s, double t) const;  // unit, outward (the emitting side)
  double jacobian(double s, double t) const;  // dA = J ds dt
  double area() const;
  // The face's part of the opening's projected area toward the unit direction w.
  double projected_area(const Vector3& w) const;
  // How much of the face's area dA at (s, t) shows toward w: |n·w| two-sided, max(0, n·w) else.
  double facing(double s, double t, const Vector3& w) const;
};

// A point of the luminous area with the face and (s, t) it lies at.
struct LuminousSample {
  Point3 point;
  int face = 0;
  double s = 0, t = 0;
};

class LuminousOpening {
 public:
  LuminousOpening() = default;  // a point
  // `dimensions` placed at `centre` with the luminaire's axes (unit, orthonormal): c0 the C0
  // direction, c90 the C90 direction, up = −nadir.
  LuminousOpening(const LuminousDimensions& dimensions, const Point3& centre, const Vector3& c0, const Vector3& c90,
                  const Vector3& up);

  // Whether the opening is modelled as an area (not a point, nor an unsupported shape).
  bool is_area() const { return !faces_.empty(); }
  LuminousShape shape() const { return shape_; }
  const Point3& centre() const { return centre_; }
  const Vector3& length_axis() const { return c0_; }  // C0 direction
  const Vector3& width_axis() const { return c90_; }  // C90 direction
  const Vector3& up() const { return up_; }           // opposite nadir
  double length_m() const { return length_; }
  double width_m() const { return width_; }
  double height_m() const { return height_; }
  const std::vector<LuminousFace>& faces() const { return faces_; }
  double area_m2() const { return area_; }

  // A_proj toward the unit direction w (from the luminaire to the viewer) [m²].
  double projected_area_m2(const Vector3& w) const;
  // The solid angle the opening subtends at `eye` [sr]: exact over its flat faces (an ellipse as a
  // 64-gon), A_proj / d² for curved ones.
  double solid_angle_sr(const Point3& eye) const;
  // <|q − centre|²> over the luminous area [m²], the near-field rule's size (luminaire.h).
  double mean_square_radius_m2() const { return mean_square_radius_; }
  // The largest distance of a luminous point from the centre [m].
  double radius_m() const { return radius_; }
  // 64 stratified points of the luminous area, for shadow rays: sample k lies on face k mod F, in
  // its cell triangle ⌊k/F⌋ (mod their number), at that triangle's k-th stratified point
  // (solver/visible_fraction.h), so that the first 4 already visit every face of a rectangle or disk.
  const std::vector<LuminousSample>& samples() const { return samples_; }

 private:
  void add(LuminousFace f);
  LuminousShape shape_ = LuminousShape::kPoint;
  Point3 centre_;
  Vector3 c0_{1, 0, 0}, c90_{0, 1, 0}, up_{0, 0, 1};
  double length_ = 0, width_ = 0, height_ = 0, area_ = 0, mean_square_radius_ = 0, radius_ = 0;
  std::vector<LuminousFace> faces_;
  std::vector<LuminousSample> samples_;
};

}  // namespace lambert
