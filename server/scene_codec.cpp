// Scene JSON (SPEC §1) -> lambert::Scene. nlohmann_json lives only in the codecs.
//
// The decoder is strict and exhaustive: it walks the whole document, records every problem as
// {JSON pointer, message} and produces a Scene only when there were none. Order of work:
//   1. a byte scan (UTF-8 validity, nesting depth <= 256) so hostile input never reaches the parser;
//   2. a SAX parse into a DOM that also reports duplicate object keys (nlohmann keeps the last one
//      silently);
//   3. the schema walk below. Lengths are converted to metres at the very end of each geometry,
//      spectra are sampled on the scene's grid and photometric totals are applied here, so the solver
//      sees absolute spectral quantities in SI units only.
#include "server/scene_codec.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string_view>
#include <system_error>
#include <utility>

#include <nlohmann/json.hpp>

#include "mesh/mesh_ops.h"
#include "solver/rgb_model.h"

namespace lambert {
namespace {

using json = nlohmann::json;

constexpr int kMaxNestingDepth = 256;
constexpr double kMaxCoordinate = 1e9;          // |x| in scene units
constexpr std::size_t kMaxSpectrumSamples = 10000;
constexpr double kMaxLobeExponent = 1e6;
constexpr long long kMaxProbeGridSide = 10000;
constexpr long long kMaxProbeGridPoints = 1000000;  // memory guard for one grid (24 MB of points)
constexpr std::size_t kMaxErrors = 500;         // beyond this only a count is reported
constexpr std::size_t kMaxListedPerMesh = 20;   // degenerate triangles listed per surface
constexpr double kDegree = kPi / 180.0;

// ---- small text helpers ---------------------------------------------------------------------

// Shortest round-trip form of a double ("1.2", "1e+300").
std::string num(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// Cuts user text for messages without splitting a UTF-8 sequence (the text is valid UTF-8: the
// pre-scan guarantees it, and a message must stay valid UTF-8 to be serialised again).
std::string quote_text(std::string_view s) {
  constexpr std::size_t kMax = 64;
  if (s.size() <= kMax) return "'" + std::string(s) + "'";
  std::size_t cut = kMax;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return "'" + std::string(s.substr(0, cut)) + "...'";
}

// RFC 6901: "~" -> "~0", "/" -> "~1".
std::string escape_token(std::string_view token) {
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

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// "; did you mean 'x'?" for the closest candidate within edit distance 2, else "".
template <typename Range>
std::string suggestion(std::string_view word, const Range& candidates) {
  if (word.size() > 64) return "";
  std::size_t best = 3;
  std::string_view best_word;
  for (const auto& c : candidates) {
    const std::string_view cand(c);
    const std::size_t d = edit_distance(word, cand);
    if (d < best) best = d, best_word = cand;
  }
  return best_word.empty() ? "" : "; did you mean '" + std::string(best_word) + "'?";
}

std::string join(const std::vector<std::string_view>& words, std::string_view last_sep) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += (i + 1 == words.size()) ? std::string(last_sep) : std::string(", ");
    out += words[i];
  }
  return out;
}

// ---- 1. byte scan -----------------------------------------------------------------------------

// Length of the well-formed UTF-8 sequence starting at s (RFC 3629 table: no overlong forms, no
// surrogates, nothing above U+10FFFF), or 0 if it is not well formed.
std::size_t utf8_sequence_length(const unsigned char* s, std::size_t available) {
  const unsigned char c = s[0];
  std::size_t len = 0;
  unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) len = 2;
  else if (c == 0xE0) len = 3, lo = 0xA0;
  else if ((c >= 0xE1 && c <= 0xEC) || c == 0xEE || c == 0xEF) len = 3;
  else if (c == 0xED) len = 3, hi = 0x9F;
  else if (c == 0xF0) len = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) len = 4;
  else if (c == 0xF4) len = 4, hi = 0x8F;
  else return 0;
  if (available < len || s[1] < lo || s[1] > hi) return 0;
  for (std::size_t k = 2; k < len; ++k)
    if (s[k] < 0x80 || s[k] > 0xBF) return 0;
  return len;
}

// Rejects invalid UTF-8 anywhere and brackets nested deeper than kMaxNestingDepth (outside strings),
// in one linear pass with no recursion, before any parser or destructor sees the text.
std::optional<DecodeError> prescan(std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    if (c >= 0x80) {
      const std::size_t len = utf8_sequence_length(s + i, n - i);
      if (len == 0) return DecodeError{"", "invalid UTF-8 at byte offset " + std::to_string(i)};
      i += len;
      escaped = false;
      continue;
    }
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNestingDepth)
        return DecodeError{"", "nesting deeper than " + std::to_string(kMaxNestingDepth) +
                                   " levels at byte offset " + std::to_string(i)};
    } else if (c == ']' || c == '}') {
      --depth;  // unbalanced input is the parser's to report, with its line and column
    }
    ++i;
  }
  return std::nullopt;
}

// ---- 2. parse -----------------------------------------------------------------------------------

// Builds the DOM like nlohmann's own DOM parser and additionally reports duplicate keys.
class DomBuilder final : public json::json_sax_t {
 public:
  explicit DomBuilder(json& root) : root_(root) {}

  std::vector<DecodeError> duplicate_keys;
  std::string parse_error_message;
  std::string parse_error_pointer;  // set when the error belongs to one value (number overflow)

  bool null() override { return add(json(nullptr)); }
  bool boolean(bool v) override { return add(json(v)); }
  bool number_integer(number_integer_t v) override { return add(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return add(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return add(json(v)); }
  bool string(string_t& v) override { return add(json(std::move(v))); }
  bool binary(binary_t&) override { return false; }  // never produced by JSON text

  bool start_object(std::size_t) override {
    frames_.push_back({add_value(json::object()), true, {}});
    return true;
  }
  bool key(string_t& k) override {
    Frame& f = frames_.back();
    if (f.value->contains(k) && duplicate_keys.size() < kMaxErrors)
      duplicate_keys.push_back({key_ptr(path(), k), "duplicate key " + quote_text(k) +
                                                        " (JSON keeps only one of them)"});
    slot_ = &(*f.value)[k];
    f.key = std::move(k);
    return true;
  }
  bool end_object() override { frames_.pop_back(); return true; }
  bool start_array(std::size_t) override {
    frames_.push_back({add_value(json::array()), false, {}});
    return true;
  }
  bool end_array() override { frames_.pop_back(); return true; }
  bool parse_error(std::size_t, const std::string&, const json::exception& ex) override {
    parse_error_message = ex.what();
    // out_of_range.406: a number like 1e400 that does not fit a double. The text is otherwise
    // well formed, so the value's pointer is known: the next member or element being parsed.
    if (ex.id == 406 && !frames_.empty()) {
      const Frame& f = frames_.back();
      parse_error_pointer = f.is_object ? key_ptr(path(), f.key) : index_ptr(path(), f.value->size());
    }
    return false;
  }

 private:
  struct Frame {
    json* value;       // an object or array still being filled (pointers stay valid: siblings are
    bool is_object;    // only appended after this container is closed)
    std::string key;   // object: the key of the member being parsed
  };

  bool add(json&& v) { add_value(std::move(v)); return true; }
  json* add_value(json&& v) {
    if (frames_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    Frame& f = frames_.back();
    if (f.is_object) {
      *slot_ = std::move(v);
      return slot_;
    }
    f.value->push_back(std::move(v));
    return &f.value->back();
  }
  // Pointer of the innermost open container.
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      p = f.is_object ? key_ptr(p, f.key) : index_ptr(p, f.value->size() - 1);
    }
    return p;
  }

  json& root_;
  std::vector<Frame> frames_;
  json* slot_ = nullptr;
};

// ---- geometry helpers -----------------------------------------------------------------------

// sin and cos of an angle in degrees, exact at multiples of 90° (so that "rotate_deg": [90, 0, 0]
// maps axes onto axes without 6e-17 residues).
std::pair<double, double> sincos_deg(double deg) {
  double r = std::fmod(deg, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0) return {0, 1};
  if (r == 90) return {1, 0};
  if (r == 180) return {0, -1};
  if (r == 270) return {-1, 0};
  return {std::sin(r * kDegree), std::cos(r * kDegree)};
}

struct Transform {
  Vector3 scale{1, 1, 1};
  Vector3 rotate_deg{0, 0, 0};
  Vector3 translate{0, 0, 0};
  bool flips() const { return scale.x * scale.y * scale.z < 0; }
  // p' = Rz Ry Rx (s ⊙ p) + t: scale, then rotate about x, y, z in that order, then translate.
  Point3 apply(const Point3& p) const {
    Vector3 v{p.x * scale.x, p.y * scale.y, p.z * scale.z};
    const auto [sx, cx] = sincos_deg(rotate_deg.x);
    v = {v.x, cx * v.y - sx * v.z, sx * v.y + cx * v.z};
    const auto [sy, cy] = sincos_deg(rotate_deg.y);
    v = {cy * v.x + sy * v.z, v.y, -sy * v.x + cy * v.z};
    const auto [sz, cz] = sincos_deg(rotate_deg.z);
    v = {cz * v.x - sz * v.y, sz * v.x + cz * v.y, v.z};
    return to_point(v + translate);
  }
};

// Direction of a vector of any finite magnitude (scaled first so that 1e300 or 1e-320 components
// neither overflow nor underflow).
std::optional<Vector3> unit_vector(const Vector3& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0)) return std::nullopt;
  const Vector3 w = v / m;
  return w / length(w);
}

