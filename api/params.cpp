#include "api/params.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace geoslice::api {
namespace {

// Quotes a piece of user text for an error message, cut to a readable length.
std::string quoted(std::string_view text) {
    std::string out = "'";
    const std::size_t n = std::min<std::size_t>(text.size(), 64);
    for (std::size_t i = 0; i < n; ++i) {
        const char c = text[i];
        out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
    }
    if (text.size() > n) out += "...";
    return out + "'";
}

Error bad(std::string_view name, std::string_view text, std::string_view what,
          ErrorCode code = ErrorCode::InvalidArgument) {
    // A command-line flag ("--size") is named as it is; an HTTP parameter as "parameter 'size'".
    const std::string named = name.starts_with("--") ? std::string(name) : "parameter '" + std::string(name) + "'";
    return Error{code, named + ": " + quoted(text) + " " + std::string(what)};
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

}  // namespace

std::optional<std::string_view> param(const Params& params, std::string_view name) {
    const auto it = params.find(name);
    if (it == params.end()) return std::nullopt;
    return std::string_view(it->second);
}

Result<double> parseNumber(std::string_view name, std::string_view text) {
    const std::string_view t = trim(text);
    if (t.empty()) return bad(name, text, "is empty, expected a number");
    double v = 0.0;
    const char* first = t.data();
    if (*first == '+') ++first;
    const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range)
        return bad(name, text, "is out of the range of a double", ErrorCode::OutOfRange);
    if (ec != std::errc() || end != t.data() + t.size()) return bad(name, text, "is not a number");
    if (!std::isfinite(v)) return bad(name, text, "is not a finite number");
    return v;
}

Result<long long> parseInteger(std::string_view name, std::string_view text, long long lo, long long hi) {
    const std::string_view t = trim(text);
    long long v = 0;
    const char* first = t.data();
    if (!t.empty() && *first == '+') ++first;
    const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v);
    if (t.empty() || ec == std::errc::invalid_argument || end != t.data() + t.size())
        return bad(name, text, "is not a whole number");
    if (ec == std::errc::result_out_of_range || v < lo || v > hi)
        return bad(name, text, "is outside " + std::to_string(lo) + ".." + std::to_string(hi), ErrorCode::OutOfRange);
    return v;
}

Result<std::vector<double>> parseNumberList(std::string_view name, std::string_view text, std::size_t count,
                                            std::size_t maxCount) {
    std::vector<double> values;
    std::string_view rest = text;
    while (true) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        if (values.size() >= maxCount)
            return bad(name, text, "has more than " + std::to_string(maxCount) + " values", ErrorCode::OutOfRange);
        auto v = parseNumber(name, item);
        if (!v) return bad(name, text, "has a value " + quoted(item) + " that is not a finite number");
        values.push_back(v.value());
        if (comma == std::string_view::npos) break;
        rest.remove_prefix(comma + 1);
    }
    if (count != 0 && values.size() != count)
        return bad(name, text, "has " + std::to_string(values.size()) + " values, expected " + std::to_string(count));
    return values;
}

Result<Size2> parseSize(std::string_view name, std::string_view text, int maxSide, long long maxPixels) {
    std::size_t sep = text.find_first_of("x,X");
    if (sep == std::string_view::npos) return bad(name, text, "is not WIDTHxHEIGHT");
    auto w = parseInteger(name, text.substr(0, sep), -(1LL << 40), 1LL << 40);
    auto h = parseInteger(name, text.substr(sep + 1), -(1LL << 40), 1LL << 40);
    if (!w || !h) return bad(name, text, "is not WIDTHxHEIGHT in whole pixels");
    const std::string range = "1.." + std::to_string(maxSide);
    if (w.value() < 1 || w.value() > maxSide)
        return bad(name, text, "has a width outside " + range, ErrorCode::OutOfRange);
    if (h.value() < 1 || h.value() > maxSide)
        return bad(name, text, "has a height outside " + range, ErrorCode::OutOfRange);
    if (w.value() * h.value() > maxPixels)
        return bad(name, text, "has more than " + std::to_string(maxPixels) + " pixels", ErrorCode::OutOfRange);
    return Size2{int(w.value()), int(h.value())};
}

Result<Rgba8> parseBackground(std::string_view name, std::string_view text) {
    if (text == "transparent" || text == "none") return Rgba8{0, 0, 0, 0};
    std::string t(text);
    if (!t.empty() && t[0] != '#') t = "#" + t;
    if (auto c = parseColour(t)) return *c;
    return bad(name, text, "is not 'transparent' or a colour #rrggbb[aa]");
}

Result<bool> parseBool(std::string_view name, std::string_view text) {
    if (text == "1" || text == "true" || text == "yes") return true;
    if (text == "0" || text == "false" || text == "no") return false;
    return bad(name, text, "is not true/false or 1/0");
}

Status checkKnownParams(const Params& params, const std::vector<std::string_view>& known) {
    std::string unknown;
    int count = 0;
    for (const auto& [name, value] : params) {
        if (name == kVersionParam || std::find(known.begin(), known.end(), std::string_view(name)) != known.end())
            continue;
        if (count++ < 8) unknown += (unknown.empty() ? "" : ", ") + api::quoted(name);
    }
    if (count == 0) return {};
    std::string list;
    for (std::string_view k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    return makeError(ErrorCode::InvalidArgument,
                     std::string(count == 1 ? "unknown parameter " : "unknown parameters ") + unknown +
                         (count > 8 ? " and more" : "") + "; known: " + list);
}

std::string formatNumber(double value) {
    if (value == 0.0) value = 0.0;  // -0 -> 0
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    return ec == std::errc() ? std::string(buf, end) : std::string("nan");
}

}  // namespace geoslice::api
