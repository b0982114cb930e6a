// The decoder's core: message helpers, typed readers and error collection (server/codec/decoder.h).
#include "server/codec/decoder.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>

#include "solver/rgb_model.h"

namespace lambert::codec {

// ---- text and pointer helpers ----------------------------------------------------------------

std::string num(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// Cuts user text for messages without splitting a UTF-8 sequence (the text is valid UTF-8: the
// pre-scan guarantees it, and a message must stay valid UTF-8 to be serialised again).
std::string quote_text(std::string_view s) {
  constexpr std::size_t kMax = 64;
  std::string out = "'";
  if (s.size() <= kMax) return out.append(s).append("'");
  std::size_t cut = kMax;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return out.append(s.substr(0, cut)).append("...'");
}

// RFC 6901: "~" -> "~0", "/" -> "~1".
static std::string escape_token(std::string_view token) {
  std::string out;
  out.reserve(token.size());
  for (char c : token) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}
std::string key_ptr(const std::string& base, std::string_view key) {
  return base + "/" + escape_token(key);
}
std::string index_ptr(const std::string& base, std::size_t index) {
  return base + "/" + std::to_string(index);
}

std::string a_type(const json& j) {
  switch (j.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    default: return j.is_number() ? "a number" : std::string("a ") + j.type_name();
  }
}

std::size_t edit_distance(std::string_view a, std::string_view b, std::size_t limit) {
  if (a.size() > b.size()) std::swap(a, b);
  if (b.size() - a.size() > limit) return limit + 1;
  constexpr std::size_t kFar = std::numeric_limits<std::size_t>::max() / 2;
  // row[j] = distance(a[0, i), b[0, j)); cells outside the band stay "far".
  std::vector<std::size_t> row(b.size() + 1, kFar), next(b.size() + 1, kFar);
  for (std::size_t j = 0; j <= std::min(b.size(), limit); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    const std::size_t lo = i > limit ? i - limit : 0, hi = std::min(b.size(), i + limit);
    if (lo == 0) next[0] = i;
    else next[lo - 1] = kFar;  // the band moved right: what this buffer held there is stale
    std::size_t best = next[0];
    for (std::size_t j = std::max<std::size_t>(lo, 1); j <= hi; ++j) {
      next[j] = std::min({row[j] + 1, next[j - 1] + 1, row[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      best = std::min(best, next[j]);
    }
    if (best > limit) return limit + 1;
    row.swap(next);
  }
  return std::min(row[b.size()], limit + 1);
}

std::string join(const std::vector<std::string_view>& words, std::string_view last_sep) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += (i + 1 == words.size()) ? std::string(last_sep) : std::string(", ");
    out += words[i];
  }
  return out;
}

bool is_one_of(std::string_view key, std::initializer_list<std::string_view> keys) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::optional<Vector3> valid_triple(const json& j, bool coordinate) {
  if (!j.is_array() || j.size() != 3) return std::nullopt;
  std::array<double, 3> c{};
  for (std::size_t k = 0; k < 3; ++k) {
    if (!j[k].is_number()) return std::nullopt;
    c[k] = j[k].get<double>();
    if (!std::isfinite(c[k]) || (coordinate && std::abs(c[k]) > kMaxCoordinate)) return std::nullopt;
  }
  return Vector3{c[0], c[1], c[2]};
}

// Scaled first so that 1e300 or 1e-320 components neither overflow nor underflow.
std::optional<Vector3> unit_vector(const Vector3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0)) return std::nullopt;
  const Vector3 w = v / m;
  return w / length(w);
}

// ---- reporting --------------------------------------------------------------------------------

Decoder::Decoder(const FileAccess& files, const SceneLimits& limits, std::vector<DecodeError> prior_errors,
                 std::size_t omitted_prior)
    : files_(files), limits_(limits), errors_(std::move(prior_errors)), dropped_errors_(omitted_prior) {}

void Decoder::error(std::string pointer, std::string message) {
  if (errors_.size() < kMaxListedErrors) errors_.push_back(bounded_error(std::move(pointer), std::move(message)));
  else ++dropped_errors_;
}

void Decoder::warn(const std::string& pointer, const std::string& text) {
  if (scene_.warnings.size() >= kMaxListedErrors) {
    ++dropped_warnings_;
    return;
  }
  scene_.warnings.push_back(shorten_for_report((pointer.empty() ? std::string("(document)") : pointer) + ": " + text,
                                               2 * kMaxErrorTextBytes));
}

// ---- typed access -----------------------------------------------------------------------------

bool Decoder::object(const json& j, const std::string& p, const Keys& allowed) {
  if (!j.is_object()) {
    error(p, "expected an object, got " + a_type(j));
    return false;
  }
  unknown_keys(j, p, allowed);
  return true;
}

void Decoder::unknown_keys(const json& j, const std::string& p, const Keys& allowed) {
  for (const auto& [k, v] : j.items()) {
    if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
    error(key_ptr(p, k), "unknown key " + quote_text(k) + (listing() ? suggestion(k, allowed) : ""));
  }
}

const json* Decoder::member(const json& obj, std::string_view key) const {
  auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}

const json* Decoder::required(const json& obj, const std::string& p, std::string_view key) {
  const json* v = member(obj, key);
  if (!v) error(p, "missing required key '" + std::string(key) + "'");
  return v;
}

std::optional<double> Decoder::number(const json& j, const std::string& p) {
  if (!j.is_number()) {
    error(p, "expected a number, got " + a_type(j));
    return std::nullopt;
  }
  const double v = j.get<double>();
  if (!std::isfinite(v)) {  // e.g. 1e400, which the parser turns into infinity
    error(p, "number is not finite (out of the double range)");
    return std::nullopt;
  }
  return v;
}

std::optional<double> Decoder::number_in(const json& j, const std::string& p, double lo,
                                         bool lo_closed, double hi, bool hi_closed) {
  auto v = number(j, p);
  if (!v) return v;
  const bool above = lo_closed ? *v >= lo : *v > lo;
  const bool below = hi_closed ? *v <= hi : *v < hi;
  if (above && below) return v;
  if (std::isinf(hi)) error(p, num(*v) + " must be " + (lo_closed ? ">= " : "> ") + num(lo));
  else
    error(p, num(*v) + " is outside " + (lo_closed ? "[" : "(") + num(lo) + ", " + num(hi) +
                 (hi_closed ? "]" : ")"));
  return std::nullopt;
}

std::optional<long long> Decoder::whole(const json& j, const std::string& p, long long lo,
                                        long long hi) {
  // get<int>() would truncate 1.5 to 1 (STACK P10); check wholeness on the double ourselves.
  auto v = number(j, p);
  if (!v) return std::nullopt;
  if (std::trunc(*v) != *v) {
    error(p, "expected a whole number, got " + num(*v));
    return std::nullopt;
  }
  if (*v < static_cast<double>(lo) || *v > static_cast<double>(hi)) {
    error(p, num(*v) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return std::nullopt;
  }
  return static_cast<long long>(*v);
}

std::optional<std::string> Decoder::string(const json& j, const std::string& p) {
  if (!j.is_string()) {
    error(p, "expected a string, got " + a_type(j));
    return std::nullopt;
  }
  return j.get<std::string>();
}

std::optional<bool> Decoder::boolean(const json& j, const std::string& p) {
  if (!j.is_boolean()) {
    error(p, "expected a boolean (true or false), got " + a_type(j));
    return std::nullopt;
  }
  return j.get<bool>();
}

const json* Decoder::array(const json& j, const std::string& p, std::size_t min_size) {
  if (!j.is_array()) {
    error(p, "expected an array, got " + a_type(j));
    return nullptr;
  }
  if (j.size() < min_size) {
    error(p, min_size == 1 ? std::string("must not be empty")
                           : "needs at least " + std::to_string(min_size) + " entries, got " +
                                 std::to_string(j.size()));
    return nullptr;
  }
  return &j;
}

std::optional<Vector3> Decoder::triple(const json& j, const std::string& p, bool coordinate) {
  if (auto v = valid_triple(j, coordinate)) return v;
  if (!j.is_array() || j.size() != 3) {
    error(p, j.is_array() ? "expected 3 numbers [x, y, z], got " + std::to_string(j.size())
                          : "expected an array of 3 numbers [x, y, z], got " + a_type(j));
    return std::nullopt;
  }
  std::array<double, 3> c{};
  bool ok = true;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string pk = index_ptr(p, k);
    auto v = number(j[k], pk);
    if (!v) {
      ok = false;
    } else if (coordinate && std::abs(*v) > kMaxCoordinate) {
      error(pk, num(*v) + " is beyond the coordinate limit of 1e9 scene units");
      ok = false;
    } else {
      c[k] = *v;
    }
  }
  return ok ? std::optional<Vector3>(Vector3{c[0], c[1], c[2]}) : std::nullopt;
}

std::optional<Point3> Decoder::point(const json& j, const std::string& p) {
  auto v = triple(j, p, true);
  return v ? std::optional<Point3>(to_point(*v)) : std::nullopt;
}

std::optional<Vector3> Decoder::direction(const json& j, const std::string& p) {
  auto v = triple(j, p, false);
  if (!v) return std::nullopt;
  auto u = unit_vector(*v);
  if (!u) error(p, "must not be the zero vector");
  return u;
}

std::string Decoder::unique_name(const json& j, const std::string& p, std::string default_name,
                                 std::map<std::string, std::string>& names, std::string_view what) {
  std::string name = std::move(default_name);
  std::string name_ptr = p;
  if (const json* n = member(j, "name")) {
    name_ptr = p + "/name";
    if (auto s = string(*n, name_ptr)) name = *s;
  }
  if (auto [it, fresh] = names.emplace(name, name_ptr); !fresh)
    error(name_ptr, "duplicate " + std::string(what) + " name " + quote_text(name) +
                        " (first used at " + it->second + ")");
  return name;
}

// ---- the scene being built --------------------------------------------------------------------

void Decoder::set_grid(WavelengthGrid grid) {
  scene_.grid = grid;
  grid_ = std::move(grid);
}

void Decoder::add_light(Light light, const std::string& p) {
  scene_.lights.push_back(std::move(light));
  scene_.light_pointers.push_back(p);
}

DecodeResult Decoder::finish() {
  if (dropped_warnings_ > 0)
    scene_.warnings.push_back("(document): " + std::to_string(dropped_warnings_) + " more warnings not listed");
  if (errors_.empty() && scene_.mode == SpectrumMode::Rgb) reduce_scene_to_rgb(scene_);
  DecodeResult result;
  if (errors_.empty()) result.scene = std::move(scene_);
  result.errors = std::move(errors_);
  result.omitted_errors = dropped_errors_;
  return result;
}

}  // namespace lambert::codec
