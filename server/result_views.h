// Other forms of a finished job's result, served beside it: GET /v1/jobs/{id}/result.glb,
// result.ply and result.csv (server/export/export_formats.h). Query parameters: shading=smooth|flat
// and white=CD_M2, as the options of `lambert export`. The HTTP server routes each view through the
// same job lookup as GET /v1/jobs/{id}/result; this file knows nothing of HTTP.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace lambert {

struct ResultViewOutcome {
  std::string body;
  std::string error;  // non-empty: a query parameter was wrong (HTTP 400), naming it
};

struct ResultView {
  std::string file;        // the last path segment, "result.glb"
  std::string media_type;  // "model/gltf-binary"
  ResultViewOutcome (*render)(const std::string& result_json, const std::multimap<std::string, std::string>& query);
};

const std::vector<ResultView>& result_views();

}  // namespace lambert
