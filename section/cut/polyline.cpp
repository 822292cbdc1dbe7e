#include "section/cut/polyline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>

namespace geoslice {
namespace {

constexpr std::size_t kMaxLinePoints = 256;  // as api/plan.hpp's kMaxLineVertices
constexpr double kMinLeg = 1e-3;             // metres: closer consecutive points are one point

// Clips against one vertical line: keeps x >= c (keepRight) or x <= c.
Ring clipHalf(const Ring& in, double c, bool keepRight) {
    Ring out;
    const std::size_t n = in.size();
    if (n == 0) return out;
    auto inside = [&](const glm::dvec2& p) { return keepRight ? p.x >= c : p.x <= c; };
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2& p = in[i];
        const glm::dvec2& q = in[(i + 1) % n];
        const bool ip = inside(p), iq = inside(q);
        if (ip) out.push_back(p);
        if (ip != iq) {
            const double t = (c - p.x) / (q.x - p.x);
            out.push_back({c, p.y + t * (q.y - p.y)});
        }
    }
    return out;
}

// Appends the parts of polyline `pts` (closed: last joins first) inside lo <= x <= hi.
void clipPolyline(const std::vector<glm::dvec2>& pts, bool closed, double lo, double hi,
                  std::vector<std::vector<glm::dvec2>>& out) {
    std::vector<glm::dvec2> run;
    auto flush = [&] {
        if (run.size() >= 2) out.push_back(run);
        run.clear();
    };
    const std::size_t n = pts.size(), segs = closed ? n : n - 1;
    for (std::size_t i = 0; i < segs; ++i) {
        glm::dvec2 a = pts[i], b = pts[(i + 1) % n];
        double t0 = 0.0, t1 = 1.0;
        const double dx = b.x - a.x;
        if (dx == 0.0) {
            if (a.x < lo || a.x > hi) t1 = -1.0;
        } else {
            double ta = (lo - a.x) / dx, tb = (hi - a.x) / dx;
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta);
            t1 = std::min(t1, tb);
        }
        if (t0 > t1) {
            flush();
            continue;
        }
        const glm::dvec2 p = t0 == 0.0 ? a : a + t0 * (b - a), q = t1 == 1.0 ? b : a + t1 * (b - a);
        if (run.empty() || run.back() != p) {
            flush();
            run.push_back(p);
        }
        run.push_back(q);
        if (t1 < 1.0) flush();
    }
    flush();
}

// Whether the map segment a-b meets the rectangle [lo, hi] (Liang-Barsky).
bool segmentMeetsRect(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& lo, const glm::dvec2& hi) {
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 2; ++k) {
        const double d = b[k] - a[k];
        if (d == 0.0) {
            if (a[k] < lo[k] || a[k] > hi[k]) return false;
            continue;
        }
        double ta = (lo[k] - a[k]) / d, tb = (hi[k] - a[k]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

void extendBox(glm::dvec2& lo, glm::dvec2& hi, const std::vector<glm::dvec2>& pts) {
    for (const auto& p : pts) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
}

}  // namespace

std::size_t SectionLine::legAt(double s) const {
    const std::size_t legs = points.size() < 2 ? 0 : points.size() - 1;
    if (legs == 0) return 0;
    const auto it = std::upper_bound(chainage.begin(), chainage.end(), s);
    const std::size_t k = it == chainage.begin() ? 0 : static_cast<std::size_t>(it - chainage.begin()) - 1;
    return std::min(k, legs - 1);
}

glm::dvec2 SectionLine::mapAt(double s) const {
    if (points.size() < 2) return points.empty() ? glm::dvec2(0.0) : points[0];
    const std::size_t k = legAt(s);
    const glm::dvec2 d = (points[k + 1] - points[k]) / (chainage[k + 1] - chainage[k]);
    return points[k] + (s - chainage[k]) * d;
}

Result<SectionLine> makeSectionLine(const std::vector<glm::dvec2>& points) {
    if (points.size() < 2)
        return makeError(ErrorCode::InvalidArgument,
                         "a section line needs at least 2 points (got " + std::to_string(points.size()) + ")");
    if (points.size() > kMaxLinePoints)
        return makeError(ErrorCode::InvalidArgument, "a section line has at most " + std::to_string(kMaxLinePoints) +
                                                         " points (got " + std::to_string(points.size()) + ")");
    SectionLine line;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const glm::dvec2& p = points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            return makeError(ErrorCode::InvalidArgument,
                             "section line point " + std::to_string(i) + " has a non-finite coordinate");
        if (!line.points.empty() && glm::length(p - line.points.back()) < kMinLeg) continue;
        line.chainage.push_back(line.points.empty() ? 0.0 : line.chainage.back() + glm::length(p - line.points.back()));
        line.points.push_back(p);
    }
    if (line.points.size() < 2)
        return makeError(ErrorCode::InvalidArgument, "the section line has zero length (all points within 1 mm)");
    if (!std::isfinite(line.length()))
        return makeError(ErrorCode::InvalidArgument, "the section line's length overflows (coordinates too large)");
    return line;
}

Ring clipRingToStrip(const Ring& ring, double lo, double hi) {
    Ring r = clipHalf(ring, lo, true);
    r = clipHalf(r, hi, false);
    // Drop repeated points the clip may have produced.
    Ring out;
    for (const auto& p : r)
        if (out.empty() || out.back() != p) out.push_back(p);
    while (out.size() > 1 && out.back() == out.front()) out.pop_back();
    if (out.size() < 3) out.clear();
    return out;
}

