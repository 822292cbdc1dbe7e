#include "print/sheet.hpp"

namespace geoslice::print {

const char* fontFamilyFor(std::string_view text) {
    for (std::size_t i = 0; i < text.size();) {
        const auto b = static_cast<unsigned char>(text[i]);
        const std::size_t n = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 1;
        if (n == 3 && i + 2 < text.size()) {
            const unsigned cp = ((b & 0x0Fu) << 12) | ((static_cast<unsigned char>(text[i + 1]) & 0x3Fu) << 6) |
                                (static_cast<unsigned char>(text[i + 2]) & 0x3Fu);
            // CJK radicals .. CJK unified ideographs (incl. kana, bopomofo, CJK symbols),
            // hangul syllables, CJK compatibility ideographs, full-width forms.
            if ((cp >= 0x2E80 && cp <= 0x9FFF) || (cp >= 0xAC00 && cp <= 0xD7AF) || (cp >= 0xF900 && cp <= 0xFAFF) ||
                (cp >= 0xFF00 && cp <= 0xFFEF))
                return kCjkFontFamily;
        }
        if (n == 4) return kCjkFontFamily;  // supplementary planes: CJK extension B and beyond
        i += n;
    }
    return kFontFamily;
}

}  // namespace geoslice::print
