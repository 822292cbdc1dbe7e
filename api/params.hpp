// Request parameters: a flat name -> text map (an HTTP query string, or the fields of a
// JSON body) and the typed readers that turn one field into a number, a list or a size.
// Every error is InvalidArgument or OutOfRange and names the parameter and the bad text,
// e.g. "parameter 'size': '0x512' has a width outside 1..8192". No HTTP headers here.
// Pure functions, any thread.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "model/attributes.hpp"
#include "model/result.hpp"

namespace geoslice::api {

using Params = std::map<std::string, std::string, std::less<>>;

// The text of `name`, or nullopt when absent.
std::optional<std::string_view> param(const Params& params, std::string_view name);

// A finite double. NaN, Inf, empty text and trailing junk are errors.
Result<double> parseNumber(std::string_view name, std::string_view text);
// A whole number in [lo, hi].
Result<long long> parseInteger(std::string_view name, std::string_view text, long long lo, long long hi);
// Comma-separated finite doubles; `count` = exact count wanted, 0 = any (at least one);
// at most `maxCount` values.
Result<std::vector<double>> parseNumberList(std::string_view name, std::string_view text, std::size_t count = 0,
                                            std::size_t maxCount = 4096);
// "WxH" (also "W,H"), each side in [1, maxSide], and W*H <= maxPixels.
struct Size2 {
    int width = 0, height = 0;
};
Result<Size2> parseSize(std::string_view name, std::string_view text, int maxSide, long long maxPixels);
// "transparent", "#rrggbb", "#rrggbbaa" or "rrggbb".
Result<Rgba8> parseBackground(std::string_view name, std::string_view text);
// "1", "true", "yes", "0", "false", "no".
Result<bool> parseBool(std::string_view name, std::string_view text);

// InvalidArgument naming every parameter of `params` that is not in `known`, so that a
// misspelt parameter is an error instead of silently ignored. `version` (the model content version
// a URL names, kVersionParam) is known everywhere: server/routes/common.hpp checks it.
Status checkKnownParams(const Params& params, const std::vector<std::string_view>& known);
constexpr std::string_view kVersionParam = "version";

// Shortest text that reads back to the same double (std::to_chars); -0 prints as 0.
std::string formatNumber(double value);

}  // namespace geoslice::api
