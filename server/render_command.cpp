// `lambert render` (see render_command.h).
#include "server/render_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/cli_progress.h"
#include "server/export/result_model.h"
#include "server/canvas.h"
#include "server/grid_map.h"
#include "server/render.h"
#include "server/scene_codec.h"
#include "solver/form_factor.h"
#include "solver/light_model.h"
#include "solver/report.h"
#include "solver/rgb_model.h"
#include "solver/spectrum.h"
#include "solver/visibility.h"

namespace lambert {
namespace {

using json = nlohmann::json;

struct RenderArgs {
  std::string input, output, camera_text;
  std::string false_colour = "none";
  std::string scale = "log", probe_grid;
  std::optional<double> white_cd_m2;
  bool smooth = false;
};

constexpr const char* kRenderFooter =
    "A scene is solved first (its specular lobes are drawn too); a result is drawn as it is.\n"
    "Camera positions are in scene units; default: the scene seen from -z, +y up, 40 degrees, 640x480.";

int render_usage_error(const std::string& message) { return cli::usage_error("render", message); }

// The linear sRGB value of a spectral radiance (or of three rgb-mode channels).
std::array<double, 3> linear_srgb(const std::vector<double>& L, const Scene& scene) {
  const Xyz c = scene.mode == SpectrumMode::Rgb ? xyz_from_rgb_channels({L[0], L[1], L[2]}) : tristimulus(L, scene.grid);
  return xyz_to_linear_srgb(c);
}

// A result file's patches (vertices in scene units) as render draws them: none marked as emitting,
// so that the white comes from the result itself (display_white).
RenderPatches patches_of(const ResultModel& model) {
  RenderPatches out;
  for (const ResultPatch& p : model.patches) {
    out.triangles.push_back(p.triangle);
    out.srgb.push_back(p.srgb);
    out.luminance_cd_m2.push_back(p.luminance_cd_m2);
    out.illuminance_lx.push_back(p.illuminance_lx);
    out.emits.push_back(0);
    out.surface.push_back(p.surface);
  }
  return out;
}

}  // namespace

std::function<std::array<double, 3>(std::size_t, const Point3&, const Vector3&)> specular_shading(
    const Scene& scene, const Solution& sol) {
  struct Shading {
    const Scene& scene;
    const Solution& sol;
    std::vector<Triangle> triangles;
    std::unique_ptr<Visibility> vis;
    std::vector<std::unique_ptr<LightModel>> lights;  // parallel to scene.lights
    std::vector<std::size_t> emitters;                // Lambertian emitting patches
  };
  auto s = std::make_shared<Shading>(Shading{scene, sol, {}, nullptr, {}, {}});
  bool any_lobe = false;
  for (const Material& m : scene.materials) any_lobe |= m.specular && m.specular->coefficient > 0;
  if (!any_lobe) return {};
  for (const Patch& p : sol.patches) s->triangles.push_back(p.triangle);
  s->vis = std::make_unique<Visibility>(s->triangles);
  // The lobes are drawn for lights that come from one direction (a sky, like ambient light, has none).
  for (const Light& l : scene.lights)
    s->lights.push_back(std::holds_alternative<DirectionalLight>(l) || std::holds_alternative<PointLight>(l)
                            ? make_light_model(l)
                            : nullptr);
  for (std::size_t j = 0; j < sol.patches.size(); ++j) {
    const auto& e = scene.surfaces[sol.patches[j].surface].emission;
    if (e && e->lobe_exponent == 1.0) s->emitters.push_back(j);
  }
  return [s](std::size_t i, const Point3& point, const Vector3& to_eye) -> std::array<double, 3> {
    const Scene& scene = s->scene;
    const Patch& patch = s->sol.patches[i];
    const auto& lobe = scene.materials[scene.surfaces[patch.surface].material].specular;
    if (!lobe || !(lobe->coefficient > 0)) return {0, 0, 0};
    const Vector3 n = patch.normal;
    const Point3 p = s->vis->lift(point, n);
    const std::size_t W = scene.grid.size();
    std::vector<double> L(W, 0.0);
    const double norm = lobe->coefficient * (lobe->exponent + 1) / (2 * kPi);
    // One source seen along unit direction w with irradiance g × S(λ) at p.
    auto add = [&](const Vector3& w, double g, const std::vector<double>& S) {
      const double cos_in = dot(n, w);
      if (!(g > 0) || !(cos_in > 0)) return;
      const Vector3 mirror = n * (2 * cos_in) - w;
      const double cos_alpha = dot(mirror, to_eye);
      if (!(cos_alpha > 0)) return;
      const double weight = norm * std::pow(cos_alpha, lobe->exponent) * g;
      for (std::size_t k = 0; k < W; ++k) L[k] += weight * lobe->reflectance[k] * S[k];
    };
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
      if (const auto* d = std::get_if<DirectionalLight>(&scene.lights[l]))
        add(d->direction * -1.0, s->lights[l]->point_factor(p, n, *s->vis), s->lights[l]->spectrum());
      else if (const auto* q = std::get_if<PointLight>(&scene.lights[l]))
        add(normalize(q->position - p), s->lights[l]->point_factor(p, n, *s->vis), s->lights[l]->spectrum());
      else if (const auto* m = std::get_if<LuminaireLight>(&scene.lights[l]))
        add(normalize(m->position - p), s->lights[l]->point_factor(p, n, *s->vis), s->lights[l]->spectrum());
    }
    for (std::size_t j : s->emitters) {
      if (j == i) continue;
      const Patch& e = s->sol.patches[j];
      const Point3 c = e.triangle.centroid();
      if (!(dot(p - c, e.normal) > 0)) continue;  // behind the emitter
      const double g = point_triangle_factor(p, n, e.triangle);
      if (!(g > 0) || !s->vis->visible(p, s->vis->lift(c, e.normal))) continue;
      add(normalize(c - p), g, scene.surfaces[e.surface].emission->exitance_W_m2_nm);
    }
    return linear_srgb(L, scene);
  };
}

