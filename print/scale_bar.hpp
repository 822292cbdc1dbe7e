// The scale statement of a sheet: "Scale 1:5,000", a graphic scale bar in metres
// (alternating black and white segments, a round length), and for vertical sections the
// vertical scale and exaggeration. Page millimetres. Any thread.
#pragma once

#include "print/map_frame.hpp"
#include "print/sheet.hpp"

namespace geoslice::print {

// Appends the statement centred in `band` (about 22 mm high), the bar at most
// `maxBarMm` long. `vertical`: the section has a vertical axis (not a horizontal slice).
void drawScaleBar(Sheet& sheet, const PageRect& band, const MapFrame& frame, bool vertical, double maxBarMm);

// The bar's length in metres: the largest 1-2-5 length no longer than maxBarMm at 1:S.
double scaleBarMetres(double scale, double maxBarMm);

}  // namespace geoslice::print
