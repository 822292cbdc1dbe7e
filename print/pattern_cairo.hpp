// Lithology patterns (section/fill/patterns.hpp) and unit labels (section/fill/labels.hpp)
// drawn with cairo: a repeating pattern source for sheets (PDF tiling patterns, sheet
// rasters) and the overlays of section images (section.png?patterns=1&labels=1), drawn
// into the straight-alpha RGBA8 image through a cairo image surface, so that images use the
// sheets' fonts (DejaVu Sans, WenQuanYi Micro Hei for CJK) and the same tiles.
// Any thread (each call owns its surfaces).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "model/attributes.hpp"
#include "section/fill/labels.hpp"
#include "section/fill/patterns.hpp"
#include "view/view_frame.hpp"

typedef struct _cairo_pattern cairo_pattern_t;

namespace geoslice::print {

// A repeating pattern of `l`'s tile at `unitsPerMm` user units per millimetre (the caller
// destroys it with cairo_pattern_destroy); nullptr for Lithology::None.
cairo_pattern_t* lithologyPattern(Lithology l, double unitsPerMm);

// Each pixel whose record (ids, width x height, 0 = none) has a lithology gets that
// lithology's pattern composited over its colour; tiles at `pxPerMm` pixels a millimetre
// (96 dpi: 3.78), aligned with the image's top-left corner. rgba: straight alpha.
void drawPatternsOnImage(std::uint8_t* rgba, const std::uint32_t* ids, int width, int height,
                         const std::function<Lithology(RecordId)>& lithologyOf, double pxPerMm);

struct ImageLabel {
    PlacedLabel label;
    Rgba8 box;  // the box's fill (the unit's colour), drawn under the text
    Rgba8 ink;  // the text's colour
};
// Draws the labels' boxes and texts (font size `sizePx`, centred on label.at, the baseline
// of section/fill/labels.hpp labelBaseline) into the image.
void drawLabelsOnImage(std::uint8_t* rgba, int width, int height, const std::vector<ImageLabel>& labels, double sizePx);

struct ImageDecorations {
    bool labels = false;
    bool patterns = false;
    double labelPx = 12.0;         // font size of the labels, pixels
    double pxPerMm = 96.0 / 25.4;  // pattern tiles' scale
};
// A section image's decorations: patterns over the units' pixels (by `ids`; none without
// ids), then the unit codes placed in the bodies' polygons (section frame `rect` -> pixels
// as the raster maps it), each on a box of its unit's colour, clear of the `traces`.
void decorateSectionImage(const SectionIndex& index, const std::vector<BodySection>& bodies, const FrameRect& rect,
                          int width, int height, std::uint8_t* rgba, const std::uint32_t* ids,
                          const ImageDecorations& options, const std::vector<SectionTrace>* traces = nullptr);

// Advance width (pixels) of `text` at a font size of `sizePx` pixels, in the sheets' fonts.
double labelTextWidth(const std::string& text, double sizePx);

}  // namespace geoslice::print