double mesh_area(const TriangleMesh& mesh) {
  double a = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) a += mesh.triangle(t).area();
  return a;
}

// ---- photometric totals ----------------------------------------------------------------------

struct TotalKind {
  std::string_view key;
  bool luminous;  // luminous_integral (683 Σ w ȳ s) rather than integrate (Σ w s)
};
constexpr std::array<TotalKind, 10> kTotalKinds = {{
    {"luminous_intensity_cd", true},   {"radiant_intensity_W_sr", false},
    {"luminous_flux_lm", true},        {"radiant_flux_W", false},
    {"illuminance_lx", true},          {"irradiance_W_m2", false},
    {"luminous_exitance_lm_m2", true}, {"radiant_exitance_W_m2", false},
    {"luminance_cd_m2", true},         {"radiance_W_m2_sr", false},
}};

struct Total {
  std::string_view key;
  bool luminous = false;
  double value = 0;
};

bool is_one_of(std::string_view key, std::initializer_list<std::string_view> keys) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// ---- 3. the schema walk ---------------------------------------------------------------------

using Keys = std::vector<std::string_view>;

Keys with_totals(Keys keys) {
  for (const auto& t : kTotalKinds) keys.push_back(t.key);
  return keys;
}

class Decoder {
 public:
  explicit Decoder(const FileAccess& files) : files_(files) {}

  DecodeResult run(const json& doc, std::vector<DecodeError> prior_errors);

 private:
  // -- reporting
  void error(std::string pointer, std::string message) {
    if (errors_.size() < kMaxErrors) errors_.push_back({std::move(pointer), std::move(message)});
    else ++dropped_errors_;
  }
  void warn(const std::string& pointer, const std::string& text) {
    scene_.warnings.push_back((pointer.empty() ? std::string("(document)") : pointer) + ": " + text);
  }

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
  std::optional<Point3> point(const json& j, const std::string& p) {
    auto v = triple(j, p, true);
    return v ? std::optional<Point3>(to_point(*v)) : std::nullopt;
  }
  std::optional<Vector3> direction(const json& j, const std::string& p);
  Point3 metres(const Point3& q) const {  // scene units -> metres
    return {q.x * scene_.unit_m, q.y * scene_.unit_m, q.z * scene_.unit_m};
  }

  // -- sections
  void decode_version(const json& doc);
  void decode_units(const json& doc);
  void decode_grid(const json* spectrum);
  std::optional<WavelengthGrid> decode_rgb_mode(const json& spectrum);
  void decode_materials(const json& doc);
  void decode_surfaces(const json& doc);
  void decode_surface(const json& j, std::size_t i, std::map<std::string, std::string>& names);
  std::optional<TriangleMesh> decode_polygon(const json& j, const std::string& p);
  std::optional<TriangleMesh> decode_inline_mesh(const json& j, const std::string& p);
  std::optional<TriangleMesh> decode_file_mesh(const json& j, const std::string& p);
  std::optional<std::filesystem::path> resolve_file(const std::string& rel, const std::string& p);
  std::optional<Transform> decode_transform(const json& j, const std::string& p);
  void check_mesh_health(const TriangleMesh& mesh, const std::string& p, bool inline_mesh);
  std::optional<Emission> decode_emission(const json& j, const std::string& p,
                                          std::optional<double> area_m2);
  void decode_lights(const json& doc);
  void decode_light(const json& j, std::size_t i);
  void decode_probes(const json& doc);
  void decode_probe(const json& j, std::size_t i, std::map<std::string, std::string>& names);
  void decode_options(const json& doc);

  // -- spectra
  std::optional<SpectrumSpec> spectrum_spec(const json& j, const std::string& p, SpectrumRole role);
  std::optional<std::vector<double>> spectrum(const json& j, const std::string& p,
                                              SpectrumRole role);
  std::optional<Total> total(const json& obj, const std::string& p, const Keys& applicable,
                             std::string_view source);
  bool scale_to_total(std::vector<double>& s, const Total& t, double geometric_factor,
                      const std::string& spectrum_pointer);

  const FileAccess& files_;
  Scene scene_;
  std::optional<WavelengthGrid> grid_;   // empty when the spectrum section is invalid
  std::map<std::string, int> material_index_;
  std::vector<DecodeError> errors_;
  std::size_t dropped_errors_ = 0;
};

// ---------------------------------------------------------------------------------------------

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
    error(key_ptr(p, k), "unknown key " + quote_text(k) + suggestion(k, allowed));
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

// Fast path for the common, valid case (big inline meshes): no pointer strings are built.
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

std::optional<Vector3> Decoder::direction(const json& j, const std::string& p) {
  auto v = triple(j, p, false);
  if (!v) return std::nullopt;
  auto u = unit_vector(*v);
  if (!u) error(p, "must not be the zero vector");
  return u;
}

// ---- top level --------------------------------------------------------------------------------

DecodeResult Decoder::run(const json& doc, std::vector<DecodeError> prior_errors) {
  errors_ = std::move(prior_errors);
  if (!doc.is_object()) {
    error("", "a scene must be a JSON object, got " + a_type(doc));
    return {std::nullopt, std::move(errors_)};
  }
  unknown_keys(doc, "", {"lambert", "name", "description", "units", "spectrum", "materials",
                         "surfaces", "lights", "probes", "meshing", "solver", "output", "expected"});
  decode_version(doc);
  if (const json* v = member(doc, "name"))
    if (auto s = string(*v, "/name")) scene_.name = *s;
  if (const json* v = member(doc, "description")) string(*v, "/description");
  decode_units(doc);
  decode_grid(member(doc, "spectrum"));
  if (grid_) scene_.grid = *grid_;
  decode_materials(doc);
  decode_surfaces(doc);
  decode_lights(doc);
  decode_probes(doc);
  decode_options(doc);
  // Reference values for tests (scenes_test); the solver ignores them, but they must be an object.
  if (const json* v = member(doc, "expected"); v && !v->is_object())
    error("/expected", "expected an object, got " + a_type(*v));

  if (dropped_errors_ > 0)
    errors_.push_back({"", std::to_string(dropped_errors_) + " more errors not shown"});
  if (errors_.empty() && scene_.mode == SpectrumMode::Rgb) reduce_scene_to_rgb(scene_);
  DecodeResult result;
  if (errors_.empty()) result.scene = std::move(scene_);
  result.errors = std::move(errors_);
  return result;
}

