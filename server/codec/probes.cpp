// "probes" (SPEC §1, §5): irradiance sensors at one point or on a grid of cell centres, each with the
// quantity it measures (planar by default: the plane facing `normal`; vertical, cylindrical,
// semicylindrical, hemispherical) and the directions that quantity needs.
#include <array>
#include <map>
#include <string_view>
#include <utility>

#include "server/codec/sections.h"

namespace lambert::codec {
namespace {

constexpr long long kMaxProbeGridSide = 10000;
constexpr long long kMaxProbeGridPoints = 1000000;  // memory guard for one grid (24 MB of points)

// The scene's probe points so far (`points`) with `more` added stay within
// limits().max_probe_points; checked before a grid's points are allocated (100 grids of 10⁶ points
// ended in std::bad_alloc). Counts them on success.
bool within_probe_point_limit(Decoder& d, std::size_t& points, std::size_t more, const std::string& p) {
  const std::size_t limit = d.limits().max_probe_points;
  if (limit > 0 && points + more > limit) {
    d.error(p, "the probes would have " + std::to_string(points + more) + " points in all; the limit is " +
                   limit_text(kMaxProbePointsName, limit));
    return false;
  }
  points += more;
  return true;
}

// The points of "grid": {origin, u, v, nu, nv}; false after an error. The grid's shape (zero or
// parallel sides, too many points) is checked only once its members and the probe's normal
// (normal_ok) read well.
bool decode_grid_points(Decoder& d, const json& jg, const std::string& pg, bool normal_ok,
                        std::size_t& points, Probe& probe) {
  if (!d.object(jg, pg, {"origin", "u", "v", "nu", "nv"})) return false;
  const json* jo = d.required(jg, pg, "origin");
  const json* ju = d.required(jg, pg, "u");
  const json* jv = d.required(jg, pg, "v");
  const json* jnu = d.required(jg, pg, "nu");
  const json* jnv = d.required(jg, pg, "nv");
  auto origin = jo ? d.point(*jo, pg + "/origin") : std::nullopt;
  auto u = ju ? d.triple(*ju, pg + "/u", true) : std::nullopt;
  auto v = jv ? d.triple(*jv, pg + "/v", true) : std::nullopt;
  std::optional<long long> nu, nv;
  if (jnu) nu = d.whole(*jnu, pg + "/nu", 1, kMaxProbeGridSide);
  if (jnv) nv = d.whole(*jnv, pg + "/nv", 1, kMaxProbeGridSide);
  if (!origin || !u || !v || !nu || !nv || !normal_ok) return false;
  const auto du = unit_vector(*u), dv = unit_vector(*v);
  if (!du || !dv || length(cross(*du, *dv)) < 1e-9) {
    d.error(pg, !du ? "u must not be the zero vector"
                    : !dv ? "v must not be the zero vector" : "u and v must not be parallel");
    return false;
  }
  if (*nu * *nv > kMaxProbeGridPoints) {
    d.error(pg, "nu × nv = " + std::to_string(*nu * *nv) + " points; at most " +
                    std::to_string(kMaxProbeGridPoints) + " per grid");
    return false;
  }
  if (!within_probe_point_limit(d, points, static_cast<std::size_t>(*nu * *nv), pg)) return false;
  probe.is_grid = true;
  probe.nu = static_cast<int>(*nu);
  probe.nv = static_cast<int>(*nv);
  probe.points.reserve(static_cast<std::size_t>(*nu * *nv));
  // Cell centres, u fastest: origin + (a + 1/2)/nu u + (b + 1/2)/nv v.
  for (long long b = 0; b < *nv; ++b)
    for (long long a = 0; a < *nu; ++a) {
      const Point3 q = *origin + *u * ((a + 0.5) / static_cast<double>(*nu)) +
                       *v * ((b + 0.5) / static_cast<double>(*nv));
      probe.points.push_back(d.metres(q));
    }
  return true;
}

constexpr std::array<std::pair<std::string_view, ProbeQuantity>, 5> kQuantities = {
    {{"planar", ProbeQuantity::Planar},
     {"vertical", ProbeQuantity::Vertical},
     {"cylindrical", ProbeQuantity::Cylindrical},
     {"semicylindrical", ProbeQuantity::Semicylindrical},
     {"hemispherical", ProbeQuantity::Hemispherical}}};

// "quantity" and, for a semicylinder, "facing" (perpendicular to the axis `normal`, within 1e-6 in
// cosine: a direction is not silently projected); false after an error.
bool decode_quantity(Decoder& d, const json& j, const std::string& p, Probe& probe, bool normal_ok) {
  if (const json* jq = d.member(j, "quantity")) {
    const auto name = d.string(*jq, p + "/quantity");
    if (!name) return false;
    bool known = false;
    for (const auto& [word, quantity] : kQuantities)
      if (*name == word) probe.quantity = quantity, known = true;
    if (!known) {
      std::vector<std::string_view> words;
      for (const auto& entry : kQuantities) words.push_back(entry.first);
      d.error(p + "/quantity", "unknown quantity " + quote_text(*name) + " (expected " + join(words, " or ") + ")" +
                                   suggestion(*name, words));
      return false;
    }
  }
  const json* jf = d.member(j, "facing");
  if (probe.quantity != ProbeQuantity::Semicylindrical) {
    if (jf) d.error(p + "/facing", "facing applies to semicylindrical probes only");
    return !jf;
  }
  if (!jf) {
    d.error(p, "a semicylindrical probe needs facing (the direction the half cylinder faces, perpendicular to "
               "normal, its axis)");
    return false;
  }
  const auto f = d.direction(*jf, p + "/facing");
  if (!f || !normal_ok) return false;
  const double c = dot(*f, probe.normal);
  if (std::abs(c) > 1e-6) {
    d.error(p + "/facing", "must be perpendicular to normal (the cylinder's axis); they make " +
                               num(std::acos(std::clamp(c, -1.0, 1.0)) / kDegree) + "°");
    return false;
  }
  probe.facing = *f;
  return true;
}

void decode_probe(Decoder& d, const json& j, std::size_t i,
                  std::map<std::string, std::string>& names, std::size_t& points) {
  const std::string p = index_ptr("/probes", i);
  if (!d.object(j, p, {"name", "position", "grid", "normal", "quantity", "facing", "daylight_factor",
                       "daylight_factor_target_pct", "en17037", "vertical_sky_component"}))
    return;
  Probe probe;
  probe.name = d.unique_name(j, p, "probe" + std::to_string(i), names, "probe");
  bool ok = true;
  if (const json* jn = d.required(j, p, "normal")) {
    auto v = d.direction(*jn, p + "/normal");
    if (v) probe.normal = *v;
    else ok = false;
  } else {
    ok = false;
  }
  if (!decode_quantity(d, j, p, probe, ok)) ok = false;
  const json* jp = d.member(j, "position");
  const json* jg = d.member(j, "grid");
  if (jp && jg) {
    d.error(p, "give position or grid, not both");
    return;
  }
  if (!jp && !jg) {
    d.error(p, "a probe needs position or grid");
    return;
  }
  if (jp) {
    auto q = d.point(*jp, p + "/position");
    if (!q || !ok || !within_probe_point_limit(d, points, 1, p)) return;
    probe.points.push_back(d.metres(*q));
  } else if (!decode_grid_points(d, *jg, p + "/grid", ok, points, probe)) {
    return;
  }
  if (!decode_probe_daylight(d, j, p, probe)) return;
  d.scene().probes.push_back(std::move(probe));
}

}  // namespace

void decode_probes(Decoder& d, const json& doc) {
  const json* probes = d.member(doc, "probes");
  if (!probes || !d.array(*probes, "/probes")) return;
  std::map<std::string, std::string> names;  // name -> pointer of its first use
  std::size_t points = 0;                     // of the probes decoded so far
  for (std::size_t i = 0; i < probes->size(); ++i) decode_probe(d, (*probes)[i], i, names, points);
}

}  // namespace lambert::codec
