// Reading a result document (result_model.h). nlohmann_json is confined to the codecs; this is the
// result's reading codec.
#include "server/export/result_model.h"

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "solver/spectrum.h"

namespace lambert {
namespace {

using json = nlohmann::json;

[[noreturn]] void fail(const std::string& pointer, const std::string& what) {
  throw std::invalid_argument(pointer.empty() ? what : pointer + ": " + what);
}

const json& member(const json& object, const std::string& key, const std::string& where) {
  if (!object.is_object() || !object.contains(key)) fail(where, "expected \"" + key + "\"");
  return object[key];
}

double number(const json& v, const std::string& where) {
  if (!v.is_number()) fail(where, "expected a number");
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(where, "expected a finite number");
  return x;
}

Point3 point(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 3) fail(where, "expected a point [x, y, z]");
  return {number(v[0], where + "/0"), number(v[1], where + "/1"), number(v[2], where + "/2")};
}

std::array<double, 3> triple(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 3) fail(where, "expected three numbers");
  return {number(v[0], where + "/0"), number(v[1], where + "/1"), number(v[2], where + "/2")};
}

ResultPatch read_patch(const json& p, const std::string& where, std::map<std::string, int>& surface_index,
                       std::vector<std::string>& surfaces) {
  if (!p.is_object()) fail(where, "expected a patch object");
  ResultPatch out;
  const json& v = member(p, "vertices", where);
  if (!v.is_array() || v.size() != 3) fail(where + "/vertices", "expected three points");
  for (int k = 0; k < 3; ++k) out.triangle.v[k] = point(v[k], where + "/vertices/" + std::to_string(k));
  out.area_m2 = number(member(p, "area", where), where + "/area");
  out.illuminance_lx = number(member(p, "illuminance_lx", where), where + "/illuminance_lx");
  out.luminance_cd_m2 = number(member(p, "luminance_cd_m2", where), where + "/luminance_cd_m2");
  out.srgb = triple(member(p, "srgb", where), where + "/srgb");
  const json& s = member(p, "surface", where);
  if (!s.is_string()) fail(where + "/surface", "expected a surface name");
  const auto [it, added] = surface_index.try_emplace(s.get<std::string>(), static_cast<int>(surfaces.size()));
  if (added) surfaces.push_back(it->first);
  out.surface = it->second;
  return out;
}

// srgb_encoded = encode(srgb / white) (solver/report.cpp): a channel strictly inside (0, 1) gives the
// white back; near 0 or 1 the curve's slope or the clamp would make it inexact.
std::optional<double> white_from_encoded(const json& p, const ResultPatch& patch) {
  if (!p.contains("srgb_encoded") || !p["srgb_encoded"].is_array() || p["srgb_encoded"].size() != 3) return std::nullopt;
  for (int c = 0; c < 3; ++c) {
    const json& e = p["srgb_encoded"][c];
    if (!e.is_number() || !(patch.srgb[c] > 0)) continue;
    const double encoded = e.get<double>();
    if (encoded > 0.05 && encoded < 0.95) return patch.srgb[c] / srgb_decode(encoded);
  }
  return std::nullopt;
}

ResultProbe read_probe(const json& p, const std::string& where) {
  if (!p.is_object()) fail(where, "expected a probe object");
  ResultProbe out;
  const json& name = member(p, "name", where);
  if (!name.is_string()) fail(where + "/name", "expected a string");
  out.name = name.get<std::string>();
  if (p.contains("quantity")) {  // results written before probes had quantities are planar
    if (!p["quantity"].is_string()) fail(where + "/quantity", "expected a string");
    out.quantity = p["quantity"].get<std::string>();
  }
  if (p.contains("position")) {
    out.points.push_back(point(p["position"], where + "/position"));
    out.illuminance_lx.push_back(number(member(p, "illuminance_lx", where), where + "/illuminance_lx"));
    return out;
  }
  out.is_grid = true;
  const json& nu = member(p, "nu", where);
  const json& nv = member(p, "nv", where);
  if (!nu.is_number_integer() || nu.get<long long>() < 1) fail(where + "/nu", "expected a positive integer");
  if (!nv.is_number_integer() || nv.get<long long>() < 1) fail(where + "/nv", "expected a positive integer");
  out.nu = nu.get<int>();
  out.nv = nv.get<int>();
  const json& points = member(p, "points", where);
  const json& lux = member(p, "illuminance_lx", where);
  const std::size_t n = static_cast<std::size_t>(out.nu) * static_cast<std::size_t>(out.nv);
  if (!points.is_array() || points.size() != n) fail(where + "/points", "expected nu × nv = " + std::to_string(n) + " points");
  if (!lux.is_array() || lux.size() != n) fail(where + "/illuminance_lx", "expected nu × nv = " + std::to_string(n) + " numbers");
  for (std::size_t q = 0; q < n; ++q) {
    out.points.push_back(point(points[q], where + "/points/" + std::to_string(q)));
    out.illuminance_lx.push_back(number(lux[q], where + "/illuminance_lx/" + std::to_string(q)));
  }
  return out;
}

// √(Σ area_m2 / Σ area in scene units²), snapped to the scene unit it rounds from.
double unit_from_areas(const std::vector<ResultPatch>& patches) {
  double m2 = 0, units2 = 0;
  for (const ResultPatch& p : patches) m2 += p.area_m2, units2 += p.triangle.area();
  if (!(m2 > 0) || !(units2 > 0)) return 1;
  const double unit = std::sqrt(m2 / units2);
  for (double scene_unit : {1.0, 0.01, 0.001})
    if (std::abs(unit / scene_unit - 1) < 1e-6) return scene_unit;
  return unit;
}

}  // namespace

ResultModel read_result(const std::string& result_json) {
  const json doc = json::parse(result_json, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) fail("", "not a result (a JSON object with \"patches\")");
  ResultModel model;
  if (doc.contains("name") && doc["name"].is_string()) model.name = doc["name"].get<std::string>();
  const json& patches = member(doc, "patches", "");
  if (!patches.is_array() || patches.empty()) fail("/patches", "expected a non-empty array");
  std::map<std::string, int> surface_index;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const std::string where = "/patches/" + std::to_string(i);
    model.patches.push_back(read_patch(patches[i], where, surface_index, model.surfaces));
    if (!model.white_cd_m2) model.white_cd_m2 = white_from_encoded(patches[i], model.patches.back());
  }
  if (doc.contains("probes")) {
    const json& probes = doc["probes"];
    if (!probes.is_array()) fail("/probes", "expected an array");
    for (std::size_t k = 0; k < probes.size(); ++k) model.probes.push_back(read_probe(probes[k], "/probes/" + std::to_string(k)));
  }
  model.unit_m = unit_from_areas(model.patches);
  return model;
}

double display_white(const ResultModel& model, std::optional<double> requested) {
  if (requested && *requested > 0) return *requested;
  if (model.white_cd_m2 && *model.white_cd_m2 > 0) return *model.white_cd_m2;
  double white = 0;
  for (const ResultPatch& p : model.patches) white = std::max(white, p.luminance_cd_m2);
  return white > 0 ? white : 1;
}

}  // namespace lambert