void Decoder::decode_version(const json& doc) {
  const json* v = member(doc, "lambert");
  if (!v) return;
  if (!v->is_number()) {
    error("/lambert", "expected a number (the format version), got " + a_type(*v));
    return;
  }
  const double version = v->get<double>();
  if (version != 1) {
    error("/lambert", "unsupported format version " + num(version) +
                          " (this Lambert reads version 1)");
    return;
  }
  scene_.format_version = 1;
}

void Decoder::decode_units(const json& doc) {
  const json* v = member(doc, "units");
  if (!v) return;
  auto u = string(*v, "/units");
  if (!u) return;
  if (*u == "m") scene_.unit_m = 1.0;
  else if (*u == "cm") scene_.unit_m = 0.01;
  else if (*u == "mm") scene_.unit_m = 0.001;
  else error("/units", "unknown unit " + quote_text(*u) + "; expected \"m\", \"cm\" or \"mm\"");
}

void Decoder::decode_grid(const json* spec) {
  const std::string p = "/spectrum";
  if (!spec) {
    grid_ = WavelengthGrid::uniform(380, 780, 5);
    return;
  }
  if (!spec->is_object()) {
    error(p, "expected an object, got " + a_type(*spec));
    return;
  }
  const json* mode = required(*spec, p, "mode");
  if (!mode) {
    unknown_keys(*spec, p, {"mode", "from_nm", "to_nm", "step_nm", "wavelengths_nm"});
    return;
  }
  auto m = string(*mode, p + "/mode");
  if (!m) return;
  if (*m == "rgb") {
    grid_ = decode_rgb_mode(*spec);
    return;
  }
  if (*m != "spectral") {
    error(p + "/mode", "unknown mode " + quote_text(*m) + "; expected \"spectral\" or \"rgb\"");
    return;
  }

  if (const json* list = member(*spec, "wavelengths_nm")) {
    unknown_keys(*spec, p, {"mode", "wavelengths_nm"});
    const std::string pl = p + "/wavelengths_nm";
    if (!array(*list, pl, 1)) return;
    if (list->size() > kMaxSpectrumSamples) {
      error(pl, "has " + std::to_string(list->size()) + " wavelengths; at most " +
                    std::to_string(kMaxSpectrumSamples) + " are allowed");
      return;
    }
    std::vector<double> nm;
    bool ok = true;
    for (std::size_t k = 0; k < list->size(); ++k) {
      const std::string pk = index_ptr(pl, k);
      auto v = number((*list)[k], pk);
      if (!v) { ok = false; continue; }
      if (*v <= 0 || *v > 100000) {
        error(pk, num(*v) + " is outside (0, 100000] nm");
        ok = false;
      } else if (!nm.empty() && ok && *v <= nm.back()) {
        error(pk, "wavelengths must be strictly ascending: " + num(*v) + " follows " +
                      num(nm.back()));
        ok = false;
      }
      nm.push_back(*v);
    }
    if (ok) grid_ = WavelengthGrid::from_list(std::move(nm));
    return;
  }

  unknown_keys(*spec, p, {"mode", "from_nm", "to_nm", "step_nm", "wavelengths_nm"});
  const json* jf = required(*spec, p, "from_nm");
  const json* jt = required(*spec, p, "to_nm");
  const json* js = required(*spec, p, "step_nm");
  std::optional<double> from, to, step;
  if (jf) from = number_in(*jf, p + "/from_nm", 0, false, 100000, true);
  if (jt) to = number_in(*jt, p + "/to_nm", 0, false, 100000, true);
  if (js) step = number_in(*js, p + "/step_nm", 0, false, INFINITY, false);
  if (!from || !to || !step) return;
  if (!(*to > *from)) {
    error(p + "/to_nm", "to_nm (" + num(*to) + ") must be greater than from_nm (" + num(*from) + ")");
    return;
  }
  const double intervals = (*to - *from) / *step;
  if (!(intervals + 1 <= static_cast<double>(kMaxSpectrumSamples))) {
    error(p + "/step_nm", "gives about " + num(std::floor(intervals) + 1) + " samples; at most " +
                              std::to_string(kMaxSpectrumSamples) + " are allowed");
    return;
  }
  grid_ = WavelengthGrid::uniform(*from, *to, *step);
}

// The three-sample RGB model (SPEC §1 "mode": "rgb", solver/rgb_model.h): every spectrum is first
// sampled and photometrically scaled on the fine reduction grid, exactly as in spectral mode; run()
// then reduces the finished scene to the three EBU channels.
std::optional<WavelengthGrid> Decoder::decode_rgb_mode(const json& spec) {
  unknown_keys(spec, "/spectrum", {"mode"});
  scene_.mode = SpectrumMode::Rgb;
  return rgb_reduction_grid();
}

// ---- spectra ----------------------------------------------------------------------------------

std::optional<SpectrumSpec> Decoder::spectrum_spec(const json& j, const std::string& p,
                                                   SpectrumRole role) {
  const bool reflectance = role == SpectrumRole::Reflectance;
  const double hi = reflectance ? 1.0 : INFINITY;
  const char* what = reflectance ? "a reflectance" : "an emission";
  if (j.is_number()) {
    auto v = number_in(j, p, 0, true, hi, true);
    return v ? std::optional<SpectrumSpec>(ConstantSpectrum{*v}) : std::nullopt;
  }
  if (!j.is_object()) {
    error(p, std::string("expected a spectrum (a number or an object), got ") + a_type(j));
    return std::nullopt;
  }
  const Keys all_keys = {"nm", "values", "cie", "blackbody_K", "rgb"};
  std::vector<std::string_view> forms;
  if (j.contains("nm") || j.contains("values")) forms.push_back("nm/values");
  if (j.contains("cie")) forms.push_back("cie");
  if (j.contains("blackbody_K")) forms.push_back("blackbody_K");
  if (j.contains("rgb")) forms.push_back("rgb");
  if (forms.size() != 1) {
    unknown_keys(j, p, all_keys);
    error(p, forms.empty() ? "expected a spectrum: a number or an object with nm/values, cie, "
                             "blackbody_K or rgb"
                           : "give exactly one spectrum form, not " + join(forms, " and "));
    return std::nullopt;
  }
  const std::string_view form = forms.front();

  if (form == "nm/values") {
    unknown_keys(j, p, {"nm", "values"});
    const json* jn = required(j, p, "nm");
    const json* jv = required(j, p, "values");
    if (!jn || !jv) return std::nullopt;
    const bool arrays_ok = array(*jn, p + "/nm", 1) != nullptr;
    if (!array(*jv, p + "/values", 1) || !arrays_ok) return std::nullopt;
    if (jn->size() != jv->size()) {
      error(p + "/values", "has " + std::to_string(jv->size()) + " entries but nm has " +
                               std::to_string(jn->size()));
      return std::nullopt;
    }
    TabulatedSpectrum t;
    bool ok = true;
    for (std::size_t k = 0; k < jn->size(); ++k) {
      const std::string pk = index_ptr(p + "/nm", k);
      auto v = number((*jn)[k], pk);
      if (!v) { ok = false; continue; }
      if (*v <= 0) { error(pk, num(*v) + " must be > 0 nm"); ok = false; }
      else if (!t.nm.empty() && *v <= t.nm.back()) {
        error(pk, "nm must be strictly ascending: " + num(*v) + " follows " + num(t.nm.back()));
        ok = false;
      }
      t.nm.push_back(*v);
    }
    for (std::size_t k = 0; k < jv->size(); ++k) {
      auto v = number_in((*jv)[k], index_ptr(p + "/values", k), 0, true, hi, true);
      if (!v) { ok = false; continue; }
      t.values.push_back(*v);
    }
    return ok ? std::optional<SpectrumSpec>(std::move(t)) : std::nullopt;
  }
  if (form == "cie") {
    unknown_keys(j, p, {"cie"});
    auto name = string(j.at("cie"), p + "/cie");
    if (!name) return std::nullopt;
    if (*name == "D65") return CieSpectrum{CieIlluminant::D65};
    if (*name == "A") return CieSpectrum{CieIlluminant::A};
    if (*name == "E") return CieSpectrum{CieIlluminant::E};
    error(p + "/cie",
          "unknown CIE illuminant " + quote_text(*name) + "; expected \"D65\", \"A\" or \"E\"");
    return std::nullopt;
  }
  if (form == "blackbody_K") {
    unknown_keys(j, p, {"blackbody_K"});
    auto t = number_in(j.at("blackbody_K"), p + "/blackbody_K", 0, false, INFINITY, false);
    return t ? std::optional<SpectrumSpec>(BlackbodySpectrum{*t}) : std::nullopt;
  }
  // rgb
  unknown_keys(j, p, {"rgb"});
  if (!reflectance) {
    error(p + "/rgb", std::string("rgb spectra are only for reflectances; give ") + what +
                          " as a number, nm/values, cie or blackbody_K");
    return std::nullopt;
  }
  const json& jr = j.at("rgb");
  if (!jr.is_array() || jr.size() != 3) {
    error(p + "/rgb", "expected 3 numbers [r, g, b] in [0, 1], got " +
                          (jr.is_array() ? std::to_string(jr.size()) + " entries" : a_type(jr)));
    return std::nullopt;
  }
  RgbReflectanceSpectrum rgb{};
  bool ok = true;
  for (std::size_t k = 0; k < 3; ++k) {
    auto v = number_in(jr[k], index_ptr(p + "/rgb", k), 0, true, 1, true);
    if (v) rgb.rgb[k] = *v;
    else ok = false;
  }
  return ok ? std::optional<SpectrumSpec>(rgb) : std::nullopt;
}

