// Result JSON per SPEC §2. Numbers that could be non-finite never reach here (the solver throws
// instead), so nlohmann's "NaN becomes null" behaviour (STACK.md P10) cannot lose information.
#include "server/result_codec.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <nlohmann/json.hpp>

#include "server/evaluation_codec.h"
#include "server/ugr_table_codec.h"
#include "server/viewfactors/radiant_json.h"
#include "solver/lights/luminaire.h"
#include "solver/rgb_model.h"

namespace lambert {
namespace {

using nlohmann::json;

json point_json(const Point3& p, double unit_m) { return json::array({p.x / unit_m, p.y / unit_m, p.z / unit_m}); }

json spectrum_json(const double* values, std::size_t W, double scale = 1.0) {
  json a = json::array();
  for (std::size_t w = 0; w < W; ++w) a.push_back(values[w] * scale);
  return a;
}

template <std::size_t K>
json array_json(const std::array<double, K>& v) {
  json a = json::array();
  for (double x : v) a.push_back(x);
  return a;
}

json optional_json(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// Per luminaire (SPEC §2 "luminaires"): what the file declares against the exact integral of the
// interpolated distribution, and what the scene makes it emit.
json luminaires_json(const Scene& scene) {
  json out = json::array();
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const auto* m = std::get_if<LuminaireLight>(&scene.lights[l]);
    if (!m) continue;
    const PhotometricData& f = m->photometry->file;
    const PlacedLuminaire placed(*m);
    const double integral = m->photometry->distribution.flux();
    json j = {{"light", l < scene.light_pointers.size() ? scene.light_pointers[l] : "/lights/" + std::to_string(l)},
              {"name", m->name},
              {"file", m->source},
              {"format", f.format == PhotometricFormat::kIes ? "IES " + f.version : f.version},
              {"photometry_type", photometry_type_name(f.type)},
              {"absolute_photometry", f.absolute_photometry},
              {"declared_lamp_flux_lm", optional_json(f.declared_lamp_flux_lm)},
              {"declared_output_lm", optional_json(f.declared_output_lm)},
              {"integral_lm", integral},
              {"light_output_ratio", f.declared_lamp_flux_lm ? json(integral / *f.declared_lamp_flux_lm) : json(nullptr)},
              {"tilt_factor", m->tilt_factor},
              {"maintenance_factor", m->maintenance_factor},
              {"emitted_lm", placed.flux_lm()},
              {"input_watts", f.input_watts},
              {"luminous_opening",
               {{"shape", luminous_shape_name(f.opening.shape)},
                {"description", f.opening.description},
                {"length_m", f.opening.length_m},
                {"width_m", f.opening.width_m},
                {"height_m", f.opening.height_m}}},
              {"near_field_distance_m", placed.near_field_distance_m()}};
    // The catalogue table is for the luminaire as new: the rescale and tilt factor, not maintenance.
    if (scene.output.ugr_tables)
      j["ugr_table"] = ugr_table_json(standard_ugr_table(f, m->photometry->distribution,
                                                         m->candela_scale / m->maintenance_factor));
    out.push_back(std::move(j));
  }
  return out;
}

// One element of "patches". Patches are written one at a time (write_result): with the whole result
// held as a document, writing 984 320 patches (836 MB of text) peaked at 4.8 GB; streamed, 1.55 GB.
json patch_json(const Scene& scene, const Solution& sol, const Report& report, std::size_t i) {
  const std::size_t W = sol.wavelengths();
  const bool spectral = scene.output.spectral;
  const Patch& p = sol.patches[i];
  const PatchPhotometry& ph = report.patches[i];
  json j;
  j["id"] = i;
  j["surface"] = scene.surfaces[p.surface].name;
  j["vertices"] = json::array({point_json(p.triangle.v[0], scene.unit_m), point_json(p.triangle.v[1], scene.unit_m),
                               point_json(p.triangle.v[2], scene.unit_m)});
  j["area"] = p.area_m2;
  j["normal"] = json::array({p.normal.x, p.normal.y, p.normal.z});
  if (spectral) {
    j["radiosity"] = spectrum_json(&sol.radiosity[i * W], W);
    j["irradiance"] = spectrum_json(&sol.irradiance[i * W], W);
    j["radiance"] = spectrum_json(&sol.radiosity[i * W], W, 1 / kPi);
  }
  j["illuminance_lx"] = ph.illuminance_lx;
  j["luminance_cd_m2"] = ph.luminance_cd_m2;
  j["xyz"] = json::array({ph.xyz.X, ph.xyz.Y, ph.xyz.Z});
  j["xy"] = array_json(ph.xy);
  j["rgb_ebu"] = array_json(ph.rgb_ebu);
  j["srgb"] = array_json(ph.srgb);
  j["srgb_encoded"] = array_json(ph.srgb_encoded);
  if (ph.melanopic) {
    j["melanopic_irradiance_W_m2"] = ph.melanopic->irradiance_W_m2;
    j["melanopic_edi_lx"] = ph.melanopic->edi_lx;
  }
  return j;
}

// The method's own stats (SPEC §5), beside the common ones.
json method_stats(const SolveStats& st) {
  if (st.method == SolverMethod::Dense)
    return {{"adaptive_rounds", st.dense.adaptive_rounds}, {"link_ray_thread_s", st.dense.link_ray_thread_s}};
  const SolveStats::Hierarchical& h = st.hierarchical;
  return {{"element_links", h.element_links}, {"cluster_links", h.cluster_links},
          {"leaf_links", h.leaf_links},       {"leaf_links_traced", h.leaf_links_traced},
          {"leaf_links_exact", h.leaf_links_exact}, {"crowded_links", h.crowded_links},
          {"refine_rounds", h.refine_rounds}};
}

const char* en17037_level_name(En17037Request::Level level) {
  switch (level) {
    case En17037Request::Level::kMinimum: return "minimum";
    case En17037Request::Level::kMedium: return "medium";
    case En17037Request::Level::kHigh: return "high";
  }
  return "minimum";
}

// The skies and suns of "daylight" (SPEC §5 "Daylight").
json daylight_json(const Scene& scene, const DaylightReport& daylight) {
  const std::size_t W = scene.grid.size();
  json skies = json::array(), suns = json::array();
  for (const SkyReport& sky : daylight.skies) {
    json j = {{"source", scene.light_pointers.at(sky.light)},
              {"horizontal_factor_sr", sky.horizontal_factor_sr},
              {"zenith_luminance_cd_m2", sky.zenith_luminance_cd_m2},
              {"unobstructed_illuminance_lx", {{"sky", sky.sky_illuminance_lx}, {"ground", sky.ground_illuminance_lx}}}};
    if (scene.output.spectral)
      j["unobstructed_irradiance"] = {{"sky", spectrum_json(sky.sky_irradiance.data(), W)},
                                      {"ground", spectrum_json(sky.ground_irradiance.data(), W)}};
    skies.push_back(std::move(j));
  }
  for (const SunReport& sun : daylight.suns)
    suns.push_back({{"source", scene.light_pointers.at(sun.light)},
                    {"latitude_deg", sun.placement.latitude_deg},
                    {"longitude_deg", sun.placement.longitude_deg},
                    {"time", sun.placement.time},
                    {"elevation_deg", sun.placement.elevation_deg},
                    {"azimuth_deg", sun.placement.azimuth_deg},
                    {"towards", json::array({sun.towards.x, sun.towards.y, sun.towards.z})},
                    {"normal_illuminance_lx", sun.normal_illuminance_lx},
                    {"normal_illuminance_from", sun.placement.clear_sky_illuminance ? "clear_sky_model" : "scene"}});
  return {{"skies", std::move(skies)}, {"suns", std::move(suns)}};
}

// A probe's daylight metrics, added to its result object.
void probe_daylight_json(const ProbeDaylight& d, bool grid, json& j) {
  auto values = [&](const std::vector<double>& v) { return grid ? json(v) : json(v.at(0)); };
  if (!d.daylight_factor_pct.empty()) {
    j["daylight_factor_pct"] = values(d.daylight_factor_pct);
    j["daylight_factor"] = {{"min_pct", d.min_pct},
                            {"mean_pct", d.mean_pct},
                            {"median_pct", d.median_pct},
                            {"max_pct", d.max_pct},
                            {"target_pct", d.target_pct},
                            {"share_at_or_above_target", d.share_at_or_above_target}};
  }
  if (d.en17037) {
    const En17037Summary& e = *d.en17037;
    j["en17037"] = {{"level", en17037_level_name(e.request.level)},
                    {"median_external_diffuse_illuminance_lx", e.request.median_external_diffuse_illuminance_lx},
                    {"target_illuminance_lx", e.target_illuminance_lx},
                    {"minimum_target_illuminance_lx", e.minimum_target_illuminance_lx},
                    {"target_daylight_factor_pct", e.target_daylight_factor_pct},
                    {"minimum_target_daylight_factor_pct", e.minimum_target_daylight_factor_pct},
                    {"daylight_factor_over_50_pct_of_points", e.daylight_factor_over_50_pct},
                    {"daylight_factor_over_95_pct_of_points", e.daylight_factor_over_95_pct},
                    {"target_met", e.target_met},
                    {"minimum_target_met", e.minimum_met},
                    {"met", e.target_met && e.minimum_met}};
  }
  if (!d.vertical_sky_component_pct.empty()) j["vertical_sky_component_pct"] = values(d.vertical_sky_component_pct);
}

// The result's "surfaces": each surface's summary (report.h).
json surfaces_json(const Report& report) {
  json surfaces = json::array();
  for (const SurfaceSummary& s : report.surfaces) {
    json j;
    j["name"] = s.name;
    j["area"] = s.area_m2;
    j["illuminance_lx"] = {{"mean", s.illuminance_mean_lx}, {"min", s.illuminance_min_lx}, {"max", s.illuminance_max_lx}};
    j["luminance_cd_m2"] = s.luminance_mean_cd_m2;
    if (s.melanopic_mean) {
      j["melanopic_irradiance_W_m2"] = s.melanopic_mean->irradiance_W_m2;  // area-weighted means
      j["melanopic_edi_lx"] = s.melanopic_mean->edi_lx;
    }
    j["radiosity_mean"] = s.radiosity_mean;
    j["irradiance_mean"] = s.irradiance_mean;
    surfaces.push_back(std::move(j));
  }
  return surfaces;
}

// The result's "probes": each probe's values, a grid's per point with its summary.
json probes_json(const Scene& scene, const Solution& sol, const Report& report) {
  const std::size_t W = sol.wavelengths();
  const bool spectral = scene.output.spectral;
  json probes = json::array();
  for (std::size_t k = 0; k < scene.probes.size(); ++k) {
    const Probe& probe = scene.probes[k];
    const ProbeSummary& ps = report.probes[k];
    const auto& E = sol.probes[k].irradiance;
    json j;
    j["name"] = probe.name;
    j["quantity"] = quantity_name(probe.quantity);
    if (!probe.is_grid) {
      j["position"] = point_json(probe.points[0], scene.unit_m);
      j["irradiance"] = spectrum_json(E.data(), W);
      j["illuminance_lx"] = ps.illuminance_lx.at(0);
      if (!ps.melanopic.empty()) {
        j["melanopic_irradiance_W_m2"] = ps.melanopic.at(0).irradiance_W_m2;
        j["melanopic_edi_lx"] = ps.melanopic.at(0).edi_lx;
      }
    } else {
      json points = json::array();
      for (const Point3& p : probe.points) points.push_back(point_json(p, scene.unit_m));
      j["nu"] = probe.nu;
      j["nv"] = probe.nv;
      j["points"] = std::move(points);
      j["illuminance_lx"] = ps.illuminance_lx;
      if (!ps.melanopic.empty()) {
        json mel_irradiance = json::array(), mel_edi = json::array();
        for (const Melanopic& m : ps.melanopic) {
          mel_irradiance.push_back(m.irradiance_W_m2);
          mel_edi.push_back(m.edi_lx);
        }
        j["melanopic_irradiance_W_m2"] = std::move(mel_irradiance);
        j["melanopic_edi_lx"] = std::move(mel_edi);
      }
      if (spectral) {
        json irr = json::array();
        for (std::size_t q = 0; q < probe.points.size(); ++q) irr.push_back(spectrum_json(&E[q * W], W));
        j["irradiance"] = std::move(irr);
      }
      j["min_lx"] = ps.min_lx;
      j["mean_lx"] = ps.mean_lx;
      j["max_lx"] = ps.max_lx;
      j["uniformity"] = {{"min_over_mean", ps.min_over_mean}, {"min_over_max", ps.min_over_max}};
    }
    if (report.daylight && report.daylight->probes.at(k)) probe_daylight_json(*report.daylight->probes[k], probe.is_grid, j);
    probes.push_back(std::move(j));
  }
  return probes;
}

// The result's "sources" (output.per_source): each source's share of the patches and probes.
json sources_json(const Scene& scene, const Solution& sol, const Report& report) {
  const std::size_t W = sol.wavelengths();
  const bool spectral = scene.output.spectral;
  json sources = json::array();
  for (std::size_t c = 0; c < sol.contributions.size(); ++c) {
    const SourceContribution& contribution = sol.contributions[c];
    const SourceReport& sr = report.sources.at(c);
    json j;
    j["source"] = contribution.pointer;
    j["name"] = contribution.name;
    j["patches"] = {{"illuminance_lx", sr.patch_illuminance_lx}, {"luminance_cd_m2", sr.patch_luminance_cd_m2}};
    if (spectral) {
      json radiosity = json::array(), irradiance = json::array();
      for (std::size_t i = 0; i < sol.patches.size(); ++i) {
        radiosity.push_back(spectrum_json(&contribution.radiosity[i * W], W));
        irradiance.push_back(spectrum_json(&contribution.irradiance[i * W], W));
      }
      j["patches"]["radiosity"] = std::move(radiosity);
      j["patches"]["irradiance"] = std::move(irradiance);
    }
    json probes = json::array();
    for (std::size_t k = 0; k < scene.probes.size(); ++k) {
      json probe = {{"name", scene.probes[k].name}};
      if (scene.probes[k].is_grid) probe["illuminance_lx"] = sr.probe_illuminance_lx.at(k);
      else probe["illuminance_lx"] = sr.probe_illuminance_lx.at(k).at(0);
      probes.push_back(std::move(probe));
    }
    j["probes"] = std::move(probes);
    sources.push_back(std::move(j));
  }
  return sources;
}

// The result's "stats": the common ones, then the method's own under its name.
json stats_json(const SolveStats& st) {
  json out = {
      {"patches", st.patches},
      {"links", st.links},
      {"rays", st.rays},
      {"exact_visibility_evaluations", st.exact_visibility_evaluations},
      {"links_clear_without_rays", st.links_clear},
      {"leaf_links", st.hierarchical.leaf_links},
      {"leaf_links_traced", st.hierarchical.leaf_links_traced},
      {"leaf_links_exact", st.hierarchical.leaf_links_exact},
      {"crowded_links", st.hierarchical.crowded_links},
      {"link_rays", st.link_rays},
      {"link_ray_thread_s", st.dense.link_ray_thread_s},
      {"iterations", st.iterations},
      {"residual", st.residual},
      {"spectral_systems_solved", st.spectral_systems_solved},
      {"max_patch_area_m2", st.max_patch_area_m2},
      {"adaptive_rounds", st.dense.adaptive_rounds},
      {"direct_refinement_patches", st.direct_refinement_patches},
      {"fine_regions_remeshed", st.fine_regions_remeshed},
      {"contact_triangles_cut", st.contact_triangles_cut},
      {"sliver_regions_remeshed", st.sliver_regions_remeshed},
      {"contact_area_m2", st.contact_area_m2},
      {"enclosed_patches", st.enclosed_patches},
      {"energy",
       {{"emitted_W", st.emitted_W},
        {"absorbed_W", st.absorbed_W},
        {"escaped_W", st.escaped_W},
        {"relative_imbalance", st.relative_imbalance}}},
      {"closure_max_error", st.max_closure_error},
      {"closure_residual", st.closure_residual},
      {"reciprocity_max_error", st.max_reciprocity_error},
      {"reciprocity_mean_error", st.mean_reciprocity_error},
      {"time_s",
       {{"meshing", st.time_meshing_s},
        {"visibility", st.time_visibility_s},
        {"form_factors", st.time_form_factors_s},
        {"solve", st.time_solve_s},
        {"probes", st.time_probes_s},
        {"total", st.time_total_s}}}};
  if (st.error_estimate) {
    const SolveStats::ErrorEstimate& e = *st.error_estimate;
    out["error_estimate"] = {{"coarse_patches", e.coarse_patches},
                             {"coarse_max_patch_area_m2", e.coarse_max_patch_area_m2},
                             {"surface_irradiance_max", e.surface_irradiance_max},
                             {"probe_irradiance_rms", e.probe_irradiance_rms},
                             {"probe_irradiance_max", e.probe_irradiance_max},
                             {"time_s", e.time_s}};
  }
  out["method"] = method_name(st.method);
  out[method_name(st.method)] = method_stats(st);
  return out;
}

}  // namespace

void write_result(std::ostream& os, const Scene& scene, const Solution& sol, const Report& report) {
  json out;
  out["lambert"] = 1;
  out["name"] = scene.name;
  // In rgb mode the three samples are channels, not wavelengths (solver/rgb_model.h): the result
  // names them instead of listing their nominal wavelengths, and every spectral array ("radiosity",
  // "irradiance", ...) holds the R, G, B channel values in that order (W m^-2 rather than per nm).
  if (scene.mode == SpectrumMode::Rgb) {
    out["mode"] = "rgb";
    out["channels"] = json::array();
    for (const char* channel : kRgbChannelNames) out["channels"].push_back(channel);
  } else {
    out["mode"] = "spectral";
    out["wavelengths_nm"] = sol.grid.nm;
  }

  out["patches"] = nullptr;  // written in place by write_result, one patch at a time
  out["surfaces"] = surfaces_json(report);
  out["probes"] = probes_json(scene, sol, report);
  write_evaluations(out, scene, sol, report);
  if (report.daylight) out["daylight"] = daylight_json(scene, *report.daylight);
  if (json luminaires = luminaires_json(scene); !luminaires.empty()) out["luminaires"] = std::move(luminaires);

  if (!sol.contributions.empty()) out["sources"] = sources_json(scene, sol, report);
  if (sol.radiant) {
    if (scene.output.view_factors) out["view_factors"] = view_factors_json(*sol.radiant, scene.unit_m);
    if (sol.radiant->thermal) out["thermal"] = thermal_json(scene, *sol.radiant);
  }

  out["stats"] = stats_json(sol.stats);
  out["warnings"] = sol.warnings;

  // out.dump(), with "patches" (in its sorted place among the keys) written patch by patch.
  os << '{';
  bool first = true;
  for (const auto& [key, value] : out.items()) {
    if (!first) os << ',';
    first = false;
    os << json(key).dump() << ':';
    if (key != "patches") {
      os << value.dump();
      continue;
    }
    os << '[';
    for (std::size_t i = 0; i < sol.patches.size(); ++i) os << (i ? "," : "") << patch_json(scene, sol, report, i).dump();
    os << ']';
  }
  os << '}';
}

std::string encode_result(const Scene& scene, const Solution& sol, const Report& report) {
  std::ostringstream os;
  write_result(os, scene, sol, report);
  return std::move(os).str();
}

ResultSizeBound result_size_bound(const Scene& scene) {
  constexpr double kNumber = 25, kElement = 320, kStatsAndKeys = 64 << 10, kSolverWarnings = 256 << 10;
  const double W = static_cast<double>(scene.grid.size());
  const double spectral = scene.output.spectral ? 1 : 0;
  std::size_t emitters = 0, longest_surface_name = 0;
  ResultSizeBound b;
  b.fixed_bytes = kStatsAndKeys + kSolverWarnings + kNumber * W + static_cast<double>(scene.name.size());
  for (const std::string& w : scene.warnings) b.fixed_bytes += static_cast<double>(w.size()) + 8;
  for (const Surface& s : scene.surfaces) {
    emitters += s.emission ? 1 : 0;
    longest_surface_name = std::max(longest_surface_name, s.name.size());
    b.fixed_bytes += kElement + static_cast<double>(s.name.size()) + kNumber * (8 + 2 * W);  // incl. both means
  }
  const double sources = scene.output.per_source ? static_cast<double>(scene.lights.size() + emitters) : 0;
  for (const Probe& p : scene.probes) {
    const double n = static_cast<double>(p.points.size());
    // position or points (3 n), illuminance and melanopic (3 n), the spectra (W or n W), the grid's summary.
    b.fixed_bytes += kElement + static_cast<double>(p.name.size()) + kNumber * (6 * n + 10) +
                     kNumber * W * (p.is_grid ? n * spectral : 1);
    b.fixed_bytes += sources * (64 + static_cast<double>(p.name.size()) + kNumber * n);  // per-source illuminance
    // Daylight: the daylight factor per point, its statistics and EN 17037's summary; the VSC per point.
    if (p.daylight.daylight_factor) b.fixed_bytes += 2 * kElement + kNumber * (n + 20);
    if (p.daylight.vertical_sky_component) b.fixed_bytes += kNumber * n;
  }
  // "daylight": per sky its factors and spectra, per sun its place, time and position.
  for (const Light& light : scene.lights) {
    if (std::holds_alternative<SkyLight>(light)) b.fixed_bytes += kElement + kNumber * (6 + 2 * W * spectral);
    if (const auto* d = std::get_if<DirectionalLight>(&light); d && d->sun)
      b.fixed_bytes += kElement + static_cast<double>(d->sun->time.size()) + kNumber * 10;
    // "luminaires": per luminaire its names, the opening's description and 16 numbers.
    if (const auto* m = std::get_if<LuminaireLight>(&light))
      b.fixed_bytes += kElement + static_cast<double>(m->name.size() + m->source.size() +
                                                      m->photometry->file.opening.description.size()) +
                       kNumber * (16 + (scene.output.ugr_tables ? 250 : 0));  // the table's 19 × 10 cells, rooms, sets
  }
  b.fixed_bytes += sources * kElement;
  // The evaluations (evaluation_codec.h): a task summary's line per grid it lists, and per glare
  // observer its UGR and a line for every light or emitting surface it may see.
  if (scene.task_summary)
    for (int k : scene.task_summary->grids)
      b.fixed_bytes += kElement + static_cast<double>(scene.probes.at(static_cast<std::size_t>(k)).name.size()) + kNumber * 8;
  const double luminaires = static_cast<double>(scene.lights.size() + emitters);
  for (const GlareObserver& g : scene.glare)
    b.fixed_bytes += kElement + static_cast<double>(g.name.size()) + kNumber * 3 + luminaires * (kElement + kNumber * 8);
  // id, 3 vertices, area, normal, lux, cd/m², xyz, xy, rgb_ebu, srgb, srgb_encoded, melanopic: 32 numbers.
  b.per_patch_bytes = kElement + static_cast<double>(longest_surface_name) + kNumber * (32 + 3 * W * spectral) +
                      sources * kNumber * (2 + 2 * W * spectral);
  // "view_factors" (S × S factors, per surface its name, area and row sum) and "thermal" (per surface
  // its name and 5 numbers; per point of a probe its position, 2 temperatures and S factors; per patch
  // of the exchange, which the same budget bounds, id, surface, 3 vertices, area and 5 numbers).
  const bool thermal = std::any_of(scene.surfaces.begin(), scene.surfaces.end(), [](const Surface& s) { return s.thermal.has_value(); });
  const double S = static_cast<double>(scene.surfaces.size());
  if (scene.output.view_factors || thermal) b.fixed_bytes += kElement + kNumber * S * (S + 2) + S * (kElement + static_cast<double>(longest_surface_name));
  if (thermal) {
    b.fixed_bytes += S * (kElement + static_cast<double>(longest_surface_name) + 5 * kNumber);
    for (const Probe& p : scene.probes) b.fixed_bytes += kElement + kNumber * static_cast<double>(p.points.size()) * (5 + S);
    b.per_patch_bytes += kElement + static_cast<double>(longest_surface_name) + kNumber * 17;
  }
  return b;
}

std::string summarize(const Scene& scene, const Solution& sol, const Report& report) {
  const SolveStats& st = sol.stats;
  std::string s;
  char line[512];
  std::snprintf(line, sizeof line, "%s: %zu patches, %zu links, %llu rays, %d spectral system(s), %.3f s\n",
                scene.name.empty() ? "scene" : scene.name.c_str(), st.patches, st.links,
                static_cast<unsigned long long>(st.rays), st.spectral_systems_solved, st.time_total_s);
  s += line;
  std::snprintf(line, sizeof line, "energy: emitted %.6g W, absorbed %.6g W, escaped %.6g W, imbalance %.2e\n",
                st.emitted_W, st.absorbed_W, st.escaped_W, st.relative_imbalance);
  s += line;
  s += "mean illuminance per surface:\n";
  for (const SurfaceSummary& surf : report.surfaces) {
    std::snprintf(line, sizeof line, "  %-24s %12.4f lx  (min %.4f, max %.4f)\n", surf.name.c_str(),
                  surf.illuminance_mean_lx, surf.illuminance_min_lx, surf.illuminance_max_lx);
    s += line;
  }
  for (std::size_t k = 0; k < report.probes.size(); ++k) {
    const ProbeSummary& p = report.probes[k];
    std::snprintf(line, sizeof line, "probe %-18s mean %.4f lx (min %.4f, max %.4f, Emin/Emean %.3f)\n",
                  scene.probes[k].name.c_str(), p.mean_lx, p.min_lx, p.max_lx, p.min_over_mean);
    s += line;
  }
  if (sol.radiant && sol.radiant->thermal) {
    const GreyExchange& g = *sol.radiant->thermal;
    s += "radiant exchange (net = emitted − absorbed):\n";
    for (std::size_t I = 0; I < g.surfaces.size(); ++I) {
      std::snprintf(line, sizeof line, "  %-24s %12.4f W/m²  %14.6g W\n", sol.radiant->factors.names[I].c_str(),
                    g.surfaces[I].net_flux_W_m2, g.surfaces[I].net_W);
      s += line;
    }
  }
  for (const std::string& w : sol.warnings) s += "warning: " + w + "\n";
  return s;
}

}  // namespace lambert
