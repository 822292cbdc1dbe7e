// Section fills: polygons in plane u/v -> a W x H colour image and ID buffer, the same
// output a renderer gives (colour RGBA8, record ids, and the pixel -> world transform).
//
// Frames: plane u/v metres (SectionFrame) -> pixel: x = (u - u0) / pu to the right,
// y = (v1 - v) / pv downwards, row 0 at the top; pixel (i, j) covers [i, i+1) x [j, j+1)
// and its centre is (i + 0.5, j + 0.5).
//
// ID buffer: exact point sampling at pixel centres. Each region (a body's polygons, its
// holes and nested bodies included) is filled with a scanline even-odd rule; an edge
// counts on a row when its endpoints' y straddle the centre half-open (min <= yc < max)
// and a pixel is inside a span [x0, x1) when x0 <= xc < x1, so two bodies that share a
// boundary never both claim, nor both miss, a pixel centre. Regions are painted in order
// of nesting depth.
//
// Colour: exact-area coverage anti-aliasing by signed-area accumulation (the method of
// libart and stb_truetype 2, as described by R. Levien, "Inside the fastest font
// renderer in the world", 2016, font-rs): every oriented edge adds its signed coverage to
// a 4-channel accumulation buffer (premultiplied colour times area), and a prefix sum
// along each row gives, at every pixel, the sum over regions of (colour x exact covered
// area). Regions with a shared boundary therefore blend without seams (no coverage
// conflation), and the result does not depend on drawing order. Not supersampled.
// Traces (fault lines) are drawn over the colour as anti-aliased lines of
// RasterOptions::traceWidthPx (coverage from the pixel centre's distance to the segment);
// they do not enter the ID buffer, which holds bodies only (like the oracle).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "model/result.hpp"
#include "section/cut/contours.hpp"
#include "section/index/section_index.hpp"
#include "view/view_frame.hpp"
#include "view/view_limits.hpp"

namespace geoslice {

// FrameRect and PixelFrame: view/view_frame.hpp.

struct SectionImage {
    PixelFrame frame;
    std::vector<std::uint8_t> rgba;  // width * height * 4, straight (not premultiplied) alpha
    std::vector<std::uint32_t> ids;  // width * height record ids, 0 = no geology
};

struct RasterOptions {
    Rgba8 background{0, 0, 0, 0};
    bool colour = true;
    bool ids = true;
    bool traces = true;
    float traceWidthPx = 1.5f;  // 1..4
    // Cancellation: read (relaxed) at least once per image row and per region, so a fill
    // stops within a few milliseconds of it turning true and returns DeadlineExceeded.
    // Any thread may set it; nullptr = never cancelled.
    const std::atomic<bool>* cancel = nullptr;
};

// DeadlineExceeded "cancelled" when `cancel` is set (for callers between stages of work).
inline Status checkCancel(const std::atomic<bool>* cancel) {
    if (cancel && cancel->load(std::memory_order_relaxed))
        return makeError(ErrorCode::DeadlineExceeded, "cancelled: the deadline passed or the client went away");
    return {};
}

// Raster input: a region with edges oriented so that its inside has winding +1
// (counter-clockwise outers, clockwise holes); any orientation is fine for the ID buffer.
struct FillRegion {
    RecordId record = kNoRecord;
    Rgba8 colour;
    int depth = 0;                                 // painting order of the ID buffer (deeper last)
    std::vector<std::array<glm::dvec2, 2>> edges;  // plane u/v metres
};
struct FillLine {
    Rgba8 colour;
    std::vector<glm::dvec2> points;  // plane u/v metres
    bool closed = false;             // a loop: the last point joins the first
    bool pairs = false;              // independent segments (p0, p1), (p2, p3)... instead of a polyline
};

// The core fill. `out` is resized; buffers not requested by options are left empty.
Status rasterize(const FillRegion* regions, std::size_t regionCount, const FillLine* lines, std::size_t lineCount,
                 const PixelFrame& frame, const RasterOptions& options, SectionImage& out);

// Regions and lines of a section (a body's polygons -> one region).
void sectionFill(const SectionIndex& index, const Section& section, std::vector<FillRegion>& regions,
                 std::vector<FillLine>& lines);

// A rectangle around the section's contents (not the model: views use defaultFrame of
// view/view_frame.hpp), by the one framing rule fitRect: `margin` (fraction) on each side
// and square pixels for width x height.
FrameRect fitFrame(const Section& section, int width, int height, double margin = kDefaultFrameMargin);

// The full profile image of a computed section.
Result<SectionImage> rasterizeSection(const SectionIndex& index, const Section& section, const FrameRect& rect,
                                      int width, int height, const RasterOptions& options = {});
// The same into `out`, reusing its buffers (a render worker keeps one per thread).
Status rasterizeSection(const SectionIndex& index, const Section& section, const FrameRect& rect, int width, int height,
                        const RasterOptions& options, SectionImage& out);

struct TileTimings {
    double queryMs = 0.0, cutMs = 0.0, fillMs = 0.0;
    std::size_t trianglesTested = 0;
};

// One tile of the section by `plane`, straight from the BVH: only triangles crossing the
// strip u <= rect.u1, v in [v0, v1] are cut (those left of the tile decide the even-odd
// parity and the winding inside it), no contour assembly.
Result<SectionImage> renderTile(const SectionIndex& index, const Plane& plane, const FrameRect& rect, int width,
                                int height, const RasterOptions& options = {}, TileTimings* timings = nullptr);

}  // namespace geoslice
