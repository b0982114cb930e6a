#include "server/viewer_assets.h"

#include <utility>

namespace lambert {

// Defined in the source that tools/embed_assets.cmake writes into the build directory.
const std::vector<std::pair<std::string_view, std::string_view>>& viewer_asset_table();

namespace {

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// Served with X-Content-Type-Options: nosniff, so a module's type must be right or the browser
// refuses it.
std::string media_type_of(std::string_view path) {
  if (path == "/" || ends_with(path, ".html")) return "text/html; charset=utf-8";
  if (ends_with(path, ".js")) return "text/javascript; charset=utf-8";
  if (ends_with(path, ".css")) return "text/css; charset=utf-8";
  return "text/plain; charset=utf-8";
}

}  // namespace

const std::vector<ViewerAsset>& viewer_assets() {
  static const std::vector<ViewerAsset> assets = [] {
    std::vector<ViewerAsset> out;
    for (const auto& [path, bytes] : viewer_asset_table())
      out.push_back({std::string(path), media_type_of(path), bytes});
    return out;
  }();
  return assets;
}

}  // namespace lambert
