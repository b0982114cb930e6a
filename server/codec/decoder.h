// The scene decoder's core, shared by every room of server/codec/: typed readers that report their
// own errors with the JSON pointer of the offending value, error and warning collection, and the
// pointer and message helpers. The rooms (spectra, materials, surfaces, lights, probes, options)
// are free functions that take a Decoder&; the walk that calls them is server/scene_codec.cpp.
//
// Every reader returns nullopt / false / nullptr after reporting, so a room reads on and reports
// every problem of the document in one pass (SPEC §1: strict and exhaustive).
#pragma once

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/scene_codec.h"
#include "solver/scene.h"

namespace lambert::codec {

using json = nlohmann::json;
using Keys = std::vector<std::string_view>;

constexpr double kMaxCoordinate = 1e9;    // |x| in scene units
constexpr double kMaxLobeExponent = 1e6;  // Phong emission lobes and cos^m light lobes
constexpr double kDegree = kPi / 180.0;

// ---- text and pointer helpers ----------------------------------------------------------------

// Shortest round-trip form of a double ("1.2", "1e+300").
std::string num(double v);
// 'text' in quotes, cut to 64 bytes for messages.
std::string quote_text(std::string_view s);
// RFC 6901 pointers: base + "/" + escaped key, base + "/" + index.
std::string key_ptr(const std::string& base, std::string_view key);
std::string index_ptr(const std::string& base, std::size_t index);
// "an object", "a number", ... for "expected X, got Y" messages.
std::string a_type(const json& j);
// Levenshtein distance (insertions, deletions and substitutions of one byte each), or limit + 1 when
// it exceeds `limit`: only the band |i - j| <= limit of the table is filled, O((|a| + |b|) limit).
std::size_t edit_distance(std::string_view a, std::string_view b, std::size_t limit);
// "; did you mean 'x'?" for the closest candidate within edit distance 2, else "". Cheap whatever the
// scene: the word is skipped beyond 64 bytes, at most kMaxSuggestionCandidates candidates are looked
// at, and each costs O(length) (a scene may name 10⁵ materials, each misspelt).
inline constexpr std::size_t kMaxSuggestionCandidates = 1000;
template <typename Range>
std::string suggestion(std::string_view word, const Range& candidates) {
  if (word.size() > 64) return "";
  std::size_t best = 3, looked = 0;
  std::string_view best_word;
  for (const auto& c : candidates) {
    if (++looked > kMaxSuggestionCandidates) break;
    const std::string_view cand(c);
    const std::size_t d = edit_distance(word, cand, best - 1);
    if (d < best) best = d, best_word = cand;
  }
  return best_word.empty() ? "" : "; did you mean '" + std::string(best_word) + "'?";
}
// "a, b or c" with last_sep " or ".
std::string join(const std::vector<std::string_view>& words, std::string_view last_sep);
bool is_one_of(std::string_view key, std::initializer_list<std::string_view> keys);

// [x, y, z] of finite numbers (and within kMaxCoordinate for a coordinate), without building
// pointer strings: the fast path of big inline meshes. nullopt when anything is wrong.
std::optional<Vector3> valid_triple(const json& j, bool coordinate);
// |x|, |y| and |z| within kMaxCoordinate (false for NaN).
inline bool within_coordinate_limit(const Point3& v) {
  return std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
         std::abs(v.z) <= kMaxCoordinate;
}
// Direction of a vector of any finite magnitude; nullopt for the zero vector.
std::optional<Vector3> unit_vector(const Vector3& v);

// ---- the decoder -----------------------------------------------------------------------------

class Decoder {
 public:
  // prior_errors: what the parse already found (duplicate keys), reported first, and how many more
  // it counted without listing them.
  Decoder(const FileAccess& files, const SceneLimits& limits, std::vector<DecodeError> prior_errors,
          std::size_t omitted_prior = 0);

  // -- reporting: the first kMaxListedErrors errors are kept (shortened: bounded_error), the rest
  // counted; warnings likewise, the rest summed up in a last warning.
  void error(std::string pointer, std::string message);
  // Whether the next error will be listed (not only counted): skip costly messages when not.
  bool listing() const { return errors_.size() < kMaxListedErrors; }
  void warn(const std::string& pointer, const std::string& text);

  // -- typed access; each reports its own error and returns nullopt/false on failure
  bool object(const json& j, const std::string& p, const Keys& allowed);
  void unknown_keys(const json& j, const std::string& p, const Keys& allowed);
  const json* member(const json& obj, std::string_view key) const;
  const json* required(const json& obj, const std::string& p, std::string_view key);
  std::optional<double> number(const json& j, const std::string& p);
  std::optional<double> number_in(const json& j, const std::string& p, double lo, bool lo_closed,
                                  double hi, bool hi_closed);
  std::optional<long long> whole(const json& j, const std::string& p, long long lo, long long hi);
  std::optional<std::string> string(const json& j, const std::string& p);
  std::optional<bool> boolean(const json& j, const std::string& p);
  const json* array(const json& j, const std::string& p, std::size_t min_size = 0);
  std::optional<Vector3> triple(const json& j, const std::string& p, bool coordinate);
  std::optional<Point3> point(const json& j, const std::string& p);
  std::optional<Vector3> direction(const json& j, const std::string& p);
  // The optional "name" of a surface or probe (default_name when absent), checked unique among
  // names (name -> pointer of its first use); what is "a surface" or "a probe" in the message.
  std::string unique_name(const json& j, const std::string& p, std::string default_name,
                          std::map<std::string, std::string>& names, std::string_view what);

  Point3 metres(const Point3& q) const {  // scene units -> metres
    return {q.x * scene_.unit_m, q.y * scene_.unit_m, q.z * scene_.unit_m};
  }

  // -- what the rooms fill in and look up
  Scene& scene() { return scene_; }
  const FileAccess& files() const { return files_; }
  const SceneLimits& limits() const { return limits_; }
  // The scene's wavelength grid; nullptr when the spectrum section is invalid (spectra are then
  // checked but not sampled).
  const WavelengthGrid* grid() const { return grid_ ? &*grid_ : nullptr; }
  void set_grid(WavelengthGrid grid);
  std::map<std::string, int>& material_index() { return material_index_; }
  void add_light(Light light, const std::string& p);
  // Luminaire names (name -> pointer of its first use), and the photometric files read so far (by
  // where they came from), so that a file sixty luminaires share is read and reported once.
  std::map<std::string, std::string>& luminaire_names() { return luminaire_names_; }
  std::map<std::string, std::shared_ptr<const LuminairePhotometry>>& photometry_files() { return photometry_files_; }

  // The Scene when nothing was reported (reduced to RGB in rgb mode), else the errors.
  DecodeResult finish();
  // The errors so far and no Scene, for a document that is not even an object.
  DecodeResult reject() { return {std::nullopt, std::move(errors_), dropped_errors_}; }

 private:
  const FileAccess& files_;
  const SceneLimits& limits_;
  Scene scene_;
  std::optional<WavelengthGrid> grid_;
  std::map<std::string, int> material_index_;  // material name -> index into scene_.materials
  std::map<std::string, std::string> luminaire_names_;
  std::map<std::string, std::shared_ptr<const LuminairePhotometry>> photometry_files_;
  std::vector<DecodeError> errors_;
  std::size_t dropped_errors_ = 0, dropped_warnings_ = 0;
};

}  // namespace lambert::codec
