// Print sheets over the API (print/section_sheet.hpp): GET section.pdf, section.svg with
// layout=print, and section.{png,jpg,webp} with decorate=1. The section is the view's
// (plane=, line= or elevation=, frame=, vx=); the sheet adds
//   paper=A0..A5|letter|tabloid   default A3
//   orientation=landscape|portrait default landscape
//   scale=S                       1:S horizontal (vertical 1:S/vx); default: the smallest round
//                                 scale (1, 2, 2.5, 5 x 10^k) at which the section fits the paper
//   dpi=50..600                   decorated images only: the sheet's resolution (default 150)
//   date=YYYY-MM-DD               the title block's date (default: today, UTC)
//   title=TEXT                    the section's name, first in the sheet's title ("Line 12";
//                                 UTF-8, at most 120 bytes, no control characters)
// `size` and `bg` do not apply (the paper sizes a sheet; it is printed on white), nor do
// perspective views. With colour= (api/plan.hpp BlockColouring) the sheet is coloured by the
// block property and its legend shows the ramp (print/section_sheet.hpp SheetBlocks).
// Errors name the parameter. Pure functions, any thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "api/catalog.hpp"
#include "api/params.hpp"
#include "api/plan.hpp"
#include "print/paper.hpp"

namespace geoslice::api {

enum class SheetFormat { Pdf, Svg, Raster };

struct SheetRequest {
    ViewPlan plan;
    SheetFormat format = SheetFormat::Pdf;
    print::Paper paper;
    std::optional<double> scale;
    double dpi = 150.0;
    std::string date;   // YYYY-MM-DD
    std::string title;  // empty: the sheet's own title only

    // Memory a render holds at its peak, bytes: for an image the sheet's pixels three times
    // (the cairo surface, the straight-alpha copy, the section raster); 0 for PDF and SVG.
    std::size_t memoryBytes() const;
    // The plan's canonical text plus the sheet's fields (cache keys, ETags).
    std::string canonical() const;
};

// The parameters a sheet adds to the view's; `layout` and `decorate` are the switches.
const std::vector<std::string_view>& sheetParamNames();

// True when a section.svg request asks for layout=print, or an image request for
// decorate=1. Errors: a bad value of `layout` (print|plain) or `decorate` (a boolean).
Result<bool> wantsSheet(const Params& params, SheetFormat format);

// Parses and checks everything before any cut (paper, orientation, scale range, dpi x
// paper within the image limits, date, and the view as parseViewPlan does). `today` is
// the default date. Errors name the parameter.
Result<SheetRequest> parseSheetRequest(const Params& params, const CatalogModel& model, SheetFormat format,
                                       const std::string& today);

struct SheetOutput {
    std::string document;  // PDF or SVG bytes
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // Raster: the sheet, opaque, rows top first
    double renderMs = 0.0;
};

// Cuts the section with the exact engine and lays out and draws the sheet. Errors: the
// cut's (a plane that misses the model), OutOfRange naming 'scale' when the given scale
// does not fit the paper, DeadlineExceeded when `cancel` turns true.
Result<SheetOutput> renderSheet(const CatalogModel& model, const SheetRequest& request,
                                const std::atomic<bool>* cancel = nullptr);

}  // namespace geoslice::api