RenderPatches render_patches(const Scene& scene, const Solution& sol, const Report& report) {
  RenderPatches patches;
  for (std::size_t i = 0; i < sol.patches.size(); ++i) {
    patches.triangles.push_back(sol.patches[i].triangle);
    patches.srgb.push_back(report.patches[i].srgb);
    patches.illuminance_lx.push_back(report.patches[i].illuminance_lx);
    patches.luminance_cd_m2.push_back(report.patches[i].luminance_cd_m2);
    patches.emits.push_back(scene.surfaces[sol.patches[i].surface].emission ? 1 : 0);
    patches.surface.push_back(sol.patches[i].surface);
  }
  return patches;
}

RenderPatches result_render_patches(const std::string& result_json, std::optional<double>& white_cd_m2) {
  const ResultModel model = read_result(result_json);
  white_cd_m2 = model.white_cd_m2;
  return patches_of(model);
}

namespace {

// What the input gives to draw. The scene and solution are kept for the specular shading, which
// refers to them.
struct RenderInput {
  RenderPatches patches;
  double unit_m = 1;  // metres per camera unit: a scene's unit; a result's patches are in scene units
  std::optional<double> white_cd_m2;
  std::vector<GridValues> grids;
  std::optional<Scene> scene;
  std::optional<Solution> solution;
};

std::string unit_name(double unit_m) {
  return unit_m == 1 ? "m" : unit_m == 0.01 ? "cm" : unit_m == 0.001 ? "mm" : "scene units";
}

// A grid probe's values with its cell sides, from its points (scene units).
GridValues grid_values(const std::string& name, int nu, int nv, const std::vector<Point3>& points,
                       const std::vector<double>& lux, double unit_m) {
  GridValues g{name, nu, nv, 1, 1, unit_name(unit_m), lux};
  const double du = nu > 1 ? distance(points[1], points[0]) : 0;
  const double dv = nv > 1 ? distance(points[static_cast<std::size_t>(nu)], points[0]) : 0;
  g.cell_u = du > 0 ? du : dv > 0 ? dv : 1;
  g.cell_v = dv > 0 ? dv : g.cell_u;
  return g;
}

void read_result_input(const std::string& text, RenderInput& in) {
  const ResultModel model = read_result(text);
  in.patches = patches_of(model);
  in.white_cd_m2 = model.white_cd_m2;
  for (const ResultProbe& p : model.probes)
    if (p.is_grid) in.grids.push_back(grid_values(p.name, p.nu, p.nv, p.points, p.illuminance_lx, model.unit_m));
}

// Solves the scene; false (after printing why) when the scene is invalid.
bool solve_scene_input(const std::string& path, const std::string& text, RenderInput& in) {
  in.scene = decode_scene_file(path, text);
  if (!in.scene) return false;
  in.unit_m = in.scene->unit_m;
  SolveControl control;
  show_progress_on_terminal(control);
  in.solution = solve(*in.scene, control);
  const Report report = make_report(*in.scene, *in.solution);
  in.patches = render_patches(*in.scene, *in.solution, report);
  for (std::size_t k = 0; k < in.scene->probes.size(); ++k) {
    const Probe& p = in.scene->probes[k];
    if (!p.is_grid) continue;
    std::vector<Point3> points;
    for (const Point3& q : p.points) points.push_back({q.x / in.unit_m, q.y / in.unit_m, q.z / in.unit_m});
    in.grids.push_back(grid_values(p.name, p.nu, p.nv, points, report.probes[k].illuminance_lx, in.unit_m));
  }
  return true;
}

// Reads (and for a scene, solves) the input; returns the exit status of a failure, printed.
std::optional<int> load_input(const RenderArgs& args, RenderInput& in) {
  std::string text;
  if (!read_text_file(args.input, text)) {
    std::cerr << "lambert render: cannot read " << args.input << "\n";
    return 2;
  }
  const json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    std::cerr << "lambert render: " << args.input << " is not a JSON object (a scene or a result)\n";
    return 2;
  }
  try {
    if (doc.contains("patches"))
      read_result_input(text, in);
    else if (!solve_scene_input(args.input, text, in))
      return 2;
  } catch (const SolveError& e) {
    std::cerr << "lambert render: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "lambert render: " << args.input << ": " << e.what() << "\n";
    return 2;
  }
  if (in.patches.triangles.empty()) {
    std::cerr << "lambert render: " << args.input << " has no patches to draw\n";
    return 1;
  }
  return std::nullopt;
}