Result<PolylineSection> computePolylineSection(const SectionIndex& index, const std::vector<glm::dvec2>& points,
                                               const SectionOptions& options) {
    auto line = makeSectionLine(points);
    if (!line) return line.error();
    PolylineSection out;
    out.line = std::move(line).value();
    const SectionLine& L = out.line;
    std::map<std::uint32_t, BodySection> bodies;
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    std::size_t legsCut = 0;
    for (std::size_t k = 0; k + 1 < L.points.size(); ++k) {
        PolylineLeg leg;
        leg.s0 = L.chainage[k];
        leg.s1 = L.chainage[k + 1];
        const glm::dvec2 a = L.points[k], b = L.points[k + 1];
        const glm::dvec2 d = (b - a) / glm::length(b - a);
        const glm::dvec3 n(-d.y, d.x, 0.0);  // left of a -> b: the frame's u is then along the leg
        leg.plane = Plane{n, -(n.x * a.x + n.y * a.y)};
        const glm::dvec2 mapLo(index.bounds.min.x, index.bounds.min.y), mapHi(index.bounds.max.x, index.bounds.max.y);
        if (!segmentMeetsRect(a, b, mapLo, mapHi)) {  // the leg runs beside the model: nothing to cut
            out.legs.push_back(leg);
            continue;
        }
        auto checked = checkSectionPlane(index, leg.plane);
        if (!checked) {
            if (checked.error().code != ErrorCode::OutOfRange) return checked.error();
            out.legs.push_back(leg);
            continue;
        }
        leg.plane = checked.value();
        auto sec = computeSection(index, leg.plane, options);
        if (!sec) return sec.error();
        leg.cut = true;
        ++legsCut;
        const Section& s = sec.value();
        leg.uOffset = leg.s0 - s.frame.toPlane(glm::dvec3(a.x, a.y, 0.0) - s.frame.modelOrigin).x;
        const glm::dvec2 shift(leg.uOffset, 0.0);
        for (const BodySection& bs : s.bodies) {
            BodySection* dst = nullptr;
            for (const SectionPolygon& poly : bs.polygons) {
                Ring outer = poly.outer;
                for (auto& p : outer) p += shift;
                outer = clipRingToStrip(outer, leg.s0, leg.s1);
                if (outer.empty()) continue;
                SectionPolygon cp;
                cp.outer = std::move(outer);
                double area = ringArea(cp.outer);
                for (const Ring& h : poly.holes) {
                    Ring hole = h;
                    for (auto& p : hole) p += shift;
                    hole = clipRingToStrip(hole, leg.s0, leg.s1);
                    if (hole.empty()) continue;
                    area += ringArea(hole);  // clockwise: negative
                    cp.holes.push_back(std::move(hole));
                }
                if (!dst) {
                    dst = &bodies[bs.part];
                    dst->part = bs.part;
                    dst->record = bs.record;
                }
                extendBox(lo, hi, cp.outer);
                dst->area += area;
                dst->polygons.push_back(std::move(cp));
            }
            if (dst || bs.openChains) {
                BodySection& body = bodies[bs.part];
                body.part = bs.part;
                body.record = bs.record;
                body.openChains += bs.openChains;
            }
        }
        for (const SectionTrace& t : s.traces) {
            std::vector<glm::dvec2> pts = t.points;
            for (auto& p : pts) p += shift;
            std::vector<std::vector<glm::dvec2>> runs;
            clipPolyline(pts, t.closed, leg.s0, leg.s1, runs);
            for (auto& r : runs) {
                extendBox(lo, hi, r);
                out.traces.push_back(SectionTrace{t.part, t.record, std::move(r), false});
            }
        }
        out.legs.push_back(leg);
    }
    if (legsCut == 0) {
        const Aabb& b = index.bounds;
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "the section line from (%.3f, %.3f) to (%.3f, %.3f) misses the model: its map extent is "
                      "x %.3f..%.3f, y %.3f..%.3f",
                      L.points.front().x, L.points.front().y, L.points.back().x, L.points.back().y, b.min.x, b.max.x,
                      b.min.y, b.max.y);
        return makeError(ErrorCode::OutOfRange, buf);
    }
    for (auto& [part, b] : bodies) out.bodies.push_back(std::move(b));
    out.lo = lo.x <= hi.x ? lo : glm::dvec2(0.0);
    out.hi = lo.x <= hi.x ? hi : glm::dvec2(0.0);
    return out;
}

FrameRect fitPolylineFrame(const PolylineSection& section, int width, int height, double margin) {
    return fitRect(section.lo, section.hi, width, height, 1.0, margin);
}

Result<PolylineImage> rasterizePolylineSection(const SectionIndex& index, const PolylineSection& section,
                                               const FrameRect& rect, int width, int height,
                                               const RasterOptions& options) {
    if (Status s = checkFrame(rect, width, height); !s) return s.error();
    Section flat;  // the same fill rules as a plane section, in (s, z)
    flat.bodies = section.bodies;
    flat.traces = section.traces;
    std::vector<FillRegion> regions;
    std::vector<FillLine> lines;
    sectionFill(index, flat, regions, lines);
    PixelFrame frame;  // the raster reads only rect and size
    frame.rect = rect;
    frame.width = width;
    frame.height = height;
    SectionImage img;
    if (Status s = rasterize(regions.data(), regions.size(), lines.data(), lines.size(), frame, options, img); !s)
        return s.error();
    PolylineImage out;
    out.line = section.line;
    out.rect = rect;
    out.width = width;
    out.height = height;
    out.rgba = std::move(img.rgba);
    out.ids = std::move(img.ids);
    return out;
}

}  // namespace geoslice
