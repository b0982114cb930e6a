// The luminaire's area form (luminaire.h): the opening radiates L(ω) = I_file(ω) / A_proj(ω) from each
// point q of its faces toward ω (where the face shows toward ω), so
//   E(p) = Σ_faces ∫ L(ω_qp) f(q, ω_qp) cos α / r² dA_q,   f = |n_q·ω| two-sided, max(0, n_q·ω) else,
// integrated over each face's (s, t) square (luminous_opening.h: dA = J ds dt) by a rule chosen
// from the point form's error at the receiver's distance (rule_for): a symmetric 4-point rule where
// that error is below 1 %, the degree-5 triangle rule far from the opening relative to both sizes,
// and that rule refined where the estimate changes (solver/cubature.h) nearer. Over a receiving patch each
// point q is a point source of intensity L f dA_q, whose flux into the patch is a polar integral over
// the patch's directions, exact in θ where L f is I_file / A (a flat two-sided opening, the common
// case: rectangles, disks); a solid opening's patch average is the degree-5 rule of point values.
// Shadows: kernel-weighted rays from the opening's stratified samples (solver/visible_fraction.h).
#include <cmath>

#include "solver/cubature.h"
#include "solver/lights/luminaire_near_field.h"
#include "solver/visible_fraction.h"

namespace lambert {
namespace {

constexpr double kRelTolerance = 1e-5;  // of the adaptive cubature over the opening
constexpr int kNearFieldDepth = 6;      // 1:4 levels of the (s, t) triangles
constexpr double kFarSeparation = 6;    // beyond this many opening-plus-receiver radii, the fixed rule
// Where the point form errs by at most this (luminaire.h: ε(d) = 10⁻³ (d*/d)²), a flat opening is
// integrated by the symmetric 4-point rule, exact to degree 3 (the Gauss points (±1/√3, ±1/√3) of a
// parallelogram; four points at 1/√2 of the radius of an ellipse): its error is of the order of the
// point form's error squared, 10⁻⁴.
constexpr double kFourPointError = 1e-2;

// The cubature over the opening a receiver at distance d (a patch: its nearest possible point)
// needs, from the point form's error there.
enum class OpeningRule { kFourPoint, kDegree5, kAdaptive };
OpeningRule rule_for(const PlacedLuminaire& l, double d, double receiver_radius) {
  const auto& faces = l.opening().faces();
  const double point_error = kNearFieldTolerance * std::pow(l.near_field_distance_m() / std::max(d, 1e-300), 2);
  if (faces.size() == 1 && faces[0].two_sided && point_error <= kFourPointError) return OpeningRule::kFourPoint;
  const double separation = (d + receiver_radius) / (l.opening().radius_m() + receiver_radius);
  return separation > kFarSeparation ? OpeningRule::kDegree5 : OpeningRule::kAdaptive;
}

// L f toward the unit direction w from point (s, t) of face `face`, per candela of the file [m⁻²].
double emission(const PlacedLuminaire& l, int face, double s, double t, const Vector3& w) {
  const LuminousFace& f = l.opening().faces()[static_cast<std::size_t>(face)];
  const double facing = f.facing(s, t, w);
  if (!(facing > 0)) return 0;
  const double area = l.opening().projected_area_m2(w);
  return area > 0 ? l.file_intensity_cd(w) * facing / area : 0.0;
}

// L f cos α / r² from a luminous point to a receiving point p with unit normal n.
double kernel(const PlacedLuminaire& l, int face, double s, double t, const Point3& q, const Point3& p, const Vector3& n) {
  const Vector3 d = p - q;
  const double r2 = length_squared(d);
  if (!(r2 > 0)) return 0;
  const Vector3 w = d / std::sqrt(r2);
  const double cos_alpha = -dot(n, w);
  return cos_alpha > 0 ? emission(l, face, s, t, w) * cos_alpha / r2 : 0.0;
}

// Σ_faces ∫∫ J(s, t) value(face, s, t, q) ds dt over each face's cells, by `rule`: the adaptive one
// refines until the children agree with their parent within kRelTolerance of the total.
template <class Value>
double over_opening(const PlacedLuminaire& l, OpeningRule how, Value&& value) {
  const auto& faces = l.opening().faces();
  if (how == OpeningRule::kFourPoint) {  // one flat face (rule_for)
    const LuminousFace& f = faces[0];
    const double g = 0.5 / std::sqrt(3.0), r = 1 / std::sqrt(2.0);
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      const double s = f.kind == LuminousFace::Kind::kEllipse ? r : 0.5 + (k % 2 ? g : -g);
      const double t = f.kind == LuminousFace::Kind::kEllipse ? 0.25 * k : 0.5 + (k / 2 ? g : -g);
      sum += value(0, s, t, f.point(s, t));
    }
    return 0.25 * f.area() * sum;
  }
  const TriangleRule rule = triangle_rule_degree5();
  thread_local std::vector<double> coarse;
  coarse.clear();
  double total = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    auto integrand = [&](const Point3& st) {
      return faces[f].jacobian(st.x, st.y) * value(static_cast<int>(f), st.x, st.y, faces[f].point(st.x, st.y));
    };
    for (const Triangle& cell : faces[f].cells) total += coarse.emplace_back(apply_rule(rule, cell, integrand));
  }
  if (how == OpeningRule::kDegree5 || total == 0) return total;
  const double tolerance = kRelTolerance * std::abs(total) / static_cast<double>(coarse.size());
  double fine = 0;
  std::size_t c = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    auto integrand = [&](const Point3& st) {
      return faces[f].jacobian(st.x, st.y) * value(static_cast<int>(f), st.x, st.y, faces[f].point(st.x, st.y));
    };
    for (const Triangle& cell : faces[f].cells)
      fine += integrate_adaptive(cell, integrand, coarse[c++], tolerance, kNearFieldDepth);
  }
  return fine;
}

}  // namespace

