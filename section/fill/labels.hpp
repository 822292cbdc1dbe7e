// Unit labels inside section polygons: each polygon of a body gets its unit's code (T3x,
// J2s...) at a point well inside it, when the text's box fits inside the polygon there and
// does not overlap a label already placed.
//
// The point is the polygon's pole of inaccessibility -- the interior point farthest from
// its rings (outer and holes) -- found by the polylabel algorithm of Mapbox
// (V. Agafonkin, "A new algorithm for finding a visual center of a polygon", 2016,
// github.com/mapbox/polylabel, ISC licence): a quadtree of square cells in a priority queue
// ordered by the best distance a cell could still hold (centre distance + half diagonal),
// split until no cell can beat the best found by more than `precision`. Written here from
// the paper's description.
//
// Placement is greedy, largest polygons (clipped to the view) first: a label is kept only
// when its whole box lies inside the polygon (its centre inside and no ring edge crossing
// the box), inside the view, and clear of every box placed before (with a gap). Tiny
// polygons get none. All in the output's frame (x right, y down: SVG or image pixels,
// sheet millimetres). Pure functions, any thread.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

struct LabelBox {
    double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;  // x0 <= x1, y0 <= y1
    bool overlaps(const LabelBox& o, double gap = 0.0) const {
        return x0 < o.x1 + gap && o.x0 < x1 + gap && y0 < o.y1 + gap && o.y0 < y1 + gap;
    }
};

// Pole of inaccessibility of the polygon of `rings` (even-odd: the first is usually the
// outer, the rest holes; any order works). Returns the point and, in `distance`, its
// signed distance to the nearest ring edge (positive inside). Empty rings: (0, 0), -inf.
glm::dvec2 poleOfInaccessibility(const std::vector<Ring>& rings, double precision, double* distance = nullptr);

// The box lies inside the polygon of `rings` (even-odd): its centre is inside and no ring
// edge meets the box.
bool boxInsidePolygon(const LabelBox& box, const std::vector<Ring>& rings);

// The code a unit's labels show: the record's extra column named code, unit_code, symbol,
// label or abbrev (case-insensitive, first found), else a short code in brackets at the end
// of its age ("Late Triassic (T3x)" -> "T3x"), else its name, else `fallback`.
std::string unitCode(const AttributeRecord* record, const std::string& fallback);

struct LabelCandidate {
    std::string text;
    std::vector<Ring> rings;  // output frame; rings[0] the outer, then holes
    double width = 0.0;       // the text's box (output units), centred on the label point
    double height = 0.0;
    RecordId record = kNoRecord;
    std::uint32_t part = 0;
};

struct PlacedLabel {
    std::string text;
    glm::dvec2 at{0.0};  // box centre (output frame)
    LabelBox box;
    RecordId record = kNoRecord;
    std::uint32_t part = 0;
};

// Greedy placement (see above) of `candidates` inside `view` with `gap` between boxes; a box
// that meets one of the `obstacles` (polylines in the output frame: fault traces) is dropped too.
std::vector<PlacedLabel> placeLabels(const std::vector<LabelCandidate>& candidates, const LabelBox& view,
                                     double gap = 0.0, const std::vector<std::vector<glm::dvec2>>& obstacles = {});

// Geometry of a label's text at font size `size` (output units, em): its box and where
// the baseline goes. Box height 1.0 em plus padding (DejaVu Sans: ascender 0.76, descender 0.24).
struct LabelStyle {
    double size = 12.0;     // font size (output units)
    double padding = 0.15;  // em, each side
    // Advance width of `text` at `size` output units; default: an estimate for DejaVu Sans
    // that errs wide (0.62 em a Latin letter or digit, 0.8 upper case, 1.0 a CJK character).
    std::function<double(const std::string& text, double size)> textWidth;
};
double estimateTextWidth(const std::string& text, double size);
// The baseline's y for a box centred at `centreY`.
inline double labelBaseline(double centreY, double size) { return centreY + 0.26 * size; }

// Candidates for every polygon of the bodies: rings mapped by `toOutput` (section u/v ->
// output frame) and clipped to `view`, text from unitCode of the body's record (name of
// the part as fallback).
std::vector<LabelCandidate> sectionLabelCandidates(const SectionIndex& index, const std::vector<BodySection>& bodies,
                                                   const std::function<glm::dvec2(const glm::dvec2&)>& toOutput,
                                                   const LabelBox& view, const LabelStyle& style);

// sectionLabelCandidates then placeLabels with a gap of 0.3 em, clear of the `traces`
// (surfaces' traces: faults, horizons) when given.
std::vector<PlacedLabel> sectionLabels(const SectionIndex& index, const std::vector<BodySection>& bodies,
                                       const std::function<glm::dvec2(const glm::dvec2&)>& toOutput,
                                       const LabelBox& view, const LabelStyle& style,
                                       const std::vector<SectionTrace>* traces = nullptr);

}  // namespace geoslice
