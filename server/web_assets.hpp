// The thin web client (web/index.html), embedded at build time and served at "/".
#pragma once

#include <string_view>

namespace geoslice::server {

std::string_view webIndexHtml();

}  // namespace geoslice::server
