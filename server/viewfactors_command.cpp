// `lambert viewfactors INPUT -o OUT` (SPEC §3 and §5): the view factors between a scene's surfaces,
// and the radiant exchange where the surfaces have thermal properties (their own "thermal", or
// --thermal FILE by name).
//   INPUT: a scene (.json), a View3D input file (.vs3, server/viewfactors/vs3_scene.h), or a factor
//   file this command wrote: then no geometry is computed; its matrix is written in another format,
//   or with --thermal the grey exchange is solved on it, each surface's radiosity uniform.
//   OUT: JSON (default), CSV (.csv), View3D's text (--format view3d) or EnergyPlus IDF (.idf).
// Exit status: 0 written, 1 the computation or the writing failed, 2 bad usage or invalid input.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/cli_progress.h"
#include "server/codec/document.h"
#include "server/viewfactors/formats.h"
#include "server/viewfactors/radiant_json.h"
#include "server/viewfactors/vs3_scene.h"

namespace lambert {
namespace {

using nlohmann::json;

struct ViewFactorArgs {
  std::string input, output, format, thermal, zone, method;
  bool patches = false;
  std::optional<double> max_patch_area;
};

enum class Format { Json, Csv, View3d, Idf };

int fail(int status, const std::string& message) {
  std::cerr << "lambert viewfactors: " << message << "\n";
  return status;
}

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

Format format_of(const ViewFactorArgs& args) {
  if (args.format == "csv" || (args.format.empty() && extension(args.output) == ".csv")) return Format::Csv;
  if (args.format == "idf" || (args.format.empty() && extension(args.output) == ".idf")) return Format::Idf;
  if (args.format == "view3d") return Format::View3d;
  return Format::Json;
}

// What is computed or read, ready to be written.
struct Factors {
  ViewFactorMatrix matrix;
  std::string geometry_hash;
  std::vector<std::optional<double>> emissivity;  // per reported surface, where known
  json document;                                  // the JSON output
  std::vector<double> view3d_factors;             // F, or ℱ with emit=1
  View3dHeader view3d;
  std::string name;                               // the scene's (IDF zone by default)
};

// The thermal file's entries by name: the reported surfaces, and (for the patch-level exchange) the
// occluders, each taking its entry to all its scene surfaces (an obstruction's two faces, a reported
// surface's combined parts).
struct ThermalKeys {
  std::vector<std::string> names;
  std::vector<std::optional<double>> emissivity;
  std::vector<int> of_surface;  // per scene surface: its entry
};

ThermalKeys thermal_keys(const Scene& scene, const SurfaceGroups& groups, const std::vector<double>* vs3_emissivity) {
  ThermalKeys keys;
  std::map<std::string, int> index;
  auto key = [&](const std::string& name, std::optional<double> eps) {
    const auto [it, added] = index.try_emplace(name, static_cast<int>(keys.names.size()));
    if (added) keys.names.push_back(name), keys.emissivity.push_back(eps);
    return it->second;
  };
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const int g = groups.of_surface[s];
    std::string name = g >= 0 ? groups.names[g] : scene.surfaces[s].name;
    if (g < 0 && name.size() > 7 && name.ends_with(" (back)")) name.resize(name.size() - 7);
    const std::optional<double> eps = vs3_emissivity && g >= 0 ? std::optional((*vs3_emissivity)[s]) : std::nullopt;
    keys.of_surface.push_back(key(name, eps));
  }
  return keys;
}

// --thermal FILE onto the scene's surfaces; false after printing what is wrong.
bool apply_thermal_file(const ViewFactorArgs& args, Scene& scene, const SurfaceGroups& groups,
                        const std::vector<double>* vs3_emissivity, const std::string& hash) {
  std::string text;
  if (!read_text_file(args.thermal, text)) return fail(2, "cannot read " + args.thermal), false;
  const ThermalKeys keys = thermal_keys(scene, groups, vs3_emissivity);
  std::vector<std::string> errors;
  const std::optional<ThermalFile> file = read_thermal_file(text, keys.names, keys.emissivity, errors);
  if (file && file->geometry_hash && *file->geometry_hash != hash)
    errors.push_back("/geometry_hash: " + *file->geometry_hash + " is not this geometry's (" + hash + ")");
  if (!errors.empty()) {
    std::cerr << args.thermal << ": invalid thermal file\n";
    for (const std::string& e : errors) std::cerr << e << "\n";
    return false;
  }
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) scene.surfaces[s].thermal = file->by_name[keys.of_surface[s]];
  return true;
}

