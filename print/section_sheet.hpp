// A geological section sheet: the section from the exact engine (section/) laid out on a
// paper size at a stated scale with the surrounds of a printed section -- elevation and
// distance axes in metres, the ends named (compass points for a straight section, A, B,
// C... for a polyline, its bends marked), scale statement and bar, vertical
// exaggeration, a legend of the units shown, a title block, and for horizontal slices a
// coordinate grid and a north arrow. The result is a Sheet (print/sheet.hpp) that
// print/cairo_output.hpp turns into PDF or a raster and print/svg_output.hpp into SVG.
//
// Geometry is the engine's polygons (plane u/v or chainage/elevation metres) mapped to page
// millimetres by print/map_frame.hpp, or, with `rasterGeometry`, the engine's own raster
// of the map box at the sheet's resolution (decorated PNG/JPEG).
// Pure functions of their inputs, any thread.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "model/result.hpp"
#include "print/map_frame.hpp"
#include "print/paper.hpp"
#include "print/sheet.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"

namespace geoslice::print {

// Colouring by a block property (section/blocks/block_section.hpp): vector sheets draw each cell's
// exact piece (cell ∩ plane ∩ clipping body; polyline legs alike) in its class colour over
// the bodies' fills, with the clipping bodies' contacts drawn again over the pieces; raster
// sheets colour a pixel by the cell under its centre where its record is a clipping body's
// (the profile images' rule, colourPixelsByBlocks); the legend ends with the ramp (the
// property, its unit and a swatch per class with its range) and the title block names the
// colouring. Cells with no value keep the body's colour.
struct SheetBlocks {
    const BlockModel* blocks = nullptr;  // outlives the sheet call
    PropertyClasses classes;
    std::vector<RecordId> clipRecords;  // blockClipRecords(model, *blocks)
};

struct SheetOptions {
    Paper paper;
    std::optional<double> scale;                // 1:S; nullopt = the smallest round scale that fits
    double exaggeration = 1.0;                  // vertical exaggeration of vertical and inclined sections
    std::optional<FrameRect> frame;             // section coordinates to show; nullopt = the section's contents
    bool rasterGeometry = false;                // the section as the engine's raster (for PNG/JPEG)
    double dpi = 150.0;                         // with rasterGeometry: the resolution the sheet is drawn at
    std::string scaleName = "scale";            // how errors name the scale (parameter or flag)
    const std::atomic<bool>* cancel = nullptr;  // read by the raster fill
    std::optional<SheetBlocks> blocks;          // colour by a block property
    // Lithology patterns over the units' colours (section/fill/patterns.hpp; units whose
    // lithology is known) and in their legend swatches; unit codes inside the polygons
    // (section/fill/labels.hpp) at labelPt points.
    bool patterns = true;
    bool labels = true;
    double labelPt = 7.0;
    // Drawn over the section's geometry, before the axes and surrounds (e.g. drillholes,
    // api/holes.hpp): items in page mm through the map frame (MapFrame::toPage of section
    // coordinates), clipped by the caller to frame.box.
    std::function<void(const MapFrame& frame, Sheet& sheet)> overlay;
};

// What the title block says about where the section came from (the caller knows).
struct SheetInfo {
    std::string model;       // model id
    std::string version;     // model version
    std::string crs;         // e.g. "EPSG:4523 CGCS2000 / 3-degree Gauss-Kruger zone 35", or "local metres"
    std::string date;        // YYYY-MM-DD
    std::string definition;  // the section's definition as asked, e.g. "plane=0,1,0,-3388846&vx=2"
    std::string title;       // the section's name ("Line 12"), first in the title; may be empty
};

// The sheet of a plane section (vertical, inclined or horizontal) or a polyline section.
// Errors: OutOfRange naming options.scaleName when a given scale does not fit the paper;
// Unsupported for a horizontal plane that keeps what lies above (seen from below);
// the raster fill's (cancelled).
Result<Sheet> sectionSheet(const SectionIndex& index, const Section& section, const SheetOptions& options,
                           const SheetInfo& info);
Result<Sheet> sectionSheet(const SectionIndex& index, const PolylineSection& section, const SheetOptions& options,
                           const SheetInfo& info);

}  // namespace geoslice::print