// Validates and samples a spectrum on the scene grid. The sampled values are checked again, since
// smooth RGB upsampling or interpolation must not leave [0, 1] for a reflectance either.
std::optional<std::vector<double>> Decoder::spectrum(const json& j, const std::string& p,
                                                     SpectrumRole role) {
  auto spec = spectrum_spec(j, p, role);
  if (!spec || !grid_) return std::nullopt;
  std::vector<double> s = sample_spectrum(*spec, *grid_, role);
  for (std::size_t k = 0; k < s.size(); ++k) {
    const bool bad = role == SpectrumRole::Reflectance ? !(s[k] >= 0 && s[k] <= 1)
                                                       : !(s[k] >= 0 && std::isfinite(s[k]));
    if (bad) {
      error(p, "sampled value " + num(s[k]) + " at " + num(grid_->nm[k]) + " nm is outside " +
                   (role == SpectrumRole::Reflectance ? "[0, 1]" : "[0, inf)"));
      return std::nullopt;
    }
  }
  return s;
}

// Reads the photometric/radiometric totals beside a spectrum (SPEC §1): at most one, and only one
// that applies to this kind of source. Returns nullopt when there is none (absolute spectrum) or an
// error was reported.
std::optional<Total> Decoder::total(const json& obj, const std::string& p, const Keys& applicable,
                                    std::string_view source) {
  std::vector<Total> found;
  for (const TotalKind& kind : kTotalKinds) {
    const json* v = member(obj, kind.key);
    if (!v) continue;
    const std::string pk = key_ptr(p, kind.key);
    auto value = number_in(*v, pk, 0, true, INFINITY, false);
    if (std::find(applicable.begin(), applicable.end(), kind.key) == applicable.end()) {
      error(pk, std::string(kind.key) + " does not apply to " + std::string(source) +
                    "; use one of " + join(applicable, " or "));
      continue;
    }
    if (value) found.push_back({kind.key, kind.luminous, *value});
  }
  if (found.size() > 1) {
    error(p, "two totals given (" + std::string(found[0].key) + " and " +
                 std::string(found[1].key) + "); a spectrum is scaled by at most one");
    return std::nullopt;
  }
  if (found.empty()) return std::nullopt;
  return found.front();
}

// Scales s so that total = geometric_factor × integral(s) (luminous or radiometric, on the grid).
bool Decoder::scale_to_total(std::vector<double>& s, const Total& t, double geometric_factor,
                             const std::string& spectrum_pointer) {
  const double integral = t.luminous ? luminous_integral(s, *grid_) : integrate(s, *grid_);
  const double denominator = geometric_factor * integral;
  if (!(denominator > 0) || !std::isfinite(denominator)) {
    error(spectrum_pointer,
          t.luminous ? "spectrum has no visible content, cannot scale to lumens (" +
                           std::string(t.key) + ")"
                     : "spectrum integrates to zero over the wavelength grid, cannot scale it to " +
                           std::string(t.key));
    return false;
  }
  const double factor = t.value / denominator;
  for (double& v : s) v *= factor;
  if (!std::all_of(s.begin(), s.end(), [](double v) { return std::isfinite(v); })) {
    error(spectrum_pointer, "scaling to " + std::string(t.key) + " overflows");
    return false;
  }
  return true;
}

// ---- materials --------------------------------------------------------------------------------

void Decoder::decode_materials(const json& doc) {
  const json* mats = required(doc, "", "materials");
  if (!mats) return;
  if (!mats->is_object()) {
    error("/materials", "expected an object (material name -> material), got " + a_type(*mats));
    return;
  }
  if (mats->empty()) {
    error("/materials", "must define at least one material");
    return;
  }
  for (const auto& [name, m] : mats->items()) {
    const std::string p = key_ptr("/materials", name);
    material_index_[name] = static_cast<int>(scene_.materials.size());
    Material material;
    material.name = name;
    if (name.empty()) error(p, "a material name must not be empty");
    if (!object(m, p, {"reflectance", "specular"})) {
      scene_.materials.push_back(std::move(material));
      continue;
    }
    if (const json* r = required(m, p, "reflectance"))
      if (auto s = spectrum(*r, p + "/reflectance", SpectrumRole::Reflectance))
        material.reflectance = std::move(*s);
    // The Phong lobe only affects rendered images (SPEC §1; `lambert render`).
    if (const json* sp = member(m, "specular")) {
      const std::string ps = p + "/specular";
      if (object(*sp, ps, {"coefficient", "exponent", "reflectance"})) {
        SpecularLobe lobe;
        if (const json* c = required(*sp, ps, "coefficient"))
          if (auto v = number_in(*c, ps + "/coefficient", 0, true, 1, true)) lobe.coefficient = *v;
        if (const json* e = required(*sp, ps, "exponent"))
          if (auto v = number_in(*e, ps + "/exponent", 0, true, INFINITY, false)) lobe.exponent = *v;
        lobe.reflectance.assign(scene_.grid.size(), 1.0);
        if (const json* r = member(*sp, "reflectance"))
          if (auto v = spectrum(*r, ps + "/reflectance", SpectrumRole::Reflectance)) lobe.reflectance = std::move(*v);
        material.specular = std::move(lobe);
      }
    }
    scene_.materials.push_back(std::move(material));
  }
}

// ---- surfaces ---------------------------------------------------------------------------------

void Decoder::decode_surfaces(const json& doc) {
  const json* surfaces = required(doc, "", "surfaces");
  if (!surfaces || !array(*surfaces, "/surfaces", 1)) return;
  std::map<std::string, std::string> names;  // name -> pointer of its first use
  for (std::size_t i = 0; i < surfaces->size(); ++i) decode_surface((*surfaces)[i], i, names);
}

