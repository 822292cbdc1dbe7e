// Geo3DML reading, internal: string, element-path and text-encoding helpers
// (model/io/geo3dml/geo3dml_xml.hpp).
#include "model/io/geo3dml/geo3dml_xml.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include <iconv.h>

namespace geoslice::geo3dml {

bool isValidUtf8(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t len = text::utf8Length(s, i);
        if (len == 0) return false;
        i += len;
    }
    return true;
}

// Input text made safe to put in a message (messages end up in JSON, which needs UTF-8):
// valid UTF-8 characters are kept, control characters and invalid bytes become \xNN, and
// the result is cut at about maxBytes.
std::string quoted(std::string_view s, std::size_t maxBytes) {
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        if (out.size() >= maxBytes) {
            out += "...";
            break;
        }
        const std::size_t len = text::utf8Length(s, i);
        const auto c = static_cast<unsigned char>(s[i]);
        if (len == 0 || c < 0x20 || c == 0x7F) {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 0xF];
            i += 1;
        } else {
            out.append(s.substr(i, len));
            i += len;
        }
    }
    return out;
}

// "/Geo3DModel/FeatureClasses/.../Triangle[7]/VertexList": local names, with a 1-based
// position among same-named siblings where there are several.
std::string elementPath(pugi::xml_node n) {
    std::vector<std::string> parts;
    bool truncated = false;
    for (; n && n.type() == pugi::node_element; n = n.parent()) {
        if (parts.size() == kMaxPathElements) {
            truncated = true;
            break;
        }
        const std::string_view name = localName(n.name());
        std::size_t position = 1, same = 1;
        for (pugi::xml_node s = n.previous_sibling(); s; s = s.previous_sibling())
            if (s.type() == pugi::node_element && localName(s.name()) == name) ++position, ++same;
        for (pugi::xml_node s = n.next_sibling(); s && same < 2; s = s.next_sibling())
            if (s.type() == pugi::node_element && localName(s.name()) == name) ++same;
        std::string part = quoted(name);
        if (same > 1) {
            part += '[';
            part += std::to_string(position);
            part += ']';
        }
        parts.push_back(std::move(part));
    }
    std::string path = truncated ? "..." : "";
    for (auto it = parts.rbegin(); it != parts.rend(); ++it) path += "/" + *it;
    return path;
}

bool declaresGbEncoding(std::string_view text) {
    if (!startsWithNoCase(text, "<?xml")) return false;
    const std::size_t end = text.find("?>");
    if (end == std::string_view::npos || end > 1024) return false;
    const std::string decl = text::lower(text.substr(0, end));
    std::size_t at = decl.find("encoding");
    if (at == std::string::npos) return false;
    at = decl.find_first_of("\"'", at);
    if (at == std::string::npos) return false;
    const std::size_t close = decl.find(decl[at], at + 1);
    if (close == std::string::npos) return false;
    const std::string enc = decl.substr(at + 1, close - at - 1);
    return enc == "gb2312" || enc == "gbk" || enc == "gb18030" || enc == "cp936" || enc == "x-gbk" || enc == "euc-cn";
}

std::variant<std::string, std::size_t> gb18030ToUtf8(std::string_view in) {
    iconv_t cd = iconv_open("UTF-8", "GB18030");
    if (cd == reinterpret_cast<iconv_t>(-1)) return std::size_t(0);
    std::string out;
    out.resize(in.size() + in.size() / 2 + 16);  // GB18030 -> UTF-8 grows by at most 1.5x
    char* inPtr = const_cast<char*>(in.data());  // iconv's interface is not const-correct
    std::size_t inLeft = in.size();
    char* outPtr = out.data();
    std::size_t outLeft = out.size();
    const std::size_t r = iconv(cd, &inPtr, &inLeft, &outPtr, &outLeft);
    iconv_close(cd);
    if (r == static_cast<std::size_t>(-1) || inLeft != 0) return static_cast<std::size_t>(inPtr - in.data());
    out.resize(out.size() - outLeft);
    return out;
}

}  // namespace geoslice::geo3dml
