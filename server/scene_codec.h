// Scene JSON (SPEC §1) -> validated lambert::Scene. Strict: unknown keys, wrong types, NaN/Inf,
// out-of-range values, non-planar or self-intersecting polygons and degenerate meshes are errors, each
// with the JSON pointer (RFC 6901) of the offending value. Nothing is silently clamped or defaulted
// where the user wrote something we do not understand.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/scene_limits.h"
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

// What a decode reports is bounded whatever the input: at most kMaxListedErrors errors are listed
// (the rest only counted), and a pointer or message longer than kMaxErrorTextBytes is shortened in
// the middle ("... [N bytes left out] ..."), so a 2 MB scene cannot make a 500 MB error report.
inline constexpr std::size_t kMaxListedErrors = 100;
inline constexpr std::size_t kMaxErrorTextBytes = 512;

struct DecodeResult {
  std::optional<Scene> scene;       // present iff errors is empty
  std::vector<DecodeError> errors;  // the first kMaxListedErrors problems, in document order
  std::size_t omitted_errors = 0;   // problems found beyond those listed
  bool ok() const { return errors.empty(); }
  std::size_t error_count() const { return errors.size() + omitted_errors; }
};

// `limits` (server/scene_limits.h): the probe points and what the scene alone makes of the spectral
// values and the result's size are checked here; the patch budget at solve time.
DecodeResult decode_scene(const std::string& json_text, const FileAccess& files = {},
                          const SceneLimits& limits = {});

// "pointer: message" lines, one per error.
std::string format_errors(const std::vector<DecodeError>& errors);
// The same, and a last line with the count of the errors not listed, if any.
std::string format_errors(const DecodeResult& result);

// `text` if it has at most `max_bytes` bytes; else its head and tail, cut at UTF-8 boundaries, around
// " ... [N bytes left out] ... ", in at most max_bytes bytes.
std::string shorten_for_report(std::string_view text, std::size_t max_bytes = kMaxErrorTextBytes);
// The pieces of it: the longest head or tail of `text` of at most max_bytes that ends or starts on a
// UTF-8 boundary, and head + " ... [N bytes left out] ... " + tail (kElisionMarkBytes at most between).
inline constexpr std::size_t kElisionMarkBytes = 48;
std::string_view utf8_prefix(std::string_view text, std::size_t max_bytes);
std::string_view utf8_suffix(std::string_view text, std::size_t max_bytes);
std::string elided(std::string_view head, std::size_t left_out_bytes, std::string_view tail);
// An error whose pointer and message are shortened for a report.
DecodeError bounded_error(std::string pointer, std::string message);

}  // namespace lambert