void Decoder::decode_surface(const json& j, std::size_t i,
                             std::map<std::string, std::string>& names) {
  const std::string p = index_ptr("/surfaces", i);
  if (!object(j, p, {"name", "material", "polygon", "mesh", "file", "transform", "emission"}))
    return;
  Surface surface;
  surface.pointer = p;

  surface.name = "surface" + std::to_string(i);
  std::string name_ptr = p;
  if (const json* n = member(j, "name")) {
    name_ptr = p + "/name";
    if (auto s = string(*n, name_ptr)) surface.name = *s;
  }
  if (auto [it, fresh] = names.emplace(surface.name, name_ptr); !fresh)
    error(name_ptr, "duplicate surface name " + quote_text(surface.name) + " (first used at " +
                        it->second + ")");

  if (const json* m = required(j, p, "material")) {
    if (auto s = string(*m, p + "/material")) {
      auto it = material_index_.find(*s);
      if (it != material_index_.end()) {
        surface.material = it->second;
      } else {
        std::vector<std::string> known;
        for (const auto& [k, v] : material_index_) known.push_back(k);
        error(p + "/material", "unknown material " + quote_text(*s) + suggestion(*s, known));
      }
    }
  }

  // Geometry: exactly one of polygon, mesh, file.
  std::vector<std::string_view> kinds;
  for (std::string_view k : {"polygon", "mesh", "file"})
    if (j.contains(k)) kinds.push_back(k);
  std::optional<TriangleMesh> mesh;
  std::optional<Transform> transform;
  if (const json* t = member(j, "transform")) {
    transform = decode_transform(*t, p + "/transform");
    if (j.contains("polygon"))
      error(p + "/transform", "transform applies only to mesh and file surfaces; give the "
                              "polygon's points where they belong");
  }
  if (kinds.empty()) {
    error(p, "a surface needs one of polygon, mesh or file");
  } else if (kinds.size() > 1) {
    error(p, "has both " + join(kinds, " and ") + "; give exactly one");
  } else if (kinds.front() == "polygon") {
    mesh = decode_polygon(j.at("polygon"), p + "/polygon");
  } else {
    const bool is_inline = kinds.front() == "mesh";
    const std::string pg = p + (is_inline ? "/mesh" : "/file");
    mesh = is_inline ? decode_inline_mesh(j.at("mesh"), pg) : decode_file_mesh(j.at("file"), pg);
    if (mesh && member(j, "transform") && !transform) mesh.reset();  // transform already reported
    if (mesh && transform) {
      for (Point3& v : mesh->vertices) {
        v = transform->apply(v);
        if (!(std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
              std::abs(v.z) <= kMaxCoordinate)) {
          error(p + "/transform", "moves vertices beyond the coordinate limit of 1e9 scene units");
          mesh.reset();
          break;
        }
      }
      // A mirroring scale turns counter-clockwise into clockwise: reverse the winding so the side
      // that was the front in the model stays the front.
      if (mesh && transform->flips())
        for (auto& t : mesh->triangles) std::swap(t[1], t[2]);
    }
    if (mesh) {
      for (Point3& v : mesh->vertices) v = metres(v);
      check_mesh_health(*mesh, pg, is_inline);
    }
  }

  std::optional<double> area_m2;
  if (mesh) {
    area_m2 = mesh_area(*mesh);
    surface.mesh = std::move(*mesh);
  }
  if (const json* e = member(j, "emission"))
    surface.emission = decode_emission(*e, p + "/emission", area_m2);
  scene_.surfaces.push_back(std::move(surface));
}

std::optional<TriangleMesh> Decoder::decode_polygon(const json& j, const std::string& p) {
  if (!array(j, p, 3)) return std::nullopt;
  std::vector<Point3> points;
  bool ok = true;
  for (std::size_t k = 0; k < j.size(); ++k) {
    auto q = point(j[k], index_ptr(p, k));
    if (q) points.push_back(*q);
    else ok = false;
  }
  if (!ok) return std::nullopt;
  // Triangulated in scene units: the planarity tolerance is relative to the polygon's size.
  PolygonTriangulation tri = triangulate_polygon(points, 1e-6);
  if (!tri.ok()) {
    error(p, tri.error);
    return std::nullopt;
  }
  for (Point3& v : tri.mesh.vertices) v = metres(v);
  return std::move(tri.mesh);
}

std::optional<TriangleMesh> Decoder::decode_inline_mesh(const json& j, const std::string& p) {
  if (!object(j, p, {"vertices", "triangles"})) return std::nullopt;
  const json* jv = required(j, p, "vertices");
  const json* jt = required(j, p, "triangles");
  TriangleMesh mesh;
  bool ok = jv && jt;
  const std::string pv = p + "/vertices", pt = p + "/triangles";
  if (jv && array(*jv, pv, 3)) {
    mesh.vertices.reserve(jv->size());
    for (std::size_t k = 0; k < jv->size(); ++k) {
      if (auto q = valid_triple((*jv)[k], true)) {
        mesh.vertices.push_back(to_point(*q));
      } else {
        point((*jv)[k], index_ptr(pv, k));  // reports what is wrong
        ok = false;
      }
    }
  } else {
    ok = false;
  }
  // Indices are range-checked against the vertex array as written, even if some vertex was bad.
  const long long vertex_count = jv && jv->is_array() ? static_cast<long long>(jv->size()) : -1;
  if (jt && array(*jt, pt, 1)) {
    mesh.triangles.reserve(jt->size());
    for (std::size_t k = 0; k < jt->size(); ++k) {
      const json& tri = (*jt)[k];
      if (tri.is_array() && tri.size() == 3 && tri[0].is_number_unsigned() &&
          tri[1].is_number_unsigned() && tri[2].is_number_unsigned()) {  // fast path
        const auto a = tri[0].get<std::uint64_t>(), b = tri[1].get<std::uint64_t>(),
                   c = tri[2].get<std::uint64_t>();
        const auto n = static_cast<std::uint64_t>(std::max(vertex_count, 0LL));
        if (a < n && b < n && c < n && a != b && b != c && a != c) {
          mesh.triangles.push_back({static_cast<int>(a), static_cast<int>(b), static_cast<int>(c)});
          continue;
        }
      }
      const std::string pk = index_ptr(pt, k);
      if (!tri.is_array() || tri.size() != 3) {
        error(pk, "expected 3 vertex indices [i, j, k], got " +
                      (tri.is_array() ? std::to_string(tri.size()) + " entries" : a_type(tri)));
        ok = false;
        continue;
      }
      std::array<int, 3> idx{};
      bool tri_ok = true;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::string pc = index_ptr(pk, c);
        auto v = whole(tri[c], pc, 0, std::numeric_limits<int>::max());
        if (!v) { tri_ok = false; continue; }
        if (vertex_count >= 0 && *v >= vertex_count) {
          error(pc, "vertex index " + std::to_string(*v) + " is out of range (the mesh has " +
                        std::to_string(vertex_count) + " vertices)");
          tri_ok = false;
          continue;
        }
        idx[c] = static_cast<int>(*v);
      }
      if (tri_ok && (idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2])) {
        error(pk, "triangle repeats a vertex index (degenerate)");
        tri_ok = false;
      }
      if (tri_ok) mesh.triangles.push_back(idx);
      else ok = false;
    }
  } else {
    ok = false;
  }
  return ok ? std::optional<TriangleMesh>(std::move(mesh)) : std::nullopt;
}

std::optional<std::filesystem::path> Decoder::resolve_file(const std::string& rel,
                                                           const std::string& p) {
  namespace fs = std::filesystem;
  if (rel.empty()) {
    error(p, "the file path must not be empty");
    return std::nullopt;
  }
  if (rel.find('\0') != std::string::npos) {
    error(p, "the file path must not contain NUL characters");
    return std::nullopt;
  }
  const fs::path path(rel);
  switch (files_.policy) {
    case FileAccess::Policy::Deny:
      error(p, "file surfaces are not allowed here (start the server with --mesh-root)");
      return std::nullopt;
    case FileAccess::Policy::Anywhere: {
      const fs::path full = path.is_absolute() ? path : files_.base_dir / path;
      std::error_code ec;
      if (!fs::is_regular_file(full, ec)) {
        error(p, "mesh file " + quote_text(rel) + " not found (looked for " + full.string() + ")");
        return std::nullopt;
      }
      return full;
    }
    case FileAccess::Policy::UnderRoot: {
      // Messages here never show server paths: the scene may come from an HTTP client.
      if (path.is_absolute() || path.has_root_name() || path.has_root_directory()) {
        error(p, "the file path must be relative to the mesh root, got " + quote_text(rel));
        return std::nullopt;
      }
      for (const fs::path& part : path)
        if (part == "..") {
          error(p, "the file path must not contain '..'");
          return std::nullopt;
        }
      std::error_code ec;
      const fs::path root = fs::canonical(files_.root, ec);
      if (ec) {
        error(p, "the server's mesh root cannot be resolved");
        return std::nullopt;
      }
      // Symlinks are followed; what counts is where the file really is. (A link swapped between
      // this check and the read is outside this threat model: the root is the operator's.)
      const fs::path real = fs::canonical(root / path, ec);
      if (ec || !fs::is_regular_file(real, ec)) {
        error(p, "mesh file " + quote_text(rel) + " not found under the mesh root");
        return std::nullopt;
      }
      auto [root_end, real_it] = std::mismatch(root.begin(), root.end(), real.begin(), real.end());
      if (root_end != root.end() || real_it == real.end()) {
        error(p, "mesh file " + quote_text(rel) +
                     " resolves (through a symbolic link) outside the mesh root");
        return std::nullopt;
      }
      return real;
    }
  }
  return std::nullopt;
}

