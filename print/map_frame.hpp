// The map frame of a printed section: which rectangle of the section (u/v or chainage/
// elevation, metres) is drawn into which box on the page (mm), at which scale.
//
// Scales: the horizontal axis is at 1:S (one metre of ground = 1000 / S mm), the vertical
// at 1:(S / k) with vertical exaggeration k (horizontal slices: k = 1, both axes are map
// axes). Auto-fit picks the smallest round S (print/map_scale.hpp) at which the extent fits
// the area; a given S must fit, else the error names the largest round scale that does.
// Pure functions, any thread.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "model/result.hpp"
#include "print/sheet.hpp"
#include "section/fill/raster.hpp"

namespace geoslice::print {

// Ticks are never closer than this on paper (labels of elevations and distances).
constexpr double kMinTickSpacingMm = 10.0;

struct MapFrame {
    FrameRect shown;  // section coordinates drawn in the box, metres
    PageRect box;     // page mm
    double scale = 5000.0;
    double exaggeration = 1.0;

    double mmPerMetreX() const { return 1000.0 / scale; }
    double mmPerMetreY() const { return 1000.0 * exaggeration / scale; }
    PagePoint toPage(const glm::dvec2& uv) const {
        return {box.x + (uv.x - shown.u0) * mmPerMetreX(), box.y + (shown.v1 - uv.y) * mmPerMetreY()};
    }
};

struct FitRequest {
    FrameRect extent;                  // what must be shown, metres (u1 > u0, v1 > v0)
    PageRect area;                     // the most the box may take, mm
    std::optional<double> scale;       // 1:S given; nullopt = auto-fit
    double exaggeration = 1.0;         // k > 0
    bool snapU = false, snapV = true;  // grow the shown range to whole tick steps where it still fits
    std::string scaleName = "scale";   // how errors name the scale (a parameter or a flag)
    std::string areaName;              // how errors name the area, e.g. "A4 landscape"
};

// The frame: the (snapped) extent at the scale, centred in the area.
// Errors: OutOfRange naming `scaleName` when a given scale does not fit, OutOfRange when
// no scale up to kMaxScale fits; InvalidArgument for an empty or non-finite extent.
Result<MapFrame> fitMapFrame(const FitRequest& request);

}  // namespace geoslice::print
