// Writing a Sheet (print/sheet.hpp) as an SVG 1.1 document (pugixml): width and height in
// millimetres with a viewBox in page millimetres, one <path> per path item (even-odd fill,
// a <title> when the item has one), every label a <text> element in the sheet's font, so
// text stays text (searchable, editable) as in the PDF. Any thread.
#pragma once

#include <string>

#include "model/result.hpp"
#include "print/sheet.hpp"

namespace geoslice::print {

// Errors: Unsupported for a sheet with raster items (sheets for SVG are vector only).
Result<std::string> renderSvg(const Sheet& sheet);

}  // namespace geoslice::print
