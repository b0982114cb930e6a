// `lambert render (SCENE.json | RESULT.json) -o IMAGE.png [--camera "..."] [--false-color illuminance|
// luminance] [--white CD_M2]` (SPEC §3). A scene is solved first and its materials' specular lobes are
// added (from the lights and the emitting patches, with shadows); a result is drawn as it is (its
// patches' linear sRGB radiance, diffuse only). Exit status: 0 written, 1 the solve or the writing
// failed, 2 bad usage or an invalid input (the message names the field).
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mesh/geometry.h"
#include "server/render.h"
#include "solver/radiosity.h"
#include "solver/report.h"
#include "solver/scene.h"

namespace lambert {

int render_command(const std::vector<std::string>& args);

// What `lambert render` draws of a solved scene: its patches (metres) with the report's linear sRGB
// radiance, illuminance and luminance, emitting patches marked.
RenderPatches render_patches(const Scene& scene, const Solution& solution, const Report& report);

// The same from a result file's text (vertices in scene units), and the white point its patches'
// srgb_encoded implies (absent when no channel shows it). Throws std::invalid_argument naming the
// JSON pointer of the first field it cannot use.
RenderPatches result_render_patches(const std::string& result_json, std::optional<double>& white_cd_m2);

// The specular radiance (linear sRGB, absolute) that patch i of a solved scene shows at `point`
// towards the unit direction `to_eye`: E k_s ρ_s(λ) (n+1)/(2π) cos^n α summed over the lights
// (point-like and directional; ambient light has no direction) and the Lambertian emitting patches
// (each from its centroid, with E its exact point-to-triangle factor times its exitance), each with
// a shadow ray; α is the angle between `to_eye` and the source's mirror direction. Zero for a
// material without a specular lobe. The returned function keeps references to scene and solution.
std::function<std::array<double, 3>(std::size_t, const Point3&, const Vector3&)> specular_shading(
    const Scene& scene, const Solution& solution);

}  // namespace lambert
