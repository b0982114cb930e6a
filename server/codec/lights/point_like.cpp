// Point-like sources (SPEC §1 "Light models"): I(ψ) = I_0 cos^m ψ about the axis, seen from a
// position. "point" is isotropic (m = 0, no axis), "goniometric" a cos^m lobe, "spot" a cos^m lobe
// cut off at cutoff_deg, "warn" Warn's cos^1 lobe. Each may carry an attenuation polynomial and
// one intensity or flux total.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "server/codec/lights/light_types.h"
#include "server/codec/spectra.h"

namespace lambert::codec {
namespace {

// The keys of this kind (besides the totals); sets the fixed exponent of a Warn light.
Keys keys_of(PointLight& light, std::string_view type) {
  Keys keys = {"type", "position", "intensity", "attenuation"};
  if (type == "point") {
    light.kind = PointLight::Kind::Point;
    return keys;
  }
  keys.push_back("axis");
  if (type == "goniometric") {
    light.kind = PointLight::Kind::Goniometric;
    keys.push_back("exponent");
  } else if (type == "spot") {
    light.kind = PointLight::Kind::Spot;
    keys.push_back("exponent");
    keys.push_back("cutoff_deg");
  } else {
    light.kind = PointLight::Kind::Warn;
    light.exponent = 1;  // Warn's model is the cos^1 lobe
  }
  return keys;
}

// position, axis, exponent (required for goniometric, optional for spot) and cutoff_deg.
bool read_lobe(Decoder& d, const json& j, const std::string& p, PointLight& light) {
  bool ok = true;
  if (const json* jp = d.required(j, p, "position")) {
    if (auto q = d.point(*jp, p + "/position"))
      light.position = d.metres(*q);
    else ok = false;
  } else {
    ok = false;
  }
  if (light.kind != PointLight::Kind::Point) {
    const json* ja = d.required(j, p, "axis");
    auto a = ja ? d.direction(*ja, p + "/axis") : std::nullopt;
    if (a) light.axis = *a;
    else ok = false;
  }
  if (light.kind == PointLight::Kind::Goniometric || light.kind == PointLight::Kind::Spot) {
    const json* je = light.kind == PointLight::Kind::Spot ? d.member(j, "exponent")
                                                          : d.required(j, p, "exponent");
    if (je) {
      auto m = d.number_in(*je, p + "/exponent", 0, true, kMaxLobeExponent, true);
      if (m) light.exponent = *m;
      else ok = false;
    } else if (light.kind == PointLight::Kind::Goniometric) {
      ok = false;
    }
  }
  if (light.kind == PointLight::Kind::Spot) {
    const json* jc = d.required(j, p, "cutoff_deg");
    auto c = jc ? d.number_in(*jc, p + "/cutoff_deg", 0, false, 180, true) : std::nullopt;
    if (c) light.cutoff_rad = *c == 180 ? kPi : *c * kDegree;
    else ok = false;
  }
  return ok;
}

// "attenuation": "inverse_square" or {"c1", "c2", "c3"}; false after an error.
bool read_attenuation(Decoder& d, const json& att, const std::string& pa, PointLight& light) {
  if (att.is_string()) {
    if (att.get<std::string>() == "inverse_square") return true;
    d.error(pa, "unknown attenuation " + quote_text(att.get<std::string>()) +
                    "; expected \"inverse_square\" or {\"c1\", \"c2\", \"c3\"}");
    return false;
  }
  if (!d.object(att, pa, {"c1", "c2", "c3"})) return false;
  // E = I cos α / (c1 + c2 r + c3 r²) with r in METRES, whatever the scene's units: the
  // coefficients are taken as given (c2 per metre, c3 per square metre), not converted.
  bool ok = true;
  std::array<double, 3> c{0, 0, 0};
  const std::array<std::string_view, 3> names = {"c1", "c2", "c3"};
  for (std::size_t k = 0; k < 3; ++k)
    if (const json* v = d.member(att, names[k])) {
      auto x = d.number_in(*v, key_ptr(pa, names[k]), 0, true, INFINITY, false);
      if (x) c[k] = *x;
      else ok = false;
    }
  if (c[0] == 0 && c[1] == 0 && c[2] == 0) {
    d.error(pa, "c1, c2 and c3 must not all be zero");
    ok = false;
  }
  light.attenuation = {c[0], c[1], c[2]};
  light.inverse_square = false;
  return ok;
}

// Flux = I_0 × Ω_eff, Ω_eff = ∫ cos^m ψ dω over the lit directions.
double effective_solid_angle(const PointLight& light) {
  const double m = light.exponent;
  switch (light.kind) {
    case PointLight::Kind::Point: return 4 * kPi;
    case PointLight::Kind::Goniometric:
    case PointLight::Kind::Warn: return 2 * kPi / (m + 1);
    case PointLight::Kind::Spot: {
      // cos^m with m > 0 is zero beyond 90°; an m = 0 spot is a uniform cone up to its cutoff.
      const double psi = m > 0 ? std::min(light.cutoff_rad, kPi / 2) : light.cutoff_rad;
      return 2 * kPi * (1 - std::pow(std::cos(psi), m + 1)) / (m + 1);
    }
  }
  return 1;
}

}  // namespace

void decode_point_like_light(Decoder& d, const json& j, const std::string& p,
                             std::string_view type) {
  PointLight light;
  d.unknown_keys(j, p, with_totals(keys_of(light, type)));
  bool ok = read_lobe(d, j, p, light);
  if (const json* att = d.member(j, "attenuation"))
    if (!read_attenuation(d, *att, p + "/attenuation", light)) ok = false;
  std::optional<std::vector<double>> I;
  if (const json* ji = d.required(j, p, "intensity"))
    I = spectrum(d, *ji, p + "/intensity", SpectrumRole::Emission);
  static const std::map<PointLight::Kind, std::string_view> kDescription = {
      {PointLight::Kind::Point, "a point light"},
      {PointLight::Kind::Goniometric, "a goniometric light"},
      {PointLight::Kind::Spot, "a spot light"},
      {PointLight::Kind::Warn, "a Warn light"}};
  const auto t = total(d, j, p,
                       {"luminous_intensity_cd", "radiant_intensity_W_sr", "luminous_flux_lm",
                        "radiant_flux_W"},
                       kDescription.at(light.kind));
  if (!ok || !I) return;
  if (t) {
    const bool flux = is_one_of(t->key, {"luminous_flux_lm", "radiant_flux_W"});
    const double G = flux ? effective_solid_angle(light) : 1;
    if (!scale_to_total(d, *I, *t, G, p + "/intensity")) return;
  }
  light.intensity_W_sr_nm = std::move(*I);
  d.add_light(std::move(light), p);
}

}  // namespace lambert::codec