// View3D's encl=1 says the surfaces form an enclosure: Lambert closes the rows of patches whose
// hemisphere it finds closed, and says which surfaces' views leave the enclosure instead of scaling
// them to 1 as View3D would.
void check_enclosure(const ViewFactorMatrix& m, std::vector<std::string>& warnings) {
  std::string open;
  for (std::size_t I = 0; I < m.size(); ++I) {
    const double total = m.row_sums[I] + (m.to_occluders.empty() ? 0.0 : m.to_occluders[I]);
    if (std::abs(1 - total) > 1e-6)
      open += (open.empty() ? "" : ", ") + ("\"" + m.names[I] + "\" (" + std::to_string(total) + ")");
  }
  if (!open.empty())
    warnings.push_back("encl=1, but the views of surfaces " + open + " do not close (their factors, obstructions "
                       "included, do not sum to 1: the surfaces leave gaps or are seen from behind); their factors "
                       "are kept as the geometry gives them, not scaled to 1");
}

std::optional<Factors> compute(const ViewFactorArgs& args, Scene& scene, const SurfaceGroups& groups,
                               const Vs3Scene* vs3, int& status) {
  if (args.max_patch_area) scene.meshing.max_patch_area_m2 = *args.max_patch_area * scene.unit_m * scene.unit_m;
  if (args.method == "dense") scene.solver.method = SolverMethod::Dense;
  if (args.method == "hierarchical") scene.solver.method = SolverMethod::Hierarchical;
  status = 2;
  if (!args.thermal.empty() &&
      !apply_thermal_file(args, scene, groups, vs3 ? &vs3->emissivity : nullptr, geometry_hash(scene, groups)))
    return std::nullopt;
  RadiantOptions options;
  options.patch_factors = args.patches;
  options.thermal = std::all_of(scene.surfaces.begin(), scene.surfaces.end(), [](const Surface& s) { return s.thermal.has_value(); });
  if (vs3 && vs3->controls.emittances) options.total_exchange_emissivity = vs3->emissivity;
  SolveControl control;
  show_progress_on_terminal(control);
  status = 1;
  RadiantExchange r;
  try {
    r = radiant_exchange(scene, groups, options, control);
  } catch (const std::exception& e) {
    fail(1, e.what());
    return std::nullopt;
  }
  Factors out;
  out.matrix = r.factors;
  out.geometry_hash = r.geometry_hash;
  out.name = scene.name;
  if (vs3) out.emissivity = vs3->group_emissivity;
  out.document = view_factors_json(r, scene.unit_m, out.emissivity);
  if (r.thermal) out.document["thermal"] = thermal_json(scene, r);
  std::vector<std::string> warnings = r.warnings;
  if (vs3) {
    warnings.insert(warnings.begin(), vs3->warnings.begin(), vs3->warnings.end());
    out.view3d.enclosure = vs3->controls.enclosure;
    out.view3d.with_emittances = vs3->controls.emittances;
    if (vs3->controls.enclosure) check_enclosure(r.factors, warnings);
  }
  out.view3d_factors = r.total_exchange.empty() ? r.factors.F : r.total_exchange;
  out.document["warnings"] = warnings;
  for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";
  status = 0;
  return out;
}

// A factor file written before: its matrix in another format, or (--thermal) the grey exchange on it.
std::optional<Factors> reuse(const ViewFactorArgs& args, const json& doc, int& status) {
  status = 2;
  if (args.patches || args.max_patch_area || !args.method.empty())
    return fail(2, "--patches, --max-patch-area and --method need a scene, not a factor file"), std::nullopt;
  std::vector<std::string> errors;
  const std::optional<SavedFactors> saved = read_saved_factors(doc, errors);
  Factors out;
  if (saved) {
    out.matrix = saved->matrix;
    out.geometry_hash = saved->geometry_hash;
    out.emissivity = saved->emissivity;
    out.view3d_factors = out.matrix.F;
    out.name = std::filesystem::path(args.input).stem().string();
    out.document = view_factors_json(out.matrix, out.geometry_hash, out.emissivity);
  }
  std::string text;
  std::optional<ThermalFile> thermal;
  if (saved && !args.thermal.empty()) {
    if (!read_text_file(args.thermal, text)) return fail(2, "cannot read " + args.thermal), std::nullopt;
    thermal = read_thermal_file(text, out.matrix.names, out.emissivity, errors);
    if (thermal && thermal->geometry_hash && *thermal->geometry_hash != out.geometry_hash)
      errors.push_back(args.thermal + ": /geometry_hash: " + *thermal->geometry_hash + " is not the factor file's (" +
                       out.geometry_hash + ")");
  }
  if (!errors.empty()) {
    std::cerr << args.input << ": invalid factor or thermal file\n";
    for (const std::string& e : errors) std::cerr << e << "\n";
    return std::nullopt;
  }
  if (thermal) {
    status = 1;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const GreyExchange g = grey_exchange(out.matrix, thermal->by_name, {});
      out.document["thermal"] = thermal_json(out.matrix, g, out.geometry_hash);
    } catch (const std::exception& e) {
      return fail(1, e.what()), std::nullopt;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "radiant exchange on the saved surface matrix (each surface's radiosity uniform): " << ms << " ms\n";
  }
  status = 0;
  return out;
}

