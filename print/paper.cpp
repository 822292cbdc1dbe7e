#include "print/paper.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <utility>

namespace geoslice::print {
namespace {

struct Known {
    const char* name;
    double shortMm, longMm;
};
// ISO 216 A series (rounded to whole millimetres, as the standard states them) and ANSI.
constexpr std::array<Known, 8> kPapers{{{"A0", 841, 1189},
                                        {"A1", 594, 841},
                                        {"A2", 420, 594},
                                        {"A3", 297, 420},
                                        {"A4", 210, 297},
                                        {"A5", 148, 210},
                                        {"LETTER", 215.9, 279.4},
                                        {"TABLOID", 279.4, 431.8}}};

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

std::string Paper::describe() const {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %s, %g x %g mm", name.c_str(),
                  orientation == Orientation::Landscape ? "landscape" : "portrait", widthMm, heightMm);
    return buf;
}

Result<Paper> paperSize(std::string_view name, Orientation orientation) {
    const std::string key = upper(name);
    for (const Known& k : kPapers) {
        if (key != k.name) continue;
        Paper p;
        p.name = k.name;
        p.orientation = orientation;
        p.widthMm = orientation == Orientation::Landscape ? k.longMm : k.shortMm;
        p.heightMm = orientation == Orientation::Landscape ? k.shortMm : k.longMm;
        return p;
    }
    return makeError(ErrorCode::InvalidArgument,
                     "'" + std::string(name) + "' is not a paper size: use A0, A1, A2, A3, A4, A5, letter or tabloid");
}

Result<Orientation> parseOrientation(std::string_view text) {
    const std::string key = upper(text);
    if (key == "LANDSCAPE") return Orientation::Landscape;
    if (key == "PORTRAIT") return Orientation::Portrait;
    return makeError(ErrorCode::InvalidArgument,
                     "'" + std::string(text) + "' is not an orientation: use landscape or portrait");
}

}  // namespace geoslice::print
