// The rooms of the scene decoder, one per top-level section of a scene (SPEC §1), in the order
// server/scene_codec.cpp walks them. The spectrum section is in spectra.h (every room samples
// spectra on its grid). Each reads its section of doc into d.scene() and reports what is wrong.
#pragma once

#include <string>

#include "server/codec/decoder.h"

namespace lambert::codec {

void decode_materials(Decoder& d, const json& doc);  // materials.cpp
void decode_surfaces(Decoder& d, const json& doc);   // surfaces.cpp (needs the materials)
void decode_lights(Decoder& d, const json& doc);     // lights/dispatch.cpp
// Clear glass ("transmission": "specular") with what it does not support yet (materials.cpp).
void check_clear_glass(Decoder& d);
void decode_probes(Decoder& d, const json& doc);     // probes.cpp
// A probe's daylight metrics, read into probe.daylight once its points and normal are read; the
// lights must be decoded (probe_daylight.cpp). False after an error.
bool decode_probe_daylight(Decoder& d, const json& j, const std::string& p, Probe& probe);
void decode_options(Decoder& d, const json& doc);    // options.cpp: meshing, solver, output
void decode_evaluations(Decoder& d, const json& doc);  // evaluation.cpp: task_summary, glare (needs the probes)

}  // namespace lambert::codec