int write_image(const Image& image, const std::string& output, const std::string& what) {
  try {
    write_png(image, output);
  } catch (const std::exception& e) {
    std::cerr << "lambert render: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote " << output << " (" << image.width << "x" << image.height << ", " << what << ")\n";
  return 0;
}

int draw_grid(const RenderArgs& args, const RenderInput& in) {
  std::string names;
  for (const GridValues& g : in.grids) {
    if (g.name == args.probe_grid)
      return write_image(draw_grid_map(g, args.scale == "linear" ? ScaleKind::Linear : ScaleKind::Log), args.output,
                         "probe grid " + g.name);
    names += (names.empty() ? "" : ", ") + g.name;
  }
  return render_usage_error("--probe-grid: " + args.input + " has no probe grid '" + args.probe_grid + "'" +
                            (names.empty() ? " (it has none)" : " (its grids: " + names + ")"));
}

int draw_view(const RenderArgs& args, RenderInput& in) {
  RenderOptions options;
  options.false_colour = args.false_colour == "illuminance" ? FalseColour::Illuminance
                         : args.false_colour == "luminance" ? FalseColour::Luminance
                                                            : FalseColour::None;
  options.scale = args.scale == "linear" ? ScaleKind::Linear : ScaleKind::Log;
  options.white_cd_m2 = args.white_cd_m2 ? args.white_cd_m2 : in.white_cd_m2;
  options.smooth = args.smooth;
  if (in.scene) options.view_dependent = specular_shading(*in.scene, *in.solution);
  // The camera is given in scene units; the patches of a solved scene are in metres.
  const double unit_m = in.unit_m;
  Camera camera = default_camera(in.patches.triangles);
  camera.eye = {camera.eye.x / unit_m, camera.eye.y / unit_m, camera.eye.z / unit_m};
  camera.look = {camera.look.x / unit_m, camera.look.y / unit_m, camera.look.z / unit_m};
  try {
    camera = parse_camera(args.camera_text, camera);
  } catch (const std::invalid_argument& e) {
    return render_usage_error(e.what());
  }
  camera.eye = {camera.eye.x * unit_m, camera.eye.y * unit_m, camera.eye.z * unit_m};
  camera.look = {camera.look.x * unit_m, camera.look.y * unit_m, camera.look.z * unit_m};
  return write_image(render(in.patches, camera, options), args.output,
                     std::to_string(in.patches.triangles.size()) + " patches");
}

int run_render(const RenderArgs& args) {
  RenderInput in;
  if (const auto failed = load_input(args, in)) return *failed;
  return args.probe_grid.empty() ? draw_view(args, in) : draw_grid(args, in);
}

}  // namespace

cli::CommandSpec command_render() {
  return {"render", "a picture of a solution, or a false-colour map with its scale", [](cli::Options& o) {
            auto args = std::make_shared<RenderArgs>();
            o.input("INPUT", args->input, "a scene (solved first) or a result of lambert solve");
            o.output(args->output, "the PNG image to write").required();
            const cli::Option camera_option = o.text("--camera", args->camera_text,
                   "\"eye=X,Y,Z look=X,Y,Z up=X,Y,Z fov=DEG size=WxH\", any of them, in scene units");
            const cli::Option false_colour_option = o.choice("--false-color,--false-colour", args->false_colour, {"none", "illuminance", "luminance"},
                     "draw this quantity in false colour, with its scale");
            o.positive("--white", args->white_cd_m2,
                       "the luminance in cd/m2 shown as white (default: the brightest patch that does not emit)");
            const cli::Option smooth_option =
                o.flag("--smooth", args->smooth, "interpolate the radiance between the patches' vertices");
            o.choice("--scale", args->scale, {"log", "linear"},
                     "the false colours' scale: three decades down from the largest value, or 0 to it");
            cli::Option grid = o.text("--probe-grid", args->probe_grid,
                                            "instead of a view: the map of this probe grid, with isolux lines", "NAME");
            grid.excludes(camera_option).excludes(false_colour_option).excludes(smooth_option);
            o.footer(kRenderFooter);
            return [args] { return run_render(*args); };
          }};
}

int render_command(const std::vector<std::string>& args) { return cli::run_one(command_render(), args); }

}  // namespace lambert
