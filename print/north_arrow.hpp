// A north arrow for plan views (horizontal slices): an arrow pointing to grid north (up
// the sheet, the +y axis of the model's CRS) with an "N", a line naming it grid north, and
// where the CRS is projected how far true north lies from it (print/grid_convergence.hpp).
// Page millimetres. Any thread.
#pragma once

#include <optional>

#include "print/sheet.hpp"

namespace geoslice::print {

// Appends the arrow centred on `centre`, `heightMm` tall (the "N" above it). `trueNorthDeg`:
// true north's azimuth from grid north (degrees clockwise), stated under the arrow.
void drawNorthArrow(Sheet& sheet, PagePoint centre, double heightMm, std::optional<double> trueNorthDeg);

}  // namespace geoslice::print
