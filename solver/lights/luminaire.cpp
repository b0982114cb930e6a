// The luminaire light (luminaire.h): the placed luminaire and its LightModel. Its spectrum is the
// spectral intensity of one candela of the file, scaled (S(λ) = candela_scale · shape(λ) /
// (683 Σ w ȳ shape), as the codec makes it); its geometric factor g is in candela of the file:
//   far (d ≥ d*): g = I_file(ω) cos α / d², shadowed by one ray to the centre; over a patch, the
//     polar integral of I_file over the patch's directions divided by its area;
//   near: the opening's area form (luminaire_near_field.cpp).
#include "solver/lights/luminaire.h"

#include <cmath>
#include <stdexcept>

#include "solver/light_model.h"
#include "solver/receiver.h"
#include "solver/lights/luminaire_near_field.h"
#include "solver/lights/polar_integral.h"
#include "solver/visible_fraction.h"

namespace lambert {

PlacedLuminaire::PlacedLuminaire(const LuminaireLight& light) : light_(light) {
  if (!light_.photometry) throw std::invalid_argument("a luminaire needs its photometry");
  up_ = normalize(-light_.nadir);
  c0_ = normalize(light_.c0 - up_ * dot(light_.c0, up_));
  c90_ = cross(up_, c0_);
  opening_ = LuminousOpening(light_.photometry->file.opening, light_.position, c0_, c90_, up_);
  if (opening_.is_area()) {
    const double spread = 3 + distribution().relative_curvature() + 4 * distribution().relative_slope();
    near_distance_ = std::sqrt(spread * opening_.mean_square_radius_m2() / (2 * kNearFieldTolerance));
  }
}

const PhotometricDistribution& PlacedLuminaire::distribution() const { return light_.photometry->distribution; }

double PlacedLuminaire::luminance_cd_m2(const Vector3& direction) const {
  const double area = opening_.projected_area_m2(direction);
  return area > 0 ? intensity_cd(direction) / area : 0.0;
}

// The outer (azimuth) integral's relative error bound: three orders below the near-field rule's 10⁻³,
// so the patch averages add nothing measurable to the point form's agreement.
constexpr double kThroughTolerance = 1e-6;

double distribution_through(const PlacedLuminaire& l, const Point3& from, const Triangle& t) {
  const PhotometricDistribution& d = l.distribution();
  const PolarFrame frame(l.to_scene(d.zero()), l.to_scene(d.quarter()), l.to_scene(d.polar()));
  return polar_integral(
      from, frame, t.v, [&](double phi, double theta1, double theta2) { return d.band(phi, theta1, theta2); },
      d.theta_max(), d.plane_azimuths(), kThroughTolerance);
}

namespace {

class LuminaireModel final : public LightModel {
 public:
  explicit LuminaireModel(const LuminaireLight& light) : placed_(light) {}

  const std::vector<double>& spectrum() const override { return placed_.light().intensity_W_sr_nm; }

  double unshadowed_factor(const Point3& p, const Vector3& n) const override {
    return near(distance(p, placed_.centre())) ? opening_irradiance(placed_, p, n) : point_form(p, n);
  }

  double point_factor(const Point3& p, const Vector3& n, const Visibility& vis) const override {
    if (near(distance(p, placed_.centre()))) return opening_point_factor(placed_, p, n, vis);
    const double g = point_form(p, n);
    return g != 0 ? g * vis.transmitted(p, placed_.centre()) : 0;
  }

  double patch_factor(const Triangle& t, const Visibility& vis) const override {
    const double nearest = distance(t.centroid(), placed_.centre()) - t.bounding_radius();
    if (near(nearest)) return opening_patch_factor(placed_, t, vis);
    const Vector3 n = t.normal();
    if (dot(placed_.centre() - t.v[0], n) <= 0) return 0;  // the luminaire is behind the patch
    const double average = distribution_through(placed_, placed_.centre(), t) / t.area();
    if (!(average > 0)) return 0;
    return average * weighted_visible_fraction(
                         vis, [&](int k) { return std::pair{visibility_sample(t, k), placed_.centre()}; },
                         [&](const Point3& p, const Point3&) { return point_form(p, n); });
  }

  // A receiver beyond d* sees the point form: g = I_file(ω) w(ω) / d², ω the direction toward the
  // luminaire (solver/receiver.h); nearer, the planar decomposition of the area form (the default).
  double receiver_factor(const Receiver& r, const Visibility& vis) const override {
    if (r.kind == Receiver::Kind::Planar) return point_factor(r.point, r.normal, vis);
    const double dist = distance(r.point, placed_.centre());
    if (near(dist)) return LightModel::receiver_factor(r, vis);
    if (dist == 0) return 0;
    const Vector3 w = (r.point - placed_.centre()) / dist;  // luminaire to receiver
    const double g = placed_.file_intensity_cd(w) * receiver_weight(r, -w) / (dist * dist);
    return g != 0 ? g * vis.transmitted(r.point, placed_.centre()) : 0;
  }

  // Glare (per candela of the file, as S carries the scale): a point luminaire is its intensity
  // toward the eye; an opening is an area of luminance I(ω)/A_proj(ω), ω from the centre to the eye,
  // its solid angle and projected area times the share of its 64 stratified points on faces turned
  // to the eye that the eye sees.
  GlareView glare_view(const Point3& eye, const Visibility& vis) const override {
    const Vector3 d = placed_.centre() - eye;
    const double r = length(d);
    if (r == 0) return {};
    const double I = placed_.file_intensity_cd(-d / r);
    if (!(I > 0)) return {};
    GlareView g;
    g.direction = d / r;
    g.distance_m = r;
    const LuminousOpening& opening = placed_.opening();
    if (!opening.is_area()) {
      if (!vis.visible(eye, placed_.centre())) return {};
      g.kind = GlareView::Kind::Point;
      g.intensity = I;
      return g;
    }
    const double projected = opening.projected_area_m2(-d / r);
    if (!(projected > 0)) return {};
    int facing = 0, seen = 0;
    for (const LuminousSample& q : opening.samples()) {
      const LuminousFace& f = opening.faces()[q.face];
      if (!(f.facing(q.s, q.t, normalize(eye - q.point)) > 0)) continue;
      ++facing;
      seen += vis.visible(eye, q.point);
    }
    if (seen == 0) return {};
    const double share = static_cast<double>(seen) / facing;
    g.kind = GlareView::Kind::Area;
    g.luminance = I / projected;
    g.solid_angle_sr = opening.solid_angle_sr(eye) * share;
    g.projected_area_m2 = projected * share;
    return g;
  }

  // The file's flux [cd sr]: the spectrum carries candela_scale.
  double flux_factor() const override { return placed_.distribution().flux(); }
  std::string_view kind() const override { return "luminaire"; }

 private:
  bool near(double d) const { return d < placed_.near_field_distance_m(); }

  // I_file(ω) cos α / d² from the centre.
  double point_form(const Point3& p, const Vector3& n) const {
    const Vector3 d = p - placed_.centre();
    const double r = length(d);
    if (r == 0) return 0;
    const Vector3 w = d / r;
    const double cos_alpha = -dot(n, w);
    if (cos_alpha <= 0) return 0;
    return placed_.file_intensity_cd(w) * cos_alpha / (r * r);
  }

  PlacedLuminaire placed_;
};

}  // namespace

std::unique_ptr<LightModel> make_luminaire_light(const LuminaireLight& light) {
  return std::make_unique<LuminaireModel>(light);
}

}  // namespace lambert