int write_output(const ViewFactorArgs& args, Format format, const Factors& f) {
  std::string bytes;
  try {
    switch (format) {
      case Format::Json: bytes = f.document.dump() + "\n"; break;
      case Format::Csv: bytes = view_factors_csv(f.matrix); break;
      case Format::View3d: {
        View3dHeader header = f.view3d;
        header.version = LAMBERT_VERSION;
        bytes = view_factors_view3d(f.matrix, f.view3d_factors, f.emissivity, header);
        break;
      }
      case Format::Idf: {
        const std::string zone = !args.zone.empty() ? args.zone : !f.name.empty() ? f.name : "Zone 1";
        bytes = view_factors_idf(f.matrix, zone, "view factors by Lambert " LAMBERT_VERSION " (geometry " +
                                                     f.geometry_hash + ")");
        break;
      }
    }
  } catch (const std::invalid_argument& e) {
    return fail(2, e.what());
  }
  std::ofstream out(args.output, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) return fail(1, "cannot write " + args.output);
  std::cout << "wrote " << args.output << ": the view factors of " << f.matrix.size() << " surfaces";
  if (f.document.contains("thermal")) std::cout << " and their radiant exchange";
  std::cout << "\n";
  return 0;
}

int run_viewfactors(const ViewFactorArgs& args) {
  const Format format = format_of(args);
  if (args.patches && format != Format::Json)
    return cli::usage_error("viewfactors", "--patches: the patch matrix is written in JSON only");
  std::string text;
  if (!read_text_file(args.input, text)) return fail(2, "cannot read " + args.input);
  std::optional<Factors> factors;
  int status = 0;
  if (extension(args.input) == ".vs3") {
    Vs3SceneResult read = vs3_scene(text, args.input);
    if (!read.scene) {
      for (const std::string& e : read.errors) std::cerr << e << "\n";
      return 2;
    }
    factors = compute(args, read.scene->scene, read.scene->groups, &*read.scene, status);
  } else {
    codec::ParsedDocument parsed = codec::parse_document(text);
    const bool saved = parsed.fatal.empty() && parsed.doc.is_object() &&
                       (parsed.doc.contains("F") || parsed.doc.contains("view_factors"));
    if (saved) {
      factors = reuse(args, parsed.doc, status);
    } else {
      std::optional<Scene> scene = decode_scene_file(args.input, text);
      if (!scene) return 2;
      factors = compute(args, *scene, SurfaceGroups::each_surface(*scene), nullptr, status);
    }
  }
  if (!factors) return status;
  return write_output(args, format, *factors);
}

}  // namespace

cli::CommandSpec command_viewfactors() {
  return {"viewfactors", "view factors between surfaces (JSON, CSV, View3D, EnergyPlus IDF) and radiant exchange",
          [](cli::Options& o) {
            auto args = std::make_shared<ViewFactorArgs>();
            o.input("INPUT", args->input, "a scene (.json), a View3D input file (.vs3), or a factor file written before");
            o.output(args->output, "the file to write: JSON, or .csv, .idf; View3D's text with --format view3d")
                .required();
            o.choice("--format", args->format, {"json", "csv", "view3d", "idf"},
                     "the output format, when the extension does not say it (default json)");
            o.flag("--patches", args->patches, "also the patch-to-patch factors, sparse (JSON only)");
            o.text("--thermal", args->thermal,
                   "temperatures or net fluxes (and emissivities) by surface name: solve the radiant exchange",
                   "FILE");
            o.text("--zone", args->zone, "the EnergyPlus zone (IDF; default: the scene's name)", "NAME");
            o.positive("--max-patch-area", args->max_patch_area,
                       "the patch size in the scene's units squared (default: the scene's meshing.max_patch_area)");
            o.choice("--method", args->method, {"dense", "hierarchical"}, "the solver method (default: the scene's)");
            o.footer("F_IJ = sum over patches i of I of A_i sum over patches j of J of F_ij, over A_I.\n"
                     "A factor file written by this command is read back: --thermal then solves the grey\n"
                     "exchange on its surface matrix (each surface's radiosity uniform), in milliseconds.");
            return [args] { return run_viewfactors(*args); };
          }};
}

}  // namespace lambert