std::optional<TriangleMesh> Decoder::decode_file_mesh(const json& j, const std::string& p) {
  auto rel = string(j, p);
  if (!rel) return std::nullopt;
  auto path = resolve_file(*rel, p);
  if (!path) return std::nullopt;
  MeshFileResult file = read_mesh_file(path->string());
  if (!file.ok()) {
    // The reader names the full path; show the scene's own path instead, so that an HTTP client
    // never learns where the server's mesh root is.
    std::string message = file.error;
    if (const std::string full = path->string() + ": "; message.rfind(full, 0) == 0)
      message = *rel + ": " + message.substr(full.size());
    error(p, message);
    return std::nullopt;
  }
  if (file.mesh.triangles.empty()) {
    error(p, "the mesh file has no triangles");
    return std::nullopt;
  }
  const int n = static_cast<int>(file.mesh.vertices.size());
  for (std::size_t k = 0; k < file.mesh.vertices.size(); ++k) {
    const Point3& v = file.mesh.vertices[k];
    if (!(std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate &&
          std::abs(v.z) <= kMaxCoordinate)) {
      error(p, "vertex " + std::to_string(k) +
                   " is not finite or beyond the coordinate limit of 1e9 scene units");
      return std::nullopt;
    }
  }
  for (std::size_t k = 0; k < file.mesh.triangles.size(); ++k)
    for (int idx : file.mesh.triangles[k])
      if (idx < 0 || idx >= n) {
        error(p, "triangle " + std::to_string(k) + " has a vertex index out of range");
        return std::nullopt;
      }
  return std::move(file.mesh);
}

std::optional<Transform> Decoder::decode_transform(const json& j, const std::string& p) {
  if (!object(j, p, {"scale", "rotate_deg", "translate"})) return std::nullopt;
  Transform t;
  bool ok = true;
  if (const json* s = member(j, "scale")) {
    const std::string ps = p + "/scale";
    if (s->is_number()) {
      auto v = number(*s, ps);
      if (v && *v == 0) error(ps, "scale must not be zero");
      if (v && *v != 0) t.scale = {*v, *v, *v};
      else ok = false;
    } else if (auto v = triple(*s, ps, false)) {
      for (std::size_t k = 0; k < 3; ++k)
        if ((*v)[k] == 0) {
          error(index_ptr(ps, k), "scale must not be zero");
          ok = false;
        }
      t.scale = *v;
    } else {
      ok = false;
    }
  }
  if (const json* r = member(j, "rotate_deg")) {
    if (auto v = triple(*r, p + "/rotate_deg", false)) t.rotate_deg = *v;
    else ok = false;
  }
  if (const json* tr = member(j, "translate")) {
    if (auto v = triple(*tr, p + "/translate", true)) t.translate = *v;
    else ok = false;
  }
  return ok ? std::optional<Transform>(t) : std::nullopt;
}

// Mesh health in the solver's frame (metres, after transform). Degenerate triangles would make the
// solver divide by zero areas: errors. The rest a radiosity solve survives: warnings.
void Decoder::check_mesh_health(const TriangleMesh& mesh, const std::string& p, bool inline_mesh) {
  const MeshHealth health = check_mesh(mesh);
  const std::size_t listed = std::min(health.degenerate_triangles.size(), kMaxListedPerMesh);
  for (std::size_t k = 0; k < listed; ++k) {
    const int t = health.degenerate_triangles[k];
    if (inline_mesh)
      error(index_ptr(p + "/triangles", static_cast<std::size_t>(t)),
            "degenerate triangle (zero area)");
    else
      error(p, "triangle " + std::to_string(t) + " of the file is degenerate (zero area)");
  }
  if (health.degenerate_triangles.size() > listed)
    error(p, std::to_string(health.degenerate_triangles.size() - listed) +
                 " more degenerate triangles");
  if (!health.self_intersections.empty()) {
    const auto [a, b] = health.self_intersections.front();
    warn(p, std::to_string(health.self_intersections.size()) +
                " pairs of triangles intersect each other (e.g. triangles " + std::to_string(a) +
                " and " + std::to_string(b) + ")");
  }
  if (!health.consistently_oriented)
    warn(p, "triangles are not consistently oriented (front and back sides mixed)");
  if (!health.manifold) warn(p, "some edges are shared by more than two triangles (non-manifold)");
}

// Surface emission (SPEC §1): exitance R or radiance L, a lobe, and optionally one total.
// With lobe exponent n the on-axis radiance is L = R (n+1)/(2π) (the lobe normalisation of SPEC
// "Light models"; n = 1 gives L = R/π). The Scene stores R.
std::optional<Emission> Decoder::decode_emission(const json& j, const std::string& p,
                                                 std::optional<double> area_m2) {
  if (!object(j, p, with_totals({"exitance", "radiance", "lobe"}))) return std::nullopt;
  Emission emission;
  bool ok = true;
  if (const json* lobe = member(j, "lobe")) {
    const std::string pl = p + "/lobe";
    if (lobe->is_string()) {
      if (lobe->get<std::string>() != "lambert") {
        error(pl, "unknown lobe " + quote_text(lobe->get<std::string>()) +
                      "; expected \"lambert\" or {\"phong\": n}");
        ok = false;
      }
    } else if (lobe->is_object()) {
      unknown_keys(*lobe, pl, {"phong"});
      const json* n = required(*lobe, pl, "phong");
      auto v = n ? number_in(*n, pl + "/phong", 1, true, kMaxLobeExponent, true) : std::nullopt;
      if (v) emission.lobe_exponent = *v;
      else ok = false;
    } else {
      error(pl, "expected \"lambert\" or {\"phong\": n}, got " + a_type(*lobe));
      ok = false;
    }
  }
  const double n = emission.lobe_exponent;

  const json* jr = member(j, "exitance");
  const json* jl = member(j, "radiance");
  if (jr && jl) {
    error(p, "give exitance or radiance, not both");
    ok = false;
  } else if (!jr && !jl) {
    error(p, "an emission needs exitance or radiance");
    ok = false;
  }
  const std::string ps = p + (jr ? "/exitance" : "/radiance");
  std::optional<std::vector<double>> shape;
  if (jr || jl) shape = spectrum(jr ? *jr : *jl, ps, SpectrumRole::Emission);
  const auto t = total(j, p,
                       {"luminous_exitance_lm_m2", "radiant_exitance_W_m2", "luminance_cd_m2",
                        "radiance_W_m2_sr", "luminous_flux_lm", "radiant_flux_W",
                        "luminous_intensity_cd", "radiant_intensity_W_sr"},
                       "a surface emitter");
  if (!ok || !shape) return std::nullopt;

  // R from the given spectrum; then total = G × integral(R), G per kind of total.
  std::vector<double> R = std::move(*shape);
  const double radiance_per_exitance = (n + 1) / (2 * kPi);  // L/R on the axis
  if (jl)
    for (double& v : R) v /= radiance_per_exitance;
  if (t) {
    if (!area_m2) return std::nullopt;  // geometry failed and was reported
    double G = 1;
    if (is_one_of(t->key, {"luminance_cd_m2", "radiance_W_m2_sr"})) G = radiance_per_exitance;
    else if (is_one_of(t->key, {"luminous_flux_lm", "radiant_flux_W"})) G = *area_m2;
    else if (is_one_of(t->key, {"luminous_intensity_cd", "radiant_intensity_W_sr"}))
      G = radiance_per_exitance * *area_m2;  // peak intensity of the whole surface, on the normal
    if (!scale_to_total(R, *t, G, ps)) return std::nullopt;
  }
  emission.exitance_W_m2_nm = std::move(R);
  return emission;
}

