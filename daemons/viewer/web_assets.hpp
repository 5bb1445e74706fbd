#pragma once
/// @file The page's files (daemons/viewer/web/), embedded into the binary at build time
/// (embed_web.cmake writes web_assets.cpp): the installed viewer needs no source tree and
/// fetches nothing from elsewhere.

#include <string_view>
#include <vector>

namespace coopnav::viewer {

struct WebAsset {
  const char* path;          ///< URL path, e.g. "/viewer.js"
  const char* content_type;  ///< e.g. "text/javascript; charset=utf-8"
  std::string_view body;
};

/// Every embedded file; "/index.html" is also served at "/".
const std::vector<WebAsset>& webAssets();

}  // namespace coopnav::viewer
