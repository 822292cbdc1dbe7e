// GOCAD reading: the numbered lines of an input (text checks, statements, truncation hints),
// warnings, ids and quoted words. Part of what the GOCAD readers share (model/io/gocad/gocad_reader.hpp).
#include <algorithm>
#include <cstdio>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

Lines::Lines(std::string_view text, const std::string& source) : text_(text), source_(source) {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);  // UTF-8 byte order mark
    endsWithNewline_ = text_.empty() || text_.back() == '\n';
    lastLine_ = static_cast<std::size_t>(std::count(text_.begin(), text_.end(), '\n')) + (endsWithNewline_ ? 0 : 1);
}

bool Lines::next(std::string_view& line) {
    if (!text::nextLine(text_, pos_, line)) return false;
    ++lineNo_;
    return true;
}

std::string Lines::truncationHint() const {
    if (lineNo_ == lastLine_ && !endsWithNewline_) return " (the input ends in this line: truncated file?)";
    return "";
}

Error Lines::failAt(std::size_t line, const std::string& what, ErrorCode code) const {
    std::string msg = source_ + ": line " + std::to_string(line) + ": " + what;
    if (line == lastLine_ && !endsWithNewline_ && msg.find("truncated") == std::string::npos)
        msg += " (the input ends in this line, without END: truncated file?)";
    return makeError(code, std::move(msg));
}

bool Lines::nextStatement(Statement& out, Status& bad) {
    std::string_view line;
    while (next(line)) {
        if (Status s = checkText(line, false); !s) {
            bad = s;
            return false;
        }
        std::string_view t = text::trim(line);
        if (!t.empty() && t.front() == '#') {
            // "# CTETRA region ..." (RINGMesh and OpenGeode TSolids): a tetrahedron's region in
            // a comment line; read as a CTETRA statement. Other comments are skipped.
            const std::string_view rest = text::trim(t.substr(1));
            if (rest.substr(0, 7) != "CTETRA " && rest.substr(0, 7) != "CTETRA\t") continue;
            t = rest;
        }
        if (t.empty()) continue;
        out.line = line;
        out.text = t;
        out.tokens = text::Tokens(t);
        out.keyword = {};
        out.tokens.next(out.keyword);
        return true;
    }
    return false;
}

Status Lines::checkText(std::string_view line, bool utf8) const {
    std::size_t bad = findNonText(line, utf8);
    if (bad == std::string_view::npos) return {};
    return fail(nonTextMessage(line, bad, utf8));
}

void Context::warn(std::size_t line, const std::string& what, const std::string& key) {
    if (!key.empty() && !warned.insert(key).second) return;
    warnings.push_back(lines.source() + ": line " + std::to_string(line) + ": " + what);
}

Status readId(const Lines& lines, Tokens& tokens, const std::string& what, std::uint64_t& out) {
    std::string_view tok;
    if (!tokens.next(tok)) return lines.fail(what + " is missing");
    switch (parseId(tok, out)) {
        case IdStatus::Ok:
            return {};
        case IdStatus::NotInteger:
            return lines.fail(what + " " + quoteToken(tok) + " is not a non-negative integer");
        case IdStatus::TooLarge:
            return lines.fail(what + " " + quoteToken(tok) + " is out of range");
    }
    return {};
}

std::string_view unquote(std::string_view s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
    return s;
}

}  // namespace geoslice::gocad
