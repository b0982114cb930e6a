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
  codec::decode_probes(d, doc);
  codec::decode_options(d, doc);
  codec::decode_evaluations(d, doc);
  // Reference values for tests (scenes_test); the solver ignores them, but they must be an object.
  if (const json* v = d.member(doc, "expected"); v && !v->is_object())
    d.error("/expected", "expected an object, got " + codec::a_type(*v));
  return d.finish();
}

}  // namespace

DecodeResult decode_scene(const std::string& json_text, const FileAccess& files) {
  codec::ParsedDocument parsed = codec::parse_document(json_text);
  if (!parsed.fatal.empty()) return {std::nullopt, std::move(parsed.fatal)};
  Decoder decoder(files, std::move(parsed.duplicate_keys));
  return walk(decoder, parsed.doc);
}

std::string format_errors(const std::vector<DecodeError>& errors) {
  std::string out;
  for (const DecodeError& e : errors)
    out += (e.pointer.empty() ? std::string("(document)") : e.pointer) + ": " + e.message + "\n";
  return out;
}

}  // namespace lambert
