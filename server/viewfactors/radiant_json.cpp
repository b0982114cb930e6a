#include "server/viewfactors/radiant_json.h"

#include <cmath>
#include <map>

#include "server/codec/document.h"
#include "server/codec/thermal.h"
#include "server/scene_limits.h"
#include "solver/thermal/radiant_temperature.h"

namespace lambert {
namespace {

using nlohmann::json;

json matrix_json(const std::vector<double>& F, std::size_t S) {
  json rows = json::array();
  for (std::size_t I = 0; I < S; ++I) rows.push_back(std::vector<double>(F.begin() + I * S, F.begin() + (I + 1) * S));
  return rows;
}

json point_json(const Point3& p, double unit_m) { return json::array({p.x / unit_m, p.y / unit_m, p.z / unit_m}); }

json values_json(const ThermalValues& v) {
  json j = {{"net_flux_W_m2", v.net_flux_W_m2},
            {"net_W", v.net_W},
            {"radiosity_W_m2", v.radiosity_W_m2},
            {"irradiance_W_m2", v.irradiance_W_m2}};
  if (v.temperature_K) j["temperature_K"] = *v.temperature_K;
  return j;
}

json surfaces_json(const ViewFactorMatrix& m, const GreyExchange& g) {
  json surfaces = json::array();
  for (std::size_t I = 0; I < m.size(); ++I)
    surfaces.push_back({{"name", m.names[I]}, {"area", m.area_m2[I]}, {"thermal", values_json(g.surfaces[I])}});
  return surfaces;
}

json probes_json(const Scene& scene, const GreyExchange& g) {
  json probes = json::array();
  for (std::size_t k = 0; k < scene.probes.size() && k < g.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    const std::vector<RadiantPoint>& points = g.probes[k];
    json j = {{"name", probe.name}};
    const bool plane = has_plane_radiant_temperature(probe);
    if (!probe.is_grid && points.size() == 1) {
      j["position"] = point_json(probe.points[0], scene.unit_m);
      j["mean_radiant_temperature_K"] = points[0].mean_radiant_temperature_K;
      if (plane) j["plane_radiant_temperature_K"] = points[0].plane_radiant_temperature_K;
      j["view_factors"] = points[0].view_factors;
    } else {
      json positions = json::array(), mrt = json::array(), prt = json::array(), factors = json::array();
      for (std::size_t q = 0; q < points.size(); ++q) {
        positions.push_back(point_json(probe.points[q], scene.unit_m));
        mrt.push_back(points[q].mean_radiant_temperature_K);
        prt.push_back(points[q].plane_radiant_temperature_K);
        factors.push_back(points[q].view_factors);
      }
      j["nu"] = probe.nu;
      j["nv"] = probe.nv;
      j["points"] = std::move(positions);
      j["mean_radiant_temperature_K"] = std::move(mrt);
      if (plane) j["plane_radiant_temperature_K"] = std::move(prt);
      j["view_factors"] = std::move(factors);
    }
    probes.push_back(std::move(j));
  }
  return probes;
}

}  // namespace

json view_factors_json(const ViewFactorMatrix& m, const std::string& geometry_hash,
                       const std::vector<std::optional<double>>& emissivity) {
  const std::size_t S = m.size();
  json surfaces = json::array();
  for (std::size_t I = 0; I < S; ++I) {
    json s = {{"name", m.names[I]}, {"area", m.area_m2[I]}};
    if (I < emissivity.size() && emissivity[I]) s["emissivity"] = *emissivity[I];
    surfaces.push_back(std::move(s));
  }
  json j = {{"surfaces", std::move(surfaces)},
            {"F", matrix_json(m.F, S)},
            {"row_sums", m.row_sums},
            {"reciprocity_residual", m.reciprocity_residual},
            {"geometry_hash", geometry_hash}};
  if (!m.to_occluders.empty()) j["to_occluders"] = m.to_occluders;
  return j;
}

json view_factors_json(const RadiantExchange& r, double unit_m, const std::vector<std::optional<double>>& emissivity) {
  const ViewFactorMatrix& m = r.factors;
  const std::size_t S = m.size();
  json j = view_factors_json(m, r.geometry_hash, emissivity);
  if (!r.total_exchange.empty()) j["total_exchange_factors"] = matrix_json(r.total_exchange, S);
  if (r.patch_factors) {
    json patches = json::array();
    for (std::size_t i = 0; i < r.patches.size(); ++i) {
      const Patch& p = r.patches[i];
      const int g = r.patch_group[i];
      patches.push_back({{"id", i},
                         {"surface", g >= 0 ? json(m.names[g]) : json(nullptr)},
                         {"vertices", json::array({point_json(p.triangle.v[0], unit_m), point_json(p.triangle.v[1], unit_m),
                                                   point_json(p.triangle.v[2], unit_m)})},
                         {"area", p.area_m2}});
    }
    j["patches"] = std::move(patches);
    j["patch_factors"] = {{"i", r.patch_factors->i}, {"j", r.patch_factors->j}, {"F", r.patch_factors->F}};
  }
  const SolveStats& st = r.stats;
  j["stats"] = {{"patches", st.patches},
                {"links", st.links},
                {"link_rays", st.link_rays},
                {"closure_max_error", st.max_closure_error},
                {"closure_residual", st.closure_residual},
                {"reciprocity_max_error", st.max_reciprocity_error},
                {"time_s",
                 {{"meshing", st.time_meshing_s},
                  {"visibility", st.time_visibility_s},
                  {"form_factors", st.time_form_factors_s},
                  {"total", st.time_total_s}}}};
  return j;
}

json thermal_json(const Scene& scene, const RadiantExchange& r) {
  const GreyExchange& g = r.thermal.value();
  json patches = json::array();
  for (std::size_t i = 0; i < r.patches.size(); ++i) {
    const Patch& p = r.patches[i];
    patches.push_back({{"id", i},
                       {"surface", scene.surfaces[p.surface].name},
                       {"vertices", json::array({point_json(p.triangle.v[0], scene.unit_m),
                                                 point_json(p.triangle.v[1], scene.unit_m),
                                                 point_json(p.triangle.v[2], scene.unit_m)})},
                       {"area", p.area_m2},
                       {"thermal", values_json(g.patches[i])}});
  }
  return {{"level", "patches"},
          {"geometry_hash", r.geometry_hash},
          {"surfaces", surfaces_json(r.factors, g)},
          {"patches", std::move(patches)},
          {"probes", probes_json(scene, g)},
          {"balance", {{"net_W", g.net_sum_W}, {"occluders_net_W", g.occluders_net_W}}},
          {"iterations", g.iterations},
          {"residual", g.residual}};
}

json thermal_json(const ViewFactorMatrix& m, const GreyExchange& g, const std::string& geometry_hash) {
  return {{"level", "surfaces"},
          {"geometry_hash", geometry_hash},
          {"surfaces", surfaces_json(m, g)},
          {"balance", {{"net_W", g.net_sum_W}, {"occluders_net_W", g.occluders_net_W}}},
          {"iterations", g.iterations},
          {"residual", g.residual}};
}

namespace {

// A finite number at `at`, or an error.
std::optional<double> finite(const json& j, const std::string& at, std::vector<std::string>& errors) {
  if (j.is_number() && std::isfinite(j.get<double>())) return j.get<double>();
  errors.push_back(at + ": expected a finite number");
  return std::nullopt;
}

}  // namespace

std::optional<SavedFactors> read_saved_factors(const json& document, std::vector<std::string>& errors) {
  const bool nested = document.is_object() && document.contains("view_factors");
  const json& doc = nested ? document["view_factors"] : document;
  const std::string base = nested ? "/view_factors" : "";
  if (!doc.is_object() || !doc.contains("F")) return std::nullopt;
  SavedFactors out;
  const json& surfaces = doc.contains("surfaces") ? doc["surfaces"] : json();
  const json& F = doc["F"];
  if (!surfaces.is_array() || surfaces.empty()) errors.push_back(base + "/surfaces: expected an array of surfaces");
  if (!F.is_array() || F.size() != surfaces.size()) errors.push_back(base + "/F: expected one row per surface");
  if (!errors.empty()) return std::nullopt;
  const std::size_t S = surfaces.size();
  ViewFactorMatrix& m = out.matrix;
  for (std::size_t I = 0; I < S; ++I) {
    const std::string at = base + "/surfaces/" + std::to_string(I);
    const json& s = surfaces[I];
    if (!s.is_object() || !s.contains("name") || !s["name"].is_string() || !s.contains("area")) {
      errors.push_back(at + ": expected {\"name\": text, \"area\": m²}");
      continue;
    }
    m.names.push_back(s["name"].get<std::string>());
    const auto area = finite(s["area"], at + "/area", errors);
    if (area && !(*area > 0)) errors.push_back(at + "/area: must be > 0");
    m.area_m2.push_back(area.value_or(0));
    std::optional<double> eps;
    if (s.contains("emissivity")) eps = finite(s["emissivity"], at + "/emissivity", errors);
    out.emissivity.push_back(eps);
  }
  m.F.assign(S * S, 0.0);
  for (std::size_t I = 0; I < S; ++I) {
    const std::string at = base + "/F/" + std::to_string(I);
    if (!F[I].is_array() || F[I].size() != S) {
      errors.push_back(at + ": expected " + std::to_string(S) + " factors");
      continue;
    }
    for (std::size_t J = 0; J < S; ++J)
      if (const auto v = finite(F[I][J], at + "/" + std::to_string(J), errors)) {
        if (*v < 0 || *v > 1 + 1e-9) errors.push_back(at + "/" + std::to_string(J) + ": a view factor is in [0, 1]");
        m.F[I * S + J] = *v;
      }
  }
  if (doc.contains("geometry_hash") && doc["geometry_hash"].is_string())
    out.geometry_hash = doc["geometry_hash"].get<std::string>();
  if (!errors.empty()) return std::nullopt;
  measure_view_factors(m);
  return out;
}

std::optional<ThermalFile> read_thermal_file(const std::string& text, const std::vector<std::string>& names,
                                             const std::vector<std::optional<double>>& emissivity,
                                             std::vector<std::string>& errors) {
  codec::ParsedDocument parsed = codec::parse_document(text);
  std::vector<DecodeError> found = std::move(parsed.fatal);
  ThermalFile out;
  if (found.empty()) {
    codec::Decoder d(FileAccess{}, SceneLimits{}, std::move(parsed.duplicate_keys), parsed.omitted_duplicate_keys);
    const json& doc = parsed.doc;
    const json* surfaces = nullptr;
    if (d.object(doc, "", {"geometry_hash", "surfaces"})) {
      if (const json* h = d.member(doc, "geometry_hash")) out.geometry_hash = d.string(*h, "/geometry_hash");
      surfaces = d.required(doc, "", "surfaces");
      if (surfaces && !surfaces->is_object()) {
        d.error("/surfaces", "expected an object with an entry per surface name, got " + codec::a_type(*surfaces));
        surfaces = nullptr;
      }
    }
    std::map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < names.size(); ++k) index.emplace(names[k], k);
    out.by_name.resize(names.size());
    std::vector<char> given(names.size(), 0);
    for (auto it = surfaces ? surfaces->begin() : json::const_iterator(); surfaces && it != surfaces->end(); ++it) {
      const std::string p = codec::key_ptr("/surfaces", it.key());
      const auto at = index.find(it.key());
      if (at == index.end()) {
        d.error(p, "no surface is named " + codec::quote_text(it.key()) + codec::suggestion(it.key(), names));
        continue;
      }
      const std::size_t k = at->second;
      if (auto t = codec::decode_thermal(d, it.value(), p, k < emissivity.size() ? emissivity[k] : std::nullopt))
        out.by_name[k] = *t, given[k] = 1;
    }
    for (std::size_t k = 0; surfaces && k < names.size(); ++k)
      if (!given[k] && !surfaces->contains(names[k]))
        d.error("/surfaces", "no entry for surface " + codec::quote_text(names[k]) +
                                 " (every surface needs its temperature or net flux)");
    found = d.finish().errors;
  }
  for (const DecodeError& e : found) errors.push_back((e.pointer.empty() ? "(document)" : e.pointer) + ": " + e.message);
  if (!errors.empty()) return std::nullopt;
  return out;
}

}  // namespace lambert
