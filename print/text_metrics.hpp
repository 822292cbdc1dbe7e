// Text widths for layout, measured with cairo's font machinery in the font both outputs
// name (sheet.hpp kFontFamily), so boxes sized from them fit the text in the PDF, the
// raster and (with that font installed) the SVG. Any thread (each call has its own cairo
// context; cairo's font caches are locked internally).
#pragma once

#include <string>
#include <string_view>
#include <vector>

typedef struct _cairo cairo_t;

namespace geoslice::print {

// Unhinted metrics and outlines, so that a glyph's advance is the font's own at every
// size and resolution (hinted metrics round advances to device pixels, which would make
// measured widths depend on the surface). Every cairo context that measures or draws
// sheet text applies them.
void applyLayoutFontOptions(cairo_t* cr);

// Advance width (mm) of UTF-8 `text` at `sizePt` points.
double textWidthMm(std::string_view text, double sizePt, bool bold = false);

// `text` cut at a code point and ended with an ellipsis so that it is at most `maxWidthMm`
// wide (unchanged when it fits; "…" alone when nothing else fits).
std::string fitText(const std::string& text, double maxWidthMm, double sizePt, bool bold = false);

// `text` broken at spaces and after commas into at most `maxLines` lines of at most `maxWidthMm` (greedy);
// a word longer than a line, or text left over after the last line, is cut by fitText.
std::vector<std::string> wrapText(const std::string& text, double maxWidthMm, double sizePt, std::size_t maxLines,
                                  bool bold = false);

}  // namespace geoslice::print
