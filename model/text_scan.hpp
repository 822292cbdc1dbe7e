// The text-scanning helpers every text loader shares (OBJ, GOCAD, Geo3DML, VTU, attribute
// tables and block-model CSV, CRS text): blanks and trimming, line splitting, UTF-8 checks,
// printable token quoting for error messages, number parsing without locale or exceptions,
// the one CSV record reader and a whitespace tokenizer. No loader keeps its own copy.
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace geoslice::text {

// Inline: loaders call these per byte (an out-of-line call per byte cost the VTU ASCII reader
// 12 % of its load CPU).
inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }  // blanks within one line
std::string_view trim(std::string_view s);                                  // without leading and trailing blanks
inline bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }  // XML's S, CSV, JSON
std::string_view trimSpace(std::string_view s);
// Without leading and trailing characters of `set` (e.g. " \t\n\v\f\r", C's isspace).
std::string_view trim(std::string_view s, std::string_view set);

// The physical line at text[pos] (up to '\n', a '\r' before it dropped); `pos` advances past
// the '\n'. False at the end of the text.
bool nextLine(std::string_view text, std::size_t& pos, std::string_view& line);

// Length of the well-formed UTF-8 sequence at s[i], or 0 when it is not one.
std::size_t utf8Length(std::string_view s, std::size_t i);
bool isControl(unsigned char c);  // control bytes other than tab and CR
// 0-based column of the first byte that cannot be in a line of text, or npos. Text has no
// control bytes but tab and CR; with `utf8`, it must also be well-formed UTF-8.
std::size_t findNonText(std::string_view s, bool utf8);
// The message for the byte findNonText found at `column` of `line`: "not text: byte 0x01 at
// column 7 (binary data?)", with "(binary data, or not UTF-8)" when `utf8`.
std::string nonTextMessage(std::string_view line, std::size_t column, bool utf8);
// Bytes that are not UTF-8 become U+FFFD (names go into JSON, which needs UTF-8).
std::string toUtf8(std::string_view s);
// True when every byte of `s` belongs to a well-formed UTF-8 sequence (RFC 3629: no
// overlong forms, no surrogates, nothing past U+10FFFF). Control characters are UTF-8.
bool isUtf8(std::string_view s);
// `s` made safe to show in an error message, a log line, JSON or SVG: well-formed UTF-8 is
// kept as it is (names in Chinese stay readable), every byte that is not, and every control
// character, becomes \xNN; cut to `maxBytes` of input with "..." after. The one place where
// text taken from a request or a file is made printable (the request path uses it for
// paths, parameters and headers; problem() for every detail it sends).
std::string escapeText(std::string_view s, std::size_t maxBytes = 256);
std::string lower(std::string_view s);                               // ASCII only
bool equalsNoCase(std::string_view a, std::string_view b);           // ASCII letters folded
bool startsWithNoCase(std::string_view s, std::string_view prefix);  // ASCII letters folded
bool isDigits(std::string_view s);                                   // non-empty, '0'..'9' only
// A short, printable rendering of a token for error messages: 'abc', '\x01...' (the first 40
// bytes, bytes outside printable ASCII as \xNN); printable() is the same without the quotes.
std::string quoteToken(std::string_view tok);
std::string printable(std::string_view tok);
// The whole token as an arithmetic T (std::from_chars: no locale, no white space), a leading
// '+' allowed when no sign follows it; nullopt when it is not one or is out of T's range.
template <class T>
std::optional<T> parseNumber(std::string_view tok) {
    if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
    T v{};
    const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || end != tok.data() + tok.size()) return std::nullopt;
    return v;
}
// The whole token as a double (parseNumber), else nullopt. NaN/Inf parse: the caller decides
// whether they are allowed.
std::optional<double> parseDouble(std::string_view tok);
// The same with XML Schema's xs:double rule for magnitudes beyond a double: a negative
// exponent underflows to 0, anything else overflows to +infinity (callers refuse non-finite).
std::optional<double> parseXsDouble(std::string_view tok);

enum class IntStatus { Ok, NotInteger, TooLarge };
// The whole token as a signed integer (a leading '+' as parseNumber allows it).
IntStatus parseInt(std::string_view tok, std::int64_t& out);
// The whole token as an unsigned integer: digits only, no sign.
IntStatus parseUnsigned(std::string_view tok, std::uint64_t& out);

// The fields of one CSV record (RFC 4180: quoted fields may hold separators, doubled
// quotes and line ends) starting at text[pos]; `pos` advances past the record's line end
// ('\n', a '\r' before it dropped). `badQuote` is set when a quote is not closed. The one
// CSV reader of the project (attribute tables, block models).
std::vector<std::string> csvRecord(std::string_view text, std::size_t& pos, bool& badQuote, char separator = ',');

// Whitespace-separated tokens of one line; when `comment` is set, a token starting with
// it ends the line.
class Tokens {
public:
    explicit Tokens(std::string_view s, char comment = '\0') : rest_(s), comment_(comment) {}
    bool next(std::string_view& tok);
    std::string_view rest() const { return trim(rest_); }

private:
    std::string_view rest_;
    char comment_;
};

}  // namespace geoslice::text
