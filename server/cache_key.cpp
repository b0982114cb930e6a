// The content address of a scene (see cache_key.h).
#include "server/cache_key.h"

#include <openssl/evp.h>

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace lambert {
namespace {

using json = nlohmann::json;

// 2^53: every integer up to it in magnitude is exactly a double.
constexpr std::uint64_t kExactIntegers = std::uint64_t{1} << 53;

// Rewrites numbers into their canonical form in place (nlohmann's objects already iterate, and so
// dump, in byte order of their names). Returns false when a member names a file.
bool canonicalize(json& j) {
  switch (j.type()) {
    case json::value_t::object:
      for (auto& [name, value] : j.items()) {
        if (name == "file" || (name.size() > 5 && name.ends_with("_file"))) return false;
        if (!canonicalize(value)) return false;
      }
      return true;
    case json::value_t::array:
      for (auto& value : j)
        if (!canonicalize(value)) return false;
      return true;
    case json::value_t::number_unsigned:
      if (j.get<std::uint64_t>() <= kExactIntegers) j = static_cast<double>(j.get<std::uint64_t>());
      return true;
    case json::value_t::number_integer: {
      const std::int64_t v = j.get<std::int64_t>();
      if (v >= -static_cast<std::int64_t>(kExactIntegers) && v <= static_cast<std::int64_t>(kExactIntegers))
        j = static_cast<double>(v);
      return true;
    }
    case json::value_t::number_float:
      if (j.get<double>() == 0) j = 0.0;  // -0 and 0
      return true;
    default:
      return true;
  }
}

std::optional<json> parse(std::string_view text) {
  json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  return j;
}

}  // namespace

std::optional<std::string> canonical_json(std::string_view json_text) {
  auto j = parse(json_text);
  if (!j) return std::nullopt;
  canonicalize(*j);
  // nlohmann writes doubles in the shortest form that reads back exactly (Grisu2), integral ones
  // with ".0"; ensure_ascii off keeps UTF-8 as it is.
  return j->dump(-1, ' ', false, json::error_handler_t::strict);
}

std::string scene_cache_key(std::string_view scene_json, std::string_view program_version) {
  auto j = parse(scene_json);
  if (!j || !canonicalize(*j)) return "";
  std::string text = "lambert ";
  text += program_version;
  text += "\nscene format 1\n";
  text += j->dump(-1, ' ', false, json::error_handler_t::strict);
  return sha256_hex(text);
}

std::string sha256_hex(std::string_view bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int k = 0; k < length; ++k) {
    hex += kHex[digest[k] >> 4];
    hex += kHex[digest[k] & 15];
  }
  return hex;
}

}  // namespace lambert
