// The content address of a scene: the same scene solved by the same program gives the same result,
// so a job store answers it from a stored result without solving (server/job_store.h).
//
// The key is the SHA-256 of "lambert <version>\nscene format 1\n" followed by the scene's canonical
// JSON text, as 64 lowercase hex digits. Canonical means:
//   - objects: members sorted by name, compared as UTF-8 bytes (which is Unicode code point order);
//     (a name that appears twice never gets here: the scene decoder refuses it);
//   - numbers: the IEEE double the decoder reads, written in the shortest form that reads back as
//     that double ("1", "1.0", "1e0" and "10e-1" are one number; 0.1 and 0.10000000000000001 too);
//     integers beyond 2^53 in magnitude, which a double cannot hold exactly, keep all their digits;
//     -0 is written as 0 (no scene quantity depends on the sign of zero);
//   - strings: UTF-8, escaping only what JSON requires (", \ and control characters);
//   - no whitespace outside strings.
// So reordered members and reformatted numbers hit; any changed value misses.
//
// Scenes that name files (a member called "file" or "..._file" anywhere: mesh files, photometric
// files) have no key: the files can change while the scene text stays the same, and such scenes are
// always solved.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace lambert {

// The canonical text of a JSON document; nullopt when `json_text` is not JSON.
std::optional<std::string> canonical_json(std::string_view json_text);

// The cache key of a scene document (see above), or "" when it names files or is not JSON.
// `program_version` is LAMBERT_VERSION.
std::string scene_cache_key(std::string_view scene_json, std::string_view program_version);

// SHA-256 of `bytes` as 64 lowercase hex digits (OpenSSL).
std::string sha256_hex(std::string_view bytes);

}  // namespace lambert