// ---- lights -----------------------------------------------------------------------------------

void Decoder::decode_lights(const json& doc) {
  const json* lights = member(doc, "lights");
  if (!lights || !array(*lights, "/lights")) return;
  for (std::size_t i = 0; i < lights->size(); ++i) decode_light((*lights)[i], i);
}

void Decoder::decode_light(const json& j, std::size_t i) {
  const std::string p = index_ptr("/lights", i);
  if (!j.is_object()) {
    error(p, "expected an object, got " + a_type(j));
    return;
  }
  const json* jtype = required(j, p, "type");
  if (!jtype) return;
  auto type = string(*jtype, p + "/type");
  if (!type) return;
  static const std::vector<std::string> kTypes = {"ambient", "directional", "point",
                                                  "goniometric", "spot", "warn"};
  if (std::find(kTypes.begin(), kTypes.end(), *type) == kTypes.end()) {
    error(p + "/type", "unknown light type " + quote_text(*type) +
                           "; expected ambient, directional, point, goniometric, spot or warn" +
                           suggestion(*type, kTypes));
    return;
  }

  if (*type == "ambient" || *type == "directional") {
    const bool ambient = *type == "ambient";
    unknown_keys(j, p, with_totals(ambient ? Keys{"type", "irradiance"}
                                           : Keys{"type", "direction", "irradiance"}));
    std::optional<Vector3> dir;
    if (!ambient)
      if (const json* d = required(j, p, "direction")) dir = direction(*d, p + "/direction");
    std::optional<std::vector<double>> E;
    if (const json* e = required(j, p, "irradiance"))
      E = spectrum(*e, p + "/irradiance", SpectrumRole::Emission);
    const auto t = total(j, p, {"illuminance_lx", "irradiance_W_m2"},
                         ambient ? "an ambient light" : "a directional light");
    if (!E || (!ambient && !dir)) return;
    if (t && !scale_to_total(*E, *t, 1.0, p + "/irradiance")) return;
    if (ambient) scene_.lights.emplace_back(AmbientLight{std::move(*E)});
    else scene_.lights.emplace_back(DirectionalLight{*dir, std::move(*E)});
    scene_.light_pointers.push_back(p);
    return;
  }

  // Point-like sources: I(ψ) = I_0 cos^m ψ about the axis.
  PointLight light;
  Keys keys = {"type", "position", "intensity", "attenuation"};
  if (*type == "point") {
    light.kind = PointLight::Kind::Point;
  } else {
    keys.push_back("axis");
    if (*type == "goniometric") {
      light.kind = PointLight::Kind::Goniometric;
      keys.push_back("exponent");
    } else if (*type == "spot") {
      light.kind = PointLight::Kind::Spot;
      keys.push_back("exponent");
      keys.push_back("cutoff_deg");
    } else {
      light.kind = PointLight::Kind::Warn;
      light.exponent = 1;  // Warn's model is the cos^1 lobe
    }
  }
  unknown_keys(j, p, with_totals(keys));
  bool ok = true;
  if (const json* jp = required(j, p, "position")) {
    if (auto q = point(*jp, p + "/position"))
      light.position = metres(*q);
    else ok = false;
  } else {
    ok = false;
  }
  if (light.kind != PointLight::Kind::Point) {
    const json* ja = required(j, p, "axis");
    auto a = ja ? direction(*ja, p + "/axis") : std::nullopt;
    if (a) light.axis = *a;
    else ok = false;
  }
  if (light.kind == PointLight::Kind::Goniometric || light.kind == PointLight::Kind::Spot) {
    const json* je = light.kind == PointLight::Kind::Spot ? member(j, "exponent")
                                                          : required(j, p, "exponent");
    if (je) {
      auto m = number_in(*je, p + "/exponent", 0, true, kMaxLobeExponent, true);
      if (m) light.exponent = *m;
      else ok = false;
    } else if (light.kind == PointLight::Kind::Goniometric) {
      ok = false;
    }
  }
  if (light.kind == PointLight::Kind::Spot) {
    const json* jc = required(j, p, "cutoff_deg");
    auto c = jc ? number_in(*jc, p + "/cutoff_deg", 0, false, 180, true) : std::nullopt;
    if (c) light.cutoff_rad = *c == 180 ? kPi : *c * kDegree;
    else ok = false;
  }
  if (const json* att = member(j, "attenuation")) {
    const std::string pa = p + "/attenuation";
    if (att->is_string()) {
      if (att->get<std::string>() != "inverse_square") {
        error(pa, "unknown attenuation " + quote_text(att->get<std::string>()) +
                      "; expected \"inverse_square\" or {\"c1\", \"c2\", \"c3\"}");
        ok = false;
      }
    } else if (object(*att, pa, {"c1", "c2", "c3"})) {
      // E = I cos α / (c1 + c2 r + c3 r²) with r in METRES, whatever the scene's units: the
      // coefficients are taken as given (c2 per metre, c3 per square metre), not converted.
      std::array<double, 3> c{0, 0, 0};
      const std::array<std::string_view, 3> names = {"c1", "c2", "c3"};
      for (std::size_t k = 0; k < 3; ++k)
        if (const json* v = member(*att, names[k])) {
          auto x = number_in(*v, key_ptr(pa, names[k]), 0, true, INFINITY, false);
          if (x) c[k] = *x;
          else ok = false;
        }
      if (c[0] == 0 && c[1] == 0 && c[2] == 0) {
        error(pa, "c1, c2 and c3 must not all be zero");
        ok = false;
      }
      light.attenuation = {c[0], c[1], c[2]};
      light.inverse_square = false;
    } else {
      ok = false;
    }
  }
  std::optional<std::vector<double>> I;
  if (const json* ji = required(j, p, "intensity"))
    I = spectrum(*ji, p + "/intensity", SpectrumRole::Emission);
  static const std::map<PointLight::Kind, std::string_view> kDescription = {
      {PointLight::Kind::Point, "a point light"},
      {PointLight::Kind::Goniometric, "a goniometric light"},
      {PointLight::Kind::Spot, "a spot light"},
      {PointLight::Kind::Warn, "a Warn light"}};
  const auto t = total(j, p,
                       {"luminous_intensity_cd", "radiant_intensity_W_sr", "luminous_flux_lm",
                        "radiant_flux_W"},
                       kDescription.at(light.kind));
  if (!ok || !I) return;
  if (t) {
    // Flux = I_0 × Ω_eff, Ω_eff = ∫ cos^m ψ dω over the lit directions.
    double G = 1;
    if (is_one_of(t->key, {"luminous_flux_lm", "radiant_flux_W"})) {
      const double m = light.exponent;
      switch (light.kind) {
        case PointLight::Kind::Point: G = 4 * kPi; break;
        case PointLight::Kind::Goniometric:
        case PointLight::Kind::Warn: G = 2 * kPi / (m + 1); break;
        case PointLight::Kind::Spot: {
          // cos^m with m > 0 is zero beyond 90°; an m = 0 spot is a uniform cone up to its cutoff.
          const double psi = m > 0 ? std::min(light.cutoff_rad, kPi / 2) : light.cutoff_rad;
          G = 2 * kPi * (1 - std::pow(std::cos(psi), m + 1)) / (m + 1);
          break;
        }
      }
    }
    if (!scale_to_total(*I, *t, G, p + "/intensity")) return;
  }
  light.intensity_W_sr_nm = std::move(*I);
  scene_.lights.emplace_back(std::move(light));
  scene_.light_pointers.push_back(p);
}

