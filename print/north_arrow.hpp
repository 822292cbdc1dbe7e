// A north arrow for plan views (horizontal slices): an arrow pointing to grid north (up
// the sheet, the +y axis of the model's CRS) with an "N", and a line naming it grid north.
// Page millimetres. Any thread.
#pragma once

#include "print/sheet.hpp"

namespace geoslice::print {

// Appends the arrow centred on `centre`, `heightMm` tall (the "N" above it).
void drawNorthArrow(Sheet& sheet, PagePoint centre, double heightMm);

}  // namespace geoslice::print
