// Daylight scenes written as JSON for the tests that run them through the whole solve (scene JSON →
// result JSON): surfaces as rectangles, skies, probes, and the solve itself.
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "server/result_codec.h"
#include "server/scene_codec.h"
#include "solver/radiosity.h"
#include "solver/report.h"

namespace lambert::test::daylight {

using nlohmann::json;

inline json triple(const Vector3& v) { return json::array({v.x, v.y, v.z}); }
inline json triple(const Point3& p) { return json::array({p.x, p.y, p.z}); }

// The rectangle o + s u + t v as a polygon, front side along u × v.
inline json rectangle(const std::string& name, const std::string& material, const Point3& o, const Vector3& u,
               const Vector3& v) {
  return {{"name", name},
          {"material", material},
          {"polygon", json::array({triple(o), triple(o + u), triple(o + u + v), triple(o + v)})}};
}

// A scene with materials "black" (0) and "grey" (0.5), coarse patches (the sky's light is checked at
// probes, which take it exactly whatever the patches), and the given surfaces, lights and probes.
inline json scene_with(json surfaces, json lights, json probes, const std::string& method = "dense") {
  return {{"materials", {{"black", {{"reflectance", 0}}}, {"grey", {{"reflectance", 0.5}}}}},
          {"surfaces", std::move(surfaces)},
          {"lights", std::move(lights)},
          {"probes", std::move(probes)},
          {"meshing", {{"max_patch_area", 4}, {"refine_direct", false}}},
          {"solver", {{"method", method}}}};
}

// A room [0,4]×[0,4]×[0,3] of `material` with an unglazed roof opening [1.5,2.5]² in its ceiling.
inline json room_with_roof_opening(const std::string& material) {
  return json::array({rectangle("floor", material, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}),
                      rectangle("ceiling south", material, {0, 0, 3}, {0, 1.5, 0}, {4, 0, 0}),
                      rectangle("ceiling north", material, {0, 2.5, 3}, {0, 1.5, 0}, {4, 0, 0}),
                      rectangle("ceiling west", material, {0, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0}),
                      rectangle("ceiling east", material, {2.5, 1.5, 3}, {0, 1, 0}, {1.5, 0, 0}),
                      rectangle("south", material, {0, 0, 0}, {0, 0, 3}, {4, 0, 0}),
                      rectangle("north", material, {0, 4, 0}, {4, 0, 0}, {0, 0, 3}),
                      rectangle("west", material, {0, 0, 0}, {0, 4, 0}, {0, 0, 3}),
                      rectangle("east", material, {4, 0, 0}, {0, 0, 3}, {0, 4, 0})});
}

inline json solve_json(const json& scene) {
  DecodeResult decoded = decode_scene(scene.dump());
  if (!decoded.ok()) throw std::runtime_error(format_errors(decoded.errors));
  const Solution sol = solve(*decoded.scene);
  return json::parse(encode_result(*decoded.scene, sol, make_report(*decoded.scene, sol)));
}

inline json probe(const std::string& name, const Point3& p, const Vector3& n) {
  return {{"name", name}, {"position", triple(p)}, {"normal", triple(n)}};
}

inline json sky(json type, const std::string& scale_key, double scale) {
  return {{"type", "sky"}, {"cie_type", std::move(type)}, {scale_key, scale}, {"up", {0, 0, 1}}};
}

}  // namespace lambert::test::daylight
