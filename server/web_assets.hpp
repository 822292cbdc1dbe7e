// The thin web client (web/*) and Debian's Leaflet, embedded at build time by
// server/embed_web.cmake. Served at "/" (index.html) and "/web/<path>". Any thread.
#pragma once

#include <string_view>

namespace geoslice::server {

struct WebAsset {
    std::string_view path;         // under /web/, e.g. "app.js", "leaflet/leaflet.js"
    std::string_view contentType;  // e.g. "text/javascript; charset=utf-8"
    std::string_view body;
    std::string_view etag;  // strong, quoted: a hash of the body
};

// The asset at `path` (no leading slash), or nullptr.
const WebAsset* findWebAsset(std::string_view path);
// A hash of all the assets; the page's asset URLs carry it as ?v=<id>.
std::string_view webBuildId();

}  // namespace geoslice::server
