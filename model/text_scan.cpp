#include "model/text_scan.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <system_error>

namespace geoslice::text {

std::string_view trim(std::string_view s) {
    while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
    while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
    return s;
}

std::string_view trimSpace(std::string_view s) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

std::string_view trim(std::string_view s, std::string_view set) {
    const auto b = s.find_first_not_of(set);
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(set) - b + 1);
}

bool nextLine(std::string_view text, std::size_t& pos, std::string_view& line) {
    if (pos >= text.size()) return false;
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    line = text.substr(pos, end - pos);
    pos = end < text.size() ? end + 1 : text.size();
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
}

// Length of the well-formed UTF-8 sequence at s[i], or 0 when it is not one.
std::size_t utf8Length(std::string_view s, std::size_t i) {
    auto at = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    unsigned char c = at(i);
    if (c < 0x80) return 1;
    std::size_t n;
    unsigned char lo = 0x80, hi = 0xBF;  // allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
        n = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
        n = 3;
        if (c == 0xE0) lo = 0xA0;
        if (c == 0xED) hi = 0x9F;  // no UTF-16 surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
        n = 4;
        if (c == 0xF0) lo = 0x90;
        if (c == 0xF4) hi = 0x8F;
    } else {
        return 0;
    }
    if (i + n > s.size()) return 0;
    if (at(i + 1) < lo || at(i + 1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if (at(i + k) < 0x80 || at(i + k) > 0xBF) return 0;
    return n;
}

bool isControl(unsigned char c) { return (c < 0x20 && c != '\t' && c != '\r') || c == 0x7F; }

// 0-based column of the first byte that cannot be in a line of text, or npos. Text has no
// control bytes but tab and CR; with `utf8`, it must also be well-formed UTF-8.
std::size_t findNonText(std::string_view s, bool utf8) {
    for (std::size_t i = 0; i < s.size();) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        if (isControl(c)) return i;
        if (!utf8 || c < 0x80) {
            ++i;
            continue;
        }
        std::size_t n = utf8Length(s, i);
        if (n == 0) return i;
        i += n;
    }
    return std::string_view::npos;
}

std::string nonTextMessage(std::string_view line, std::size_t column, bool utf8) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(line[column])));
    return std::string("not text: byte ") + hex + " at column " + std::to_string(column + 1) +
           (utf8 ? " (binary data, or not UTF-8)" : " (binary data?)");
}

// Names go into JSON later, which needs UTF-8: bytes of other encodings become U+FFFD.
std::string toUtf8(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size();) {
        std::size_t n = utf8Length(s, i);
        if (n == 0) {
            out += "\xEF\xBF\xBD";
            ++i;
        } else {
            out.append(s.substr(i, n));
            i += n;
        }
    }
    return out;
}

bool isUtf8(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        if (static_cast<unsigned char>(s[i]) < 0x80) {
            ++i;
            continue;
        }
        const std::size_t n = utf8Length(s, i);
        if (n == 0) return false;
        i += n;
    }
    return true;
}

std::string escapeText(std::string_view s, std::size_t maxBytes) {
    static const char* kHex = "0123456789ABCDEF";
    std::string out;
    out.reserve(std::min(s.size(), maxBytes) + 8);
    std::size_t i = 0;
    while (i < s.size() && i < maxBytes) {
        const auto c = static_cast<unsigned char>(s[i]);
        const std::size_t n = c < 0x80 ? 1 : utf8Length(s, i);
        if (n == 0 || c < 0x20 || c == 0x7F) {
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
            ++i;
        } else {
            out.append(s.substr(i, n));
            i += n;
        }
    }
    if (i < s.size()) out += "...";
    return out;
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return out;
}

bool equalsNoCase(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && equalsNoCase(s.substr(0, prefix.size()), prefix);
}

bool isDigits(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A short, printable rendering of a token for error messages.
std::string printable(std::string_view tok) {
    constexpr std::size_t kMax = 40;
    std::string out;
    for (std::size_t i = 0; i < tok.size() && i < kMax; ++i) {
        unsigned char c = static_cast<unsigned char>(tok[i]);
        if (c < 0x20 || c >= 0x7F) {
            static const char* kHex = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
        } else {
            out += static_cast<char>(c);
        }
    }
    if (tok.size() > kMax) out += "...";
    return out;
}

std::string quoteToken(std::string_view tok) { return "'" + printable(tok) + "'"; }

std::optional<double> parseDouble(std::string_view tok) { return parseNumber<double>(tok); }

std::optional<double> parseXsDouble(std::string_view tok) {
    if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
    double v = 0.0;
    const char* end = tok.data() + tok.size();
    const auto [ptr, ec] = std::from_chars(tok.data(), end, v);
    if (ptr != end) return std::nullopt;
    if (ec == std::errc::result_out_of_range) {
        // from_chars leaves v untouched when the value is beyond a double.
        const std::size_t e = tok.find_first_of("eE");
        if (e != std::string_view::npos && e + 1 < tok.size() && tok[e + 1] == '-') return 0.0;
        return std::numeric_limits<double>::infinity();
    }
    if (ec != std::errc()) return std::nullopt;
    return v;
}

IntStatus parseInt(std::string_view tok, std::int64_t& out) {
    if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
    const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    if (ec == std::errc::result_out_of_range) return IntStatus::TooLarge;
    if (ec != std::errc() || end != tok.data() + tok.size()) return IntStatus::NotInteger;
    return IntStatus::Ok;
}

IntStatus parseUnsigned(std::string_view tok, std::uint64_t& out) {
    if (tok.empty() || tok[0] < '0' || tok[0] > '9') return IntStatus::NotInteger;
    const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    if (ec == std::errc::result_out_of_range) return IntStatus::TooLarge;
    if (ec != std::errc() || end != tok.data() + tok.size()) return IntStatus::NotInteger;
    return IntStatus::Ok;
}

bool Tokens::next(std::string_view& tok) {
    while (!rest_.empty() && isBlank(rest_.front())) rest_.remove_prefix(1);
    if (rest_.empty() || (comment_ != '\0' && rest_.front() == comment_)) return false;
    std::size_t n = 0;
    while (n < rest_.size() && !isBlank(rest_[n])) ++n;
    tok = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return true;
}

std::vector<std::string> csvRecord(std::string_view text, std::size_t& pos, bool& badQuote, char separator) {
    std::vector<std::string> fields;
    std::string cur;
    bool inQuotes = false;
    badQuote = false;
    while (pos < text.size()) {
        const char c = text[pos++];
        if (inQuotes) {
            if (c == '"') {
                if (pos < text.size() && text[pos] == '"') {
                    cur += '"';
                    ++pos;
                } else {
                    inQuotes = false;
                }
            } else {
                cur += c;
            }
        } else if (c == '"') {
            inQuotes = true;
        } else if (c == separator) {
            fields.push_back(std::move(cur));
            cur.clear();
        } else if (c == '\n') {
            break;
        } else if (c != '\r') {
            cur += c;
        }
    }
    if (inQuotes) badQuote = true;
    fields.push_back(std::move(cur));
    return fields;
}

}  // namespace geoslice::text
