// Scene JSON (SPEC §1) -> validated lambert::Scene. Strict: unknown keys, wrong types, NaN/Inf,
// out-of-range values, non-planar or self-intersecting polygons and degenerate meshes are errors, each
// with the JSON pointer (RFC 6901) of the offending value. Nothing is silently clamped or defaulted
// where the user wrote something we do not understand.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "solver/scene.h"

namespace lambert {

struct DecodeError {
  std::string pointer;   // e.g. "/materials/red/reflectance/values/3"; "" for the whole document
  std::string message;   // e.g. "1.2 is outside [0, 1]"
};

// Where "file" surfaces may be read from.
struct FileAccess {
  enum class Policy { Deny, Anywhere, UnderRoot } policy = Policy::Anywhere;
  std::filesystem::path base_dir;   // Anywhere: relative paths resolve against this (the scene's dir)
  std::filesystem::path root;       // UnderRoot: paths must be relative, without "..", resolve
                                    // against root, and lie inside it once symlinks are followed
};

struct DecodeResult {
  std::optional<Scene> scene;       // present iff errors is empty
  std::vector<DecodeError> errors;
  bool ok() const { return errors.empty(); }
};

DecodeResult decode_scene(const std::string& json_text, const FileAccess& files = {});

// "pointer: message" lines, one per error.
std::string format_errors(const std::vector<DecodeError>& errors);

}  // namespace lambert
