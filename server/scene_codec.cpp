// Scene JSON (SPEC §1) -> lambert::Scene. nlohmann_json lives only in the codecs.
//
// The decoder is strict and exhaustive: it walks the whole document, records every problem as
// {JSON pointer, message} and produces a Scene only when there were none. Order of work:
//   1. a byte scan (UTF-8 validity, nesting depth <= 256) so hostile input never reaches the parser;
//   2. a SAX parse into a DOM that also reports duplicate object keys (nlohmann keeps the last one
//      silently) (both in codec/document.cpp);
//   3. the schema walk below, one room of codec/ per section. Lengths are converted to metres at
//      the very end of each geometry, spectra are sampled on the scene's grid and photometric
//      totals are applied there, so the solver sees absolute spectral quantities in SI units only.
#include "server/scene_codec.h"

#include <utility>

#include "server/codec/decoder.h"
#include "server/codec/document.h"
#include "server/codec/sections.h"
#include "server/codec/spectra.h"

namespace lambert {
namespace {

using codec::Decoder;
using codec::json;

void decode_version(Decoder& d, const json& doc) {
  const json* v = d.member(doc, "lambert");
  if (!v) return;
  if (!v->is_number()) {
    d.error("/lambert", "expected a number (the format version), got " + codec::a_type(*v));
    return;
  }
  const double version = v->get<double>();
  if (version != 1) {
    d.error("/lambert", "unsupported format version " + codec::num(version) +
                            " (this Lambert reads version 1)");
    return;
  }
  d.scene().format_version = 1;
}

void decode_units(Decoder& d, const json& doc) {
  const json* v = d.member(doc, "units");
  if (!v) return;
  auto u = d.string(*v, "/units");
  if (!u) return;
  double& unit_m = d.scene().unit_m;
  if (*u == "m") unit_m = 1.0;
  else if (*u == "cm") unit_m = 0.01;
  else if (*u == "mm") unit_m = 0.001;
  else
    d.error("/units", "unknown unit " + codec::quote_text(*u) + "; expected \"m\", \"cm\" or \"mm\"");
}

// The sections in dependency order: units before every length, the grid before every spectrum,
// materials before the surfaces that name them.
DecodeResult walk(Decoder& d, const json& doc) {
  if (!doc.is_object()) {
    d.error("", "a scene must be a JSON object, got " + codec::a_type(doc));
    return d.reject();
  }
  d.unknown_keys(doc, "", {"lambert", "name", "description", "units", "spectrum", "materials",
                           "surfaces", "lights", "probes", "task_summary", "glare", "meshing", "solver",
                           "output", "expected"});
  decode_version(d, doc);
  if (const json* v = d.member(doc, "name"))
    if (auto s = d.string(*v, "/name")) d.scene().name = *s;
  if (const json* v = d.member(doc, "description")) d.string(*v, "/description");
  decode_units(d, doc);
  codec::decode_spectrum_section(d, d.member(doc, "spectrum"));
  codec::decode_materials(d, doc);
  codec::decode_surfaces(d, doc);
  codec::decode_lights(d, doc);
  codec::check_clear_glass(d);
  codec::decode_probes(d, doc);
  codec::decode_options(d, doc);
  codec::decode_evaluations(d, doc);
  // Reference values for tests (scenes_test); the solver ignores them, but they must be an object.
  if (const json* v = d.member(doc, "expected"); v && !v->is_object())
    d.error("/expected", "expected an object, got " + codec::a_type(*v));
  return d.finish();
}

}  // namespace

DecodeResult decode_scene(const std::string& json_text, const FileAccess& files, const SceneLimits& limits) {
  codec::ParsedDocument parsed = codec::parse_document(json_text);
  if (!parsed.fatal.empty()) return {std::nullopt, std::move(parsed.fatal), 0};
  Decoder decoder(files, limits, std::move(parsed.duplicate_keys), parsed.omitted_duplicate_keys);
  DecodeResult result = walk(decoder, parsed.doc);
  if (!result.ok()) return result;
  std::vector<DecodeError> over = check_scene_limits(*result.scene, limits);
  if (over.empty()) return result;
  return {std::nullopt, std::move(over), 0};
}

std::string format_errors(const std::vector<DecodeError>& errors) {
  std::string out;
  for (const DecodeError& e : errors)
    out += (e.pointer.empty() ? std::string("(document)") : e.pointer) + ": " + e.message + "\n";
  return out;
}

std::string format_errors(const DecodeResult& result) {
  std::string out = format_errors(result.errors);
  if (result.omitted_errors > 0)
    out += "... and " + std::to_string(result.omitted_errors) + " more errors (" +
           std::to_string(result.error_count()) + " in all; the first " + std::to_string(result.errors.size()) +
           " are listed)\n";
  return out;
}

std::string_view utf8_prefix(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t cut = max_bytes;  // never split a UTF-8 sequence: reports are JSON text again
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut);
}

std::string_view utf8_suffix(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  std::size_t cut = text.size() - max_bytes;
  while (cut < text.size() && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) ++cut;
  return text.substr(cut);
}

std::string elided(std::string_view head, std::size_t left_out_bytes, std::string_view tail) {
  return std::string(head) + " ... [" + std::to_string(left_out_bytes) + " bytes left out] ... " + std::string(tail);
}

std::string shorten_for_report(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return std::string(text);
  const std::size_t keep = max_bytes > kElisionMarkBytes ? max_bytes - kElisionMarkBytes : 0;
  const std::string_view head = utf8_prefix(text, keep / 2), tail = utf8_suffix(text, keep - keep / 2);
  return elided(head, text.size() - head.size() - tail.size(), tail);
}

DecodeError bounded_error(std::string pointer, std::string message) {
  if (pointer.size() > kMaxErrorTextBytes) pointer = shorten_for_report(pointer);
  if (message.size() > kMaxErrorTextBytes) message = shorten_for_report(message);
  return {std::move(pointer), std::move(message)};
}

}  // namespace lambert
