// Scenes and View3D files (tests/fuzz/entries.h): decode_scene, which `lambert check`, `lambert solve`
// and POST /v1/solve call on the JSON text, and vs3_scene, which `lambert viewfactors` calls on a
// .vs3 file's text. Both need the codec (and through it the solver), so they share this file.
#include <string>

#include "server/scene_codec.h"
#include "server/viewfactors/vs3_scene.h"
#include "tests/fuzz/entries.h"

namespace lambert::fuzz {

namespace {

// scene_codec.h's promise that a report is bounded whatever the input: at most kMaxListedErrors
// errors, each pointer and message at most kMaxErrorTextBytes, and a message for every error.
std::string broken_report(const DecodeResult& r) {
  if (r.errors.size() > kMaxListedErrors) return std::to_string(r.errors.size()) + " errors listed";
  if (r.omitted_errors > 0 && r.errors.size() < kMaxListedErrors) return "errors omitted before the list is full";
  for (const DecodeError& e : r.errors) {
    if (e.message.empty()) return "an error without a message at '" + e.pointer + "'";
    if (e.pointer.size() > kMaxErrorTextBytes || e.message.size() > kMaxErrorTextBytes)
      return "an error of " + std::to_string(e.pointer.size() + e.message.size()) + " bytes";
  }
  return {};
}

}  // namespace

Outcome decode_scene_bytes(std::string_view bytes) {
  const DecodeResult r = decode_scene(std::string(bytes), FileAccess{FileAccess::Policy::Deny, {}, {}});
  if (r.ok() != r.scene.has_value()) return {Verdict::kBroken, "a scene and errors together, or neither"};
  if (r.ok()) return {Verdict::kAccepted, {}};
  std::string broken = broken_report(r);
  if (!broken.empty()) return {Verdict::kBroken, std::move(broken)};
  // As `lambert check` reports it.
  return {Verdict::kRefused, std::string(kInputName) + ": invalid scene\n" + format_errors(r)};
}

Outcome read_vs3_bytes(std::string_view bytes) {
  const Vs3SceneResult r = vs3_scene(bytes, kInputName);
  if (r.scene.has_value() == !r.errors.empty()) return {Verdict::kBroken, "a scene and errors together, or neither"};
  if (r.scene) return {Verdict::kAccepted, {}};
  for (const std::string& e : r.errors)
    if (e.rfind(kInputName, 0) != 0) return {Verdict::kRefused, e};  // is_finding: the file is not named
  return {Verdict::kRefused, r.errors.front()};
}

}  // namespace lambert::fuzz
