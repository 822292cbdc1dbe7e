// Geo3DML reading, internal: the XML and text helpers the Geo3DML reader's files share
// (model/geo3dml_*.cpp). Elements and attributes are matched by local name, so namespace
// prefixes do not matter. Not a public header.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <variant>

#include <pugixml.hpp>

#include "model/text_scan.hpp"

namespace geoslice::geo3dml {

// Innermost elements shown in an error's element path; deeper paths start with ".../".
constexpr std::size_t kMaxPathElements = 12;
// Longest piece of input text quoted in an error message, in bytes.
constexpr std::size_t kMaxQuotedBytes = 40;

// --- small string helpers ------------------------------------------------------------------

using text::isDigits;
using text::isSpace;
using text::startsWithNoCase;
using text::trimSpace;

inline char asciiLower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }
bool isValidUtf8(std::string_view s);
inline bool contains(std::string_view s, std::string_view part) { return s.find(part) != std::string_view::npos; }

// Input text made safe to put in a message (messages end up in JSON, which needs UTF-8):
// valid UTF-8 characters are kept, control characters and invalid bytes become \xNN, and
// the result is cut at about maxBytes.
std::string quoted(std::string_view s, std::size_t maxBytes = kMaxQuotedBytes);

// --- pugixml helpers, by local name (inline: called per vertex and per triangle) -----------

inline std::string_view localName(const char* qualified) {
    std::string_view s(qualified);
    const std::size_t colon = s.rfind(':');
    return colon == std::string_view::npos ? s : s.substr(colon + 1);
}

inline bool isNamed(pugi::xml_node n, std::string_view local) {
    return n.type() == pugi::node_element && localName(n.name()) == local;
}

inline pugi::xml_node childNamed(pugi::xml_node n, std::string_view local) {
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (isNamed(c, local)) return c;
    return {};
}

inline pugi::xml_node firstElementChild(pugi::xml_node n) {
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_element) return c;
    return {};
}

inline pugi::xml_attribute attributeNamed(pugi::xml_node n, std::string_view local) {
    for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute())
        if (localName(a.name()) == local) return a;
    return {};
}

// Text content directly inside n (all PCDATA and CDATA children, in order), as decoded by
// pugixml (entities expanded, line ends normalised); not trimmed.
inline std::string textOf(pugi::xml_node n) {
    std::string s;
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
        if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) s += c.value();
    return s;
}

// Calls f(child) for each element child of `parent` named `wrapper` (using its children
// named `inner`) or named `inner` directly: Geo3DML wraps most lists twice
// (Features/Feature/GeoFeature), and some writers leave the middle level out.
template <class F>
void forEachWrapped(pugi::xml_node parent, std::string_view wrapper, std::string_view inner, F&& f) {
    for (pugi::xml_node c = parent.first_child(); c; c = c.next_sibling()) {
        if (isNamed(c, wrapper)) {
            for (pugi::xml_node d = c.first_child(); d; d = d.next_sibling())
                if (isNamed(d, inner)) f(d);
        } else if (isNamed(c, inner)) {
            f(c);
        }
    }
}

enum class Walk { Descend, Skip, Stop };

// Visits the element descendants of root in document order without recursion (inputs may
// nest arbitrarily deep). visit returns Descend, Skip (its subtree) or Stop.
template <class F>
void walkElements(pugi::xml_node root, F&& visit) {
    pugi::xml_node n = root.first_child();
    while (n) {
        Walk w = Walk::Skip;
        if (n.type() == pugi::node_element) {
            w = visit(n);
            if (w == Walk::Stop) return;
        }
        if (w == Walk::Descend && n.first_child()) {
            n = n.first_child();
            continue;
        }
        while (n != root && !n.next_sibling()) n = n.parent();
        if (n == root) return;
        n = n.next_sibling();
    }
}

// "/Geo3DModel/FeatureClasses/.../Triangle[7]/VertexList": local names, with a 1-based
// position among same-named siblings where there are several.
std::string elementPath(pugi::xml_node n);

// --- numbers ---------------------------------------------------------------------------------

// Splits on XML white space; calls f(token) for each; stops when f returns false.
template <class F>
void forEachToken(std::string_view text, F&& f) {
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && isSpace(text[i])) ++i;
        const std::size_t start = i;
        while (i < text.size() && !isSpace(text[i])) ++i;
        if (i > start && !f(text.substr(start, i - start))) return;
    }
}

// --- text encodings --------------------------------------------------------------------------

// Declared GB2312 / GBK / GB18030 (common in Chinese tools) is converted to UTF-8 here, as
// pugixml only knows the UTF and Latin-1 encodings. GB18030 is a superset of the other two.
bool declaresGbEncoding(std::string_view text);

// GB18030 -> UTF-8 with iconv. On failure returns the byte offset where it stopped.
std::variant<std::string, std::size_t> gb18030ToUtf8(std::string_view in);

}  // namespace geoslice::geo3dml
