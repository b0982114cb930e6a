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
  for (const Light& l : scene.lights) s->lights.push_back(make_light_model(l));
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

int run_render(const RenderArgs& args) {
  const std::string& input = args.input;
  const std::string& output = args.output;
  std::string text;
  if (!read_text_file(input, text)) {
    std::cerr << "lambert render: cannot read " << input << "\n";
    return 2;
  }
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    std::cerr << "lambert render: " << input << " is not a JSON object (a scene or a result)\n";
    return 2;
  }
  RenderOptions options;
  options.false_colour = args.false_colour == "illuminance" ? FalseColour::Illuminance
                         : args.false_colour == "luminance" ? FalseColour::Luminance
                                                            : FalseColour::None;
  options.white_cd_m2 = args.white_cd_m2;
  options.smooth = args.smooth;
  RenderPatches patches;
  double unit_m = 1;  // metres per camera unit (the scene's unit)
  // Kept alive for the specular shading, which refers to them.
  std::optional<Scene> scene;
  std::optional<Solution> solution;
  try {
    if (doc.contains("patches")) {
      const ResultModel model = read_result(text);
      patches = patches_of(model);
      if (!options.white_cd_m2) options.white_cd_m2 = model.white_cd_m2;
    } else {
      scene = decode_scene_file(input, text);
      if (!scene) return 2;
      unit_m = scene->unit_m;
      SolveControl control;
      show_progress_on_terminal(control);
      solution = solve(*scene, control);
      patches = render_patches(*scene, *solution, make_report(*scene, *solution));
      options.view_dependent = specular_shading(*scene, *solution);
    }
  } catch (const SolveError& e) {
    std::cerr << "lambert render: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "lambert render: " << input << ": " << e.what() << "\n";
    return 2;
  }
  if (patches.triangles.empty()) {
    std::cerr << "lambert render: " << input << " has no patches to draw\n";
    return 1;
  }
  // The camera is given in scene units; the patches of a solved scene are in metres.
  Camera camera = default_camera(patches.triangles);
  camera.eye = {camera.eye.x / unit_m, camera.eye.y / unit_m, camera.eye.z / unit_m};
  camera.look = {camera.look.x / unit_m, camera.look.y / unit_m, camera.look.z / unit_m};
  try {
    camera = parse_camera(args.camera_text, camera);
  } catch (const std::invalid_argument& e) {
    return render_usage_error(e.what());
  }
  camera.eye = {camera.eye.x * unit_m, camera.eye.y * unit_m, camera.eye.z * unit_m};
  camera.look = {camera.look.x * unit_m, camera.look.y * unit_m, camera.look.z * unit_m};
  try {
    render(patches, camera, options).write_png(output);
  } catch (const std::exception& e) {
    std::cerr << "lambert render: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote " << output << " (" << camera.width << "x" << camera.height << ", "
            << patches.triangles.size() << " patches)\n";
  return 0;
}

}  // namespace

cli::CommandSpec command_render() {
  return {"render", "a picture of a solution, or a false-colour map with its scale", [](cli::Options& o) {
            auto args = std::make_shared<RenderArgs>();
            o.input("INPUT", args->input, "a scene (solved first) or a result of lambert solve");
            o.output(args->output, "the PNG image to write").required();
            o.text("--camera", args->camera_text,
                   "\"eye=X,Y,Z look=X,Y,Z up=X,Y,Z fov=DEG size=WxH\", any of them, in scene units");
            o.choice("--false-color,--false-colour", args->false_colour, {"none", "illuminance", "luminance"},
                     "draw this quantity in false colour, with its scale");
            o.positive("--white", args->white_cd_m2,
                       "the luminance in cd/m2 shown as white (default: the brightest patch that does not emit)");
            o.flag("--smooth", args->smooth, "interpolate the radiance between the patches' vertices");
            o.footer(kRenderFooter);
            return [args] { return run_render(*args); };
          }};
}

int render_command(const std::vector<std::string>& args) { return cli::run_one(command_render(), args); }

}  // namespace lambert