// ---- probes -----------------------------------------------------------------------------------

void Decoder::decode_probes(const json& doc) {
  const json* probes = member(doc, "probes");
  if (!probes || !array(*probes, "/probes")) return;
  std::map<std::string, std::string> names;
  for (std::size_t i = 0; i < probes->size(); ++i) decode_probe((*probes)[i], i, names);
}

void Decoder::decode_probe(const json& j, std::size_t i, std::map<std::string, std::string>& names) {
  const std::string p = index_ptr("/probes", i);
  if (!object(j, p, {"name", "position", "grid", "normal"})) return;
  Probe probe;
  probe.name = "probe" + std::to_string(i);
  std::string name_ptr = p;
  if (const json* n = member(j, "name")) {
    name_ptr = p + "/name";
    if (auto s = string(*n, name_ptr)) probe.name = *s;
  }
  if (auto [it, fresh] = names.emplace(probe.name, name_ptr); !fresh)
    error(name_ptr, "duplicate probe name " + quote_text(probe.name) + " (first used at " +
                        it->second + ")");
  bool ok = true;
  if (const json* jn = required(j, p, "normal")) {
    auto v = direction(*jn, p + "/normal");
    if (v) probe.normal = *v;
    else ok = false;
  } else {
    ok = false;
  }
  const json* jp = member(j, "position");
  const json* jg = member(j, "grid");
  if (jp && jg) {
    error(p, "give position or grid, not both");
    return;
  }
  if (!jp && !jg) {
    error(p, "a probe needs position or grid");
    return;
  }
  if (jp) {
    auto q = point(*jp, p + "/position");
    if (!q || !ok) return;
    probe.points.push_back(metres(*q));
    scene_.probes.push_back(std::move(probe));
    return;
  }
  const std::string pg = p + "/grid";
  if (!object(*jg, pg, {"origin", "u", "v", "nu", "nv"})) return;
  const json* jo = required(*jg, pg, "origin");
  const json* ju = required(*jg, pg, "u");
  const json* jv = required(*jg, pg, "v");
  const json* jnu = required(*jg, pg, "nu");
  const json* jnv = required(*jg, pg, "nv");
  auto origin = jo ? point(*jo, pg + "/origin") : std::nullopt;
  auto u = ju ? triple(*ju, pg + "/u", true) : std::nullopt;
  auto v = jv ? triple(*jv, pg + "/v", true) : std::nullopt;
  std::optional<long long> nu, nv;
  if (jnu) nu = whole(*jnu, pg + "/nu", 1, kMaxProbeGridSide);
  if (jnv) nv = whole(*jnv, pg + "/nv", 1, kMaxProbeGridSide);
  if (!origin || !u || !v || !nu || !nv || !ok) return;
  const auto du = unit_vector(*u), dv = unit_vector(*v);
  if (!du || !dv || length(cross(*du, *dv)) < 1e-9) {
    error(pg, !du ? "u must not be the zero vector"
                  : !dv ? "v must not be the zero vector" : "u and v must not be parallel");
    return;
  }
  if (*nu * *nv > kMaxProbeGridPoints) {
    error(pg, "nu × nv = " + std::to_string(*nu * *nv) + " points; at most " +
                  std::to_string(kMaxProbeGridPoints) + " per grid");
    return;
  }
  probe.is_grid = true;
  probe.nu = static_cast<int>(*nu);
  probe.nv = static_cast<int>(*nv);
  probe.points.reserve(static_cast<std::size_t>(*nu * *nv));
  // Cell centres, u fastest: origin + (a + 1/2)/nu u + (b + 1/2)/nv v.
  for (long long b = 0; b < *nv; ++b)
    for (long long a = 0; a < *nu; ++a) {
      const Point3 q = *origin + *u * ((a + 0.5) / static_cast<double>(*nu)) +
                       *v * ((b + 0.5) / static_cast<double>(*nv));
      probe.points.push_back(metres(q));
    }
  scene_.probes.push_back(std::move(probe));
}

// ---- options ----------------------------------------------------------------------------------

void Decoder::decode_options(const json& doc) {
  const json* m = member(doc, "meshing");
  if (m && object(*m, "/meshing", {"max_patch_area", "adaptive", "refine_direct"})) {
    if (const json* a = member(*m, "max_patch_area"))
      if (auto v = number_in(*a, "/meshing/max_patch_area", 0, false, INFINITY, false))
        scene_.meshing.max_patch_area_m2 = *v * scene_.unit_m * scene_.unit_m;  // units² -> m²
    if (const json* a = member(*m, "adaptive"))
      if (auto v = boolean(*a, "/meshing/adaptive")) scene_.meshing.adaptive = *v;
    if (const json* r = member(*m, "refine_direct"))
      if (auto v = boolean(*r, "/meshing/refine_direct")) scene_.meshing.refine_direct = *v;
  }
  const json* s = member(doc, "solver");
  if (s && object(*s, "/solver", {"tolerance", "max_iterations", "method", "accuracy", "exact_visibility"})) {
    if (const json* t = member(*s, "tolerance"))
      if (auto v = number_in(*t, "/solver/tolerance", 0, false, 0.1, true))
        scene_.solver.tolerance = *v;
    if (const json* t = member(*s, "max_iterations"))
      if (auto v = whole(*t, "/solver/max_iterations", 1, 1000000))
        scene_.solver.max_iterations = static_cast<int>(*v);
    if (const json* t = member(*s, "method"))
      if (auto v = string(*t, "/solver/method")) {
        if (*v == "auto") scene_.solver.method = SolverMethod::Auto;
        else if (*v == "dense") scene_.solver.method = SolverMethod::Dense;
        else if (*v == "hierarchical") scene_.solver.method = SolverMethod::Hierarchical;
        else error("/solver/method", "unknown method \"" + *v + "\" (expected \"auto\", \"dense\" or \"hierarchical\")");
      }
    if (const json* t = member(*s, "accuracy"))
      if (auto v = number_in(*t, "/solver/accuracy", 0, false, 0.1, true)) scene_.solver.accuracy = *v;
    if (const json* t = member(*s, "exact_visibility"))
      if (auto v = boolean(*t, "/solver/exact_visibility")) scene_.solver.exact_visibility = *v;
  }
  if (const json* o = member(doc, "output"); o && object(*o, "/output", {"spectral", "per_source"})) {
    if (const json* s = member(*o, "spectral"))
      if (auto v = boolean(*s, "/output/spectral")) scene_.output.spectral = *v;
    if (const json* s = member(*o, "per_source"))
      if (auto v = boolean(*s, "/output/per_source")) scene_.output.per_source = *v;
  }
}

}  // namespace

DecodeResult decode_scene(const std::string& json_text, const FileAccess& files) {
  if (auto e = prescan(json_text)) return {std::nullopt, {*e}};

  json doc;
  DomBuilder builder(doc);
  const bool parsed = json::sax_parse(json_text, &builder, json::input_format_t::json,
                                      /*strict=*/true, /*ignore_comments=*/false);
  if (!parsed) {
    // "[json.exception.parse_error.101] parse error at line 2, column 12: ..." -> without the tag.
    std::string message = builder.parse_error_message;
    const auto tag_end = message.find("] ");
    if (message.rfind("[json.exception", 0) == 0 && tag_end != std::string::npos)
      message.erase(0, tag_end + 2);
    if (!builder.parse_error_pointer.empty())
      return {std::nullopt, {{builder.parse_error_pointer, message + " (not a finite double)"}}};
    return {std::nullopt, {{"", "invalid JSON: " + message}}};
  }
  return Decoder(files).run(doc, std::move(builder.duplicate_keys));
}

std::string format_errors(const std::vector<DecodeError>& errors) {
  std::string out;
  for (const DecodeError& e : errors)
    out += (e.pointer.empty() ? std::string("(document)") : e.pointer) + ": " + e.message + "\n";
  return out;
}

}  // namespace lambert
