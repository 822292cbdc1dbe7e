// Drawing a Sheet (print/sheet.hpp) with cairo (Debian's libcairo2): a PDF document of one
// page the size of the sheet, vector paths and text as text (fonts embedded as subsets),
// or an RGBA raster of the sheet at a resolution. Any thread (each call owns its surface).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "model/result.hpp"
#include "print/sheet.hpp"

namespace geoslice::print {

// The PDF bytes. Metadata: title, subject, creator "geoslice", creation date = sheet.date
// (so the same sheet gives the same bytes). Errors: Internal with cairo's status text.
Result<std::string> renderPdf(const Sheet& sheet);

struct SheetRaster {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // straight alpha (opaque: a white page), rows top first
};
// The sheet's pixel size at `dpi`: round(mm x dpi / 25.4) per side.
int sheetPixels(double mm, double dpi);
// The sheet on a white page at `dpi` dots per inch. Errors: OutOfRange when the image would
// exceed view/view_limits.hpp's sizes (names the size), Internal for cairo failures.
Result<SheetRaster> renderRaster(const Sheet& sheet, double dpi);

}  // namespace geoslice::print
