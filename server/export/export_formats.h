// The exchange formats of a result, by name: what `lambert export` writes and GET
// /v1/jobs/{id}/result.{glb,ply,csv} answers (export_mesh.h, gltf_writer.h, ply_writer.h,
// probe_csv.h).
#pragma once

#include <optional>
#include <string>

#include "server/export/export_mesh.h"

namespace lambert {

enum class ExportFormat { Glb, Ply, Csv };

// "glb", "ply", "csv".
std::optional<ExportFormat> export_format_named(const std::string& name);
// By a file name's extension, case-insensitive.
std::optional<ExportFormat> export_format_of_path(const std::string& path);
const char* export_format_name(ExportFormat format);
const char* export_media_type(ExportFormat format);  // model/gltf-binary, application/ply, text/csv

// The file's bytes. Throws std::invalid_argument (naming the JSON pointer) when the result cannot be
// read.
std::string export_result(const std::string& result_json, ExportFormat format, const ExportOptions& options);

}  // namespace lambert