double opening_irradiance(const PlacedLuminaire& l, const Point3& p, const Vector3& n) {
  return over_opening(l, rule_for(l, distance(p, l.centre()), 0), [&](int face, double s, double t, const Point3& q) {
    return kernel(l, face, s, t, q, p, n);
  });
}

double opening_point_factor(const PlacedLuminaire& l, const Point3& p, const Vector3& n, const Visibility& vis) {
  const double g = opening_irradiance(l, p, n);
  if (g == 0) return 0;
  const auto& samples = l.opening().samples();
  const LuminousSample* current = nullptr;  // the sample whose ray is being weighed (set by endpoints)
  return g * weighted_visible_fraction(
                 vis,
                 [&](int k) {
                   current = &samples[static_cast<std::size_t>(k)];
                   return std::pair{current->point, p};
                 },
                 [&](const Point3& q, const Point3& to) { return kernel(l, current->face, current->s, current->t, q, to, n); });
}

double opening_patch_factor(const PlacedLuminaire& l, const Triangle& t, const Visibility& vis) {
  const Vector3 nt = t.normal();
  const auto& faces = l.opening().faces();
  const double nearest = distance(t.centroid(), l.centre()) - t.bounding_radius();
  double average = 0;
  if (faces.size() == 1 && faces[0].two_sided) {
    // L f = I_file / A in every direction: each luminous point's flux into t is exact in angle.
    const double flat_area = l.opening().area_m2();
    auto flux_from = [&](int, double, double, const Point3& q) {
      return dot(q - t.v[0], nt) > 0 ? distribution_through(l, q, t) / flat_area : 0.0;  // q in front of t
    };
    average = over_opening(l, rule_for(l, nearest, t.bounding_radius()), flux_from) / t.area();
  } else {
    // Solid openings (boxes, cylinders, spheres): L f depends on the face and direction, so the angle
    // integral has no closed form; the patch average is the degree-5 rule over t of the area form's
    // irradiance, each point's opening cubature chosen by its own distance.
    average = apply_rule(triangle_rule_degree5(), t, [&](const Point3& p) { return opening_irradiance(l, p, nt); }) /
              t.area();
  }
  if (!(average > 0)) return 0;
  const auto& samples = l.opening().samples();
  const LuminousSample* current = nullptr;
  return average *
         weighted_visible_fraction(
             vis,
             [&](int k) {
               current = &samples[static_cast<std::size_t>(k)];
               return std::pair{current->point, visibility_sample(t, paired_sample(k))};
             },
             [&](const Point3& q, const Point3& p) { return kernel(l, current->face, current->s, current->t, q, p, nt); });
}

}  // namespace lambert
