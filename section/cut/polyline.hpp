// Vertical sections along a map polyline A-B-C... (a bent section, like ParaView's
// SliceAlongPolyLine or the BGS Groundhog viewer): the section is unrolled into one plane
// whose coordinates are s = distance along the line from A (metres, the chainage) and
// z = elevation (world metres).
//
// Method: each leg P[k] -> P[k+1] is cut by its vertical plane (normal = the leg's
// direction turned 90 degrees left, so the kept side is left of the line and the leg's
// SectionFrame has u along the leg and v = up: view/plane.hpp) with the exact engine
// (section/cut/contours.hpp), and the leg's polygons and traces are clipped to its chainage
// range [s_k, s_k+1] (Sutherland-Hodgman per ring against the two lines s = s_k and
// s = s_k+1; clipped rings may run along those lines, which changes no area and no
// pixel). A pixel centre at a leg junction s_k belongs to the leg that starts there.
//
// Frames: map points and world points are double, x east, y north, z up, metres in the
// model's CRS. Line coordinates (s, z) play the role of plane u/v in section/fill/raster.hpp:
// pixel x = (s - s0) / ps to the right, y = (z1 - z) / pz down, row 0 at the top.
// Thread-safety: pure functions; the index may be shared by any number of threads.
#pragma once

#include <cstdint>
#include <vector>

#include "model/result.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/raster.hpp"
#include "section/index/section_index.hpp"

namespace geoslice {

// The line itself: its map vertices and their chainage; maps (s, z) to world points.
struct SectionLine {
    std::vector<glm::dvec2> points;  // world map x, y (metres); consecutive points distinct
    std::vector<double> chainage;    // s at each point: 0, |P1 - P0|, ...
    double length() const { return chainage.empty() ? 0.0 : chainage.back(); }
    // The leg that owns chainage s: k with chainage[k] <= s < chainage[k + 1] (the first leg
    // below 0, the last at or beyond the end).
    std::size_t legAt(double s) const;
    // World map point at chainage s (extrapolated along the first/last leg outside [0, length]).
    glm::dvec2 mapAt(double s) const;
    glm::dvec3 worldAt(double s, double z) const {
        const glm::dvec2 p = mapAt(s);
        return {p.x, p.y, z};
    }
};

// Checks and cleans a polyline: at least 2 points, all finite, consecutive duplicates
// (closer than 1 mm) dropped, at most 256 points (as the HTTP API), length finite.
// Errors: InvalidArgument naming the point or the count.
Result<SectionLine> makeSectionLine(const std::vector<glm::dvec2>& points);

struct PolylineLeg {
    Plane plane;                // world; the kept side is left of the leg
    double s0 = 0.0, s1 = 0.0;  // chainage range
    double uOffset = 0.0;       // s = u + uOffset for this leg's SectionFrame u
    bool cut = false;           // false: the leg's plane misses the model's bounding box
};

struct PolylineSection {
    SectionLine line;
    std::vector<PolylineLeg> legs;
    // Bodies and traces in line coordinates (s, z), clipped to their legs; a body cut by
    // several legs has the polygons of all of them (they meet, unmerged, at the junctions);
    // `area` sums them (m²). Ascending part index. Traces carry the surface part index.
    std::vector<BodySection> bodies;
    std::vector<SectionTrace> traces;
    glm::dvec2 lo{0.0}, hi{0.0};  // bounding box of every ring and trace, (s, z) metres
    bool empty() const { return bodies.empty() && traces.empty(); }
};

// Cuts every leg and clips; a leg whose map segment misses the model's map extent is not
// cut (PolylineLeg::cut = false). Errors: those of makeSectionLine; OutOfRange when no leg
// meets the model's map extent (names the line's ends and the extent).
Result<PolylineSection> computePolylineSection(const SectionIndex& index, const std::vector<glm::dvec2>& points,
                                               const SectionOptions& options = {});

// A rectangle around the contents (s, z) by the framing rule fitRect (view/view_frame.hpp):
// `margin` (fraction) on each side, square pixels for width x height. Views use
// defaultLineFrame (the model's elevation range) instead.
FrameRect fitPolylineFrame(const PolylineSection& section, int width, int height, double margin = kDefaultFrameMargin);

// The image of a polyline section and its pixel -> world mapping.
struct PolylineImage {
    SectionLine line;
    FrameRect rect;  // u = s (chainage), v = z (elevation), metres
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4, straight alpha (as SectionImage)
    std::vector<std::uint32_t> ids;  // width * height record ids, 0 = no geology

    double pixelS() const { return (rect.u1 - rect.u0) / width; }   // metres of chainage per pixel
    double pixelZ() const { return (rect.v1 - rect.v0) / height; }  // metres of elevation per pixel
    // Pixel coordinates (x right, y down; centre of pixel (i, j) is (i + 0.5, j + 0.5)) -> (s, z).
    glm::dvec2 pixelToLine(double x, double y) const { return {rect.u0 + x * pixelS(), rect.v1 - y * pixelZ()}; }
    glm::dvec2 lineToPixel(const glm::dvec2& sz) const {
        return {(sz.x - rect.u0) / pixelS(), (rect.v1 - sz.y) / pixelZ()};
    }
    // Chainage and world point of the centre of pixel (i, j).
    double pixelCentreChainage(int i) const { return rect.u0 + (i + 0.5) * pixelS(); }
    glm::dvec3 pixelCentreWorld(int i, int j) const {
        const glm::dvec2 sz = pixelToLine(i + 0.5, j + 0.5);
        return line.worldAt(sz.x, sz.y);
    }
};

// Fills the section into width x height pixels of `rect` (line coordinates): colour with
// exact-coverage anti-aliasing and the exact ID buffer, as section/fill/raster.hpp.
// Errors: those of checkFrame.
Result<PolylineImage> rasterizePolylineSection(const SectionIndex& index, const PolylineSection& section,
                                               const FrameRect& rect, int width, int height,
                                               const RasterOptions& options = {});

// Clips a ring (any orientation) to the strip lo <= x <= hi (Sutherland-Hodgman);
// the result may have edges along x = lo and x = hi. Empty when nothing is left.
Ring clipRingToStrip(const Ring& ring, double lo, double hi);

}  // namespace geoslice
