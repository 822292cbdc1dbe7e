// Small text-scanning helpers shared by the text-format loaders (OBJ, GOCAD TSurf):
// blanks and trimming, UTF-8 checks, printable token quoting for error messages, number
// parsing without locale or exceptions, and a whitespace tokenizer.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace geoslice::text {

bool isBlank(char c);  // space, tab or CR
std::string_view trim(std::string_view s);
// Length of the well-formed UTF-8 sequence at s[i], or 0 when it is not one.
std::size_t utf8Length(std::string_view s, std::size_t i);
bool isControl(unsigned char c);  // control bytes other than tab and CR
// 0-based column of the first byte that cannot be in a line of text, or npos. Text has no
// control bytes but tab and CR; with `utf8`, it must also be well-formed UTF-8.
std::size_t findNonText(std::string_view s, bool utf8);
// Bytes that are not UTF-8 become U+FFFD (names go into JSON, which needs UTF-8).
std::string toUtf8(std::string_view s);
std::string lower(std::string_view s);  // ASCII only
// A short, printable rendering of a token for error messages: 'abc', '\x01...'.
std::string quoteToken(std::string_view tok);
// The whole token as a double (a leading '+' allowed), else nullopt. NaN/Inf parse: the
// caller decides whether they are allowed.
std::optional<double> parseDouble(std::string_view tok);

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
