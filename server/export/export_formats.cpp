#include "server/export/export_formats.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "server/export/gltf_writer.h"
#include "server/export/ply_writer.h"
#include "server/export/probe_csv.h"

namespace lambert {

std::optional<ExportFormat> export_format_named(const std::string& name) {
  if (name == "glb") return ExportFormat::Glb;
  if (name == "ply") return ExportFormat::Ply;
  if (name == "csv") return ExportFormat::Csv;
  return std::nullopt;
}

std::optional<ExportFormat> export_format_of_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (ext.empty()) return std::nullopt;
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return export_format_named(ext.substr(1));
}

const char* export_format_name(ExportFormat format) {
  switch (format) {
    case ExportFormat::Glb: return "glb";
    case ExportFormat::Ply: return "ply";
    case ExportFormat::Csv: return "csv";
  }
  return "";
}

const char* export_media_type(ExportFormat format) {
  switch (format) {
    case ExportFormat::Glb: return "model/gltf-binary";
    case ExportFormat::Ply: return "application/ply";
    case ExportFormat::Csv: return "text/csv";
  }
  return "";
}

std::string export_result(const std::string& result_json, ExportFormat format, const ExportOptions& options) {
  const ResultModel model = read_result(result_json);
  switch (format) {
    case ExportFormat::Glb: return write_glb(export_mesh(model, options));
    case ExportFormat::Ply: return write_ply(export_mesh(model, options));
    case ExportFormat::Csv: return write_probe_csv(model);
  }
  return {};
}

}  // namespace lambert
