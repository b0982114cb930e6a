// The browser viewer that `lambert serve` answers at / (server/viewer/: the page and its modules),
// with three.js's module build from npm (tools/node_modules/three, pinned by
// tools/package-lock.json), compiled into the binary by tools/embed_assets.cmake. The page loads
// three.js through an import map, so the files are served as the npm release ships them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace lambert {

struct ViewerAsset {
  std::string path;        // the URL path: "/", "/viewer/app.js", "/viewer/three/three.module.js"
  std::string media_type;  // by the file's extension: "text/html; charset=utf-8", "text/javascript; ..."
  std::string_view bytes;
};

const std::vector<ViewerAsset>& viewer_assets();

}  // namespace lambert
