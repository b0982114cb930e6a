#include "server/result_views.h"

#include <charconv>
#include <cmath>

#include "server/export/export_formats.h"

namespace lambert {
namespace {

// The export options a query asks for, or the first problem with it.
std::string read_query(const std::multimap<std::string, std::string>& query, ExportFormat format,
                       ExportOptions& options) {
  for (const auto& [key, value] : query) {
    if (key == "shading" && format != ExportFormat::Csv) {
      if (value == "smooth")
        options.shading = Shading::Smooth;
      else if (value == "flat")
        options.shading = Shading::Flat;
      else
        return "shading: '" + value + "' is not one of: smooth, flat";
    } else if (key == "white" && format != ExportFormat::Csv) {
      double white = 0;
      const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), white);
      if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(white) || !(white > 0))
        return "white: '" + value + "' is not a luminance in cd/m2 greater than 0";
      options.white_cd_m2 = white;
    } else {
      return "unknown query parameter '" + key + "' (result." + export_format_name(format) + " takes " +
             (format == ExportFormat::Csv ? "none)" : "shading and white)");
    }
  }
  return {};
}

template <ExportFormat F>
ResultViewOutcome render_as(const std::string& result_json, const std::multimap<std::string, std::string>& query) {
  ExportOptions options;
  ResultViewOutcome out;
  out.error = read_query(query, F, options);
  if (out.error.empty()) out.body = export_result(result_json, F, options);
  return out;
}

}  // namespace

const std::vector<ResultView>& result_views() {
  static const std::vector<ResultView> views = {
      {"result.glb", export_media_type(ExportFormat::Glb), render_as<ExportFormat::Glb>},
      {"result.ply", export_media_type(ExportFormat::Ply), render_as<ExportFormat::Ply>},
      {"result.csv", export_media_type(ExportFormat::Csv), render_as<ExportFormat::Csv>},
  };
  return views;
}

}  // namespace lambert
