#include "section/fill/raster.hpp"
#include "model/clock.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

namespace geoslice {
namespace {

struct Float4 {
    float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
};

Float4 premultiplied(Rgba8 c) {
    const float a = c.a / 255.0f;
    return {c.r / 255.0f * a, c.g / 255.0f * a, c.b / 255.0f * a, a};
}

// Pixel coordinates of plane u/v points (x right, y down).
struct ToPixel {
    double u0, v1, sx, sy;
    explicit ToPixel(const PixelFrame& f) : u0(f.rect.u0), v1(f.rect.v1), sx(1.0 / f.pixelU()), sy(1.0 / f.pixelV()) {}
    glm::dvec2 operator()(const glm::dvec2& uv) const { return {(uv.x - u0) * sx, (v1 - uv.y) * sy}; }
};

int clampIndex(double x, int lo, int hi) {
    if (!(x > lo)) return lo;  // also NaN
    if (x > hi) return hi;
    return static_cast<int>(x);
}

// ---- ID buffer: scanline even-odd fill at pixel centres --------------------------------

struct ScanScratch {
    std::vector<std::array<glm::dvec2, 2>> px;  // edges in pixel coordinates, y0 < y1
    std::vector<std::uint32_t> rowStart;
    std::vector<double> xs;
};

bool isSet(const std::atomic<bool>* cancel) { return cancel && cancel->load(std::memory_order_relaxed); }

void fillRegionIds(const FillRegion& region, const ToPixel& toPx, int W, int H, std::uint32_t* ids, ScanScratch& s,
                   const std::atomic<bool>* cancel) {
    s.px.clear();
    for (const auto& e : region.edges) {
        glm::dvec2 a = toPx(e[0]), b = toPx(e[1]);
        // Canonical order (y, then x) so an edge shared by two regions gives the same crossings.
        if (a.y > b.y || (a.y == b.y && a.x > b.x)) std::swap(a, b);
        if (a.y == b.y || b.y <= 0.0 || a.y >= H) continue;
        s.px.push_back({a, b});
    }
    s.rowStart.assign(static_cast<std::size_t>(H) + 1, 0);
    auto rows = [&](const std::array<glm::dvec2, 2>& e, int& j0, int& j1) {
        // Rows whose centre yc = j + 0.5 satisfies y0 <= yc < y1.
        j0 = clampIndex(std::ceil(e[0].y - 0.5), 0, H);
        j1 = clampIndex(std::ceil(e[1].y - 0.5), 0, H);
    };
    for (const auto& e : s.px) {
        int j0, j1;
        rows(e, j0, j1);
        for (int j = j0; j < j1; ++j) ++s.rowStart[static_cast<std::size_t>(j) + 1];
    }
    std::partial_sum(s.rowStart.begin(), s.rowStart.end(), s.rowStart.begin());
    s.xs.resize(s.rowStart.back());
    std::vector<std::uint32_t> fill(s.rowStart.begin(), s.rowStart.end() - 1);
    for (const auto& e : s.px) {
        int j0, j1;
        rows(e, j0, j1);
        const double dxdy = (e[1].x - e[0].x) / (e[1].y - e[0].y);
        for (int j = j0; j < j1; ++j) s.xs[fill[static_cast<std::size_t>(j)]++] = e[0].x + (j + 0.5 - e[0].y) * dxdy;
    }
    for (int j = 0; j < H; ++j) {
        if ((j & 63) == 0 && isSet(cancel)) return;
        double* x = s.xs.data() + s.rowStart[static_cast<std::size_t>(j)];
        const std::size_t n = s.rowStart[static_cast<std::size_t>(j) + 1] - s.rowStart[static_cast<std::size_t>(j)];
        if (n == 0) continue;
        for (std::size_t i = 1; i < n; ++i)  // insertion sort: a few crossings per row
            for (std::size_t k = i; k > 0 && x[k - 1] > x[k]; --k) std::swap(x[k - 1], x[k]);
        std::uint32_t* row = ids + static_cast<std::size_t>(j) * static_cast<std::size_t>(W);
        for (std::size_t k = 0; k < n; k += 2) {
            // Pixel i is inside when x0 <= i + 0.5 < x1.
            const int i0 = clampIndex(std::ceil(x[k] - 0.5), 0, W);
            const int i1 = k + 1 < n ? clampIndex(std::ceil(x[k + 1] - 0.5), 0, W) : W;  // open strip: to the edge
            if (i1 > i0) std::fill(row + i0, row + i1, region.record);
        }
    }
}

// ---- colour: signed-area accumulation (font-rs), one row at a time --------------------

// A piece of an edge in pixel coordinates with y0 < y1 and x within [0, W]; dir = +1 when
// the original edge goes down (y increasing): the area to its right gains coverage.
struct Piece {
    float x0, y0, x1, y1, dxdy, dir;
    Float4 c;
};

struct ColourRaster {
    int W = 0, H = 0;
    std::vector<Piece> pieces;
    std::vector<std::uint32_t> rowStart;  // pieces sorted by first row (counting sort)
    std::vector<std::uint32_t> order;
    std::vector<Float4> row;             // W + 2 cells: x may reach W
    std::vector<std::uint64_t> touched;  // one bit per cell of `row` written this row
    std::vector<std::uint32_t> active;

    // Splits an edge where it leaves [0, W]; pieces left of the frame move onto x = 0
    // (they still decide the coverage inside it), pieces right of it onto x = W.
    void addEdge(glm::dvec2 a, glm::dvec2 b, const Float4& c) {
        float dir = 1.0f;
        if (a.y > b.y || (a.y == b.y && a.x > b.x)) {  // canonical order: shared edges split identically
            std::swap(a, b);
            dir = -1.0f;
        }
        if (!(a.y < b.y) || b.y <= 0.0 || a.y >= H) return;  // also NaN
        // Clip to rows 0..H in double, from the canonical endpoints (so shared edges still
        // split identically): the float pieces then hold image-sized numbers only.
        if (a.y < 0.0 || b.y > H) {
            const glm::dvec2 a0 = a, d = b - a;
            if (a.y < 0.0) a = {a0.x + d.x * ((0.0 - a0.y) / d.y), 0.0};
            if (b.y > H) b = {a0.x + d.x * ((H - a0.y) / d.y), double(H)};
            if (!(a.y < b.y)) return;
        }
        const double fw = W;
        double ts[4] = {0.0, 1.0, 1.0, 1.0};
        int n = 1;
        for (double border : {0.0, fw})
            if ((a.x < border) != (b.x < border)) {
                const double t = (border - a.x) / (b.x - a.x);
                if (t > 0.0 && t < 1.0) ts[n++] = t;
            }
        ts[n++] = 1.0;
        if (n == 4 && ts[1] > ts[2]) std::swap(ts[1], ts[2]);  // the two border crossings, in order
        for (int k = 0; k + 1 < n; ++k) {
            const double t0 = ts[k], t1 = ts[k + 1];
            if (t1 <= t0) continue;
            const double ya = t0 == 0.0 ? a.y : a.y + (b.y - a.y) * t0, yb = t1 == 1.0 ? b.y : a.y + (b.y - a.y) * t1;
            double xa = t0 == 0.0 ? a.x : a.x + (b.x - a.x) * t0, xb = t1 == 1.0 ? b.x : a.x + (b.x - a.x) * t1;
            const double xm = 0.5 * (xa + xb);
            xa = std::clamp(xa, 0.0, fw);
            xb = std::clamp(xb, 0.0, fw);
            if (xm <= 0.0) xa = xb = 0.0;
            if (xm >= fw) xa = xb = fw;
            if (!(yb > ya) || yb <= 0.0 || ya >= H) continue;
            Piece p{float(xa), float(ya), float(xb), float(yb), 0.0f, dir, c};
            if (!(p.y1 > p.y0)) continue;
            p.dxdy = (p.x1 - p.x0) / (p.y1 - p.y0);
            pieces.push_back(p);
        }
    }

    void add(std::size_t i, float d, const Float4& c) {
        touched[i >> 6] |= std::uint64_t(1) << (i & 63);
        Float4& a = row[i];
        a.r += d * c.r;
        a.g += d * c.g;
        a.b += d * c.b;
        a.a += d * c.a;
    }

    // The part of piece p within row y, after font-rs's accumulate (exact signed area of
    // the piece's trapezoids per cell, stored as differences along the row).
    void step(const Piece& p, int y) {
        const float ya = std::max(float(y), p.y0), yb = std::min(float(y + 1), p.y1);
        const float dy = yb - ya;
        if (!(dy > 0.0f)) return;
        const float fw = float(W);
        const float x = std::clamp(p.x0 + (ya - p.y0) * p.dxdy, 0.0f, fw);
        const float xnext = std::clamp(p.x0 + (yb - p.y0) * p.dxdy, 0.0f, fw);
        const float d = dy * p.dir;
        const float xa = std::min(x, xnext), xb = std::max(x, xnext);
        const float xaFloor = std::floor(xa);
        const int xai = static_cast<int>(xaFloor);
        const float xbCeil = std::ceil(xb);
        const int xbi = static_cast<int>(xbCeil);
        const std::size_t base = static_cast<std::size_t>(xai);
        if (xbi <= xai + 1) {
            const float xmf = 0.5f * (x + xnext) - xaFloor;
            add(base, d - d * xmf, p.c);
            add(base + 1, d * xmf, p.c);
            return;
        }
        const float s = 1.0f / (xb - xa);
        const float xaf = xa - xaFloor;
        const float a0 = 0.5f * s * (1.0f - xaf) * (1.0f - xaf);
        const float xbf = xb - xbCeil + 1.0f;
        const float am = 0.5f * s * xbf * xbf;
        add(base, d * a0, p.c);
        if (xbi == xai + 2) {
            add(base + 1, d * (1.0f - a0 - am), p.c);
        } else {
            const float a1 = s * (1.5f - xaf);
            add(base + 1, d * (a1 - a0), p.c);
            for (int xi = xai + 2; xi < xbi - 1; ++xi) add(static_cast<std::size_t>(xi), d * s, p.c);
            const float a2 = a1 + float(xbi - xai - 3) * s;
            add(static_cast<std::size_t>(xbi - 1), d * (1.0f - a2 - am), p.c);
        }
        add(static_cast<std::size_t>(xbi), d * am, p.c);
    }

    // Prefix sum of row y's cells, composited over the background; clears the row. Cells
    // no edge touched keep the running sum, so they repeat the previous pixel (whole words
    // of the touched bitmap at a time).
    void resolveRow(const Float4& bg, std::uint32_t* out) {
        Float4 s;
        std::uint32_t last = pixel(s, bg);
        int i = 0;
        while (i < W) {
            const std::size_t w = static_cast<std::size_t>(i) >> 6;
            std::uint64_t bits = touched[w] >> (i & 63);
            if (bits == 0) {
                const int next = std::min(W, static_cast<int>((w + 1) << 6));
                std::fill(out + i, out + next, last);
                i = next;
                continue;
            }
            const int skip = std::countr_zero(bits);
            if (skip > 0) {
                std::fill(out + i, out + i + skip, last);
                i += skip;
                if (i >= W) break;
            }
            Float4& c = row[static_cast<std::size_t>(i)];
            s.r += c.r;
            s.g += c.g;
            s.b += c.b;
            s.a += c.a;
            c = Float4{};
            last = pixel(s, bg);
            out[i++] = last;
        }
        row[static_cast<std::size_t>(W)] = Float4{};
        row[static_cast<std::size_t>(W) + 1] = Float4{};
        std::fill(touched.begin(), touched.end(), 0);
    }

    static std::uint32_t pixel(const Float4& s, const Float4& bg) {
        const float a = std::clamp(s.a, 0.0f, 1.0f);
        const float k = 1.0f - a;
        const float oa = a + k * bg.a;
        std::uint8_t o[4] = {0, 0, 0, 0};
        if (oa > 0.0f) {
            const float inv = 255.0f / oa;
            o[0] = static_cast<std::uint8_t>(std::clamp((s.r + k * bg.r) * inv, 0.0f, 255.0f) + 0.5f);
            o[1] = static_cast<std::uint8_t>(std::clamp((s.g + k * bg.g) * inv, 0.0f, 255.0f) + 0.5f);
            o[2] = static_cast<std::uint8_t>(std::clamp((s.b + k * bg.b) * inv, 0.0f, 255.0f) + 0.5f);
            o[3] = static_cast<std::uint8_t>(oa * 255.0f + 0.5f);
        }
        std::uint32_t v;
        std::memcpy(&v, o, 4);
        return v;
    }

    void run(const Rgba8& background, std::uint8_t* rgba, const std::atomic<bool>* cancel) {
        rowStart.assign(static_cast<std::size_t>(H) + 1, 0);
        auto firstRow = [&](const Piece& p) { return std::max(0, static_cast<int>(std::floor(p.y0))); };
        for (const Piece& p : pieces) ++rowStart[static_cast<std::size_t>(std::min(firstRow(p), H - 1)) + 1];
        std::partial_sum(rowStart.begin(), rowStart.end(), rowStart.begin());
        order.resize(pieces.size());
        {
            std::vector<std::uint32_t> fill(rowStart.begin(), rowStart.end() - 1);
            for (std::uint32_t i = 0; i < pieces.size(); ++i)
                order[fill[static_cast<std::size_t>(std::min(firstRow(pieces[i]), H - 1))]++] = i;
        }
        row.assign(static_cast<std::size_t>(W) + 2, Float4{});
        touched.assign((static_cast<std::size_t>(W) + 2 + 63) / 64, 0);
        const Float4 bg = premultiplied(background);
        active.clear();
        for (int y = 0; y < H; ++y) {
            if (isSet(cancel)) return;
            for (std::uint32_t k = rowStart[static_cast<std::size_t>(y)]; k < rowStart[static_cast<std::size_t>(y) + 1];
                 ++k)
                active.push_back(order[k]);
            for (std::size_t k = 0; k < active.size();) {
                const Piece& p = pieces[active[k]];
                step(p, y);
                if (float(y + 1) >= p.y1) {
                    active[k] = active.back();
                    active.pop_back();
                } else {
                    ++k;
                }
            }
            resolveRow(
                bg, reinterpret_cast<std::uint32_t*>(rgba) + static_cast<std::size_t>(y) * static_cast<std::size_t>(W));
        }
    }
};

// ---- traces: anti-aliased lines over the colour image ------------------------------------

void drawLine(const FillLine& line, const ToPixel& toPx, float width, int W, int H, std::vector<std::uint8_t>& cov,
              std::vector<std::uint32_t>& touched, const std::atomic<bool>* cancel) {
    const double hw = 0.5 * width;
    auto segment = [&](glm::dvec2 p, glm::dvec2 q) {
        // Clip to the image grown by the line's reach (Liang-Barsky): pixels of the image
        // see the same distances, and every loop below is bounded by the image size, not
        // by the segment's length in pixels (which a tiny frame makes astronomical).
        {
            const double pad = hw + 2.0;
            const double lo[2] = {-pad, -pad}, hi[2] = {W + pad, H + pad};
            double t0 = 0.0, t1 = 1.0;
            const glm::dvec2 dd = q - p;
            for (int k = 0; k < 2; ++k) {
                if (!std::isfinite(p[k]) || !std::isfinite(q[k])) return;
                if (dd[k] == 0.0) {
                    if (p[k] < lo[k] || p[k] > hi[k]) return;
                    continue;
                }
                double ta = (lo[k] - p[k]) / dd[k], tb = (hi[k] - p[k]) / dd[k];
                if (ta > tb) std::swap(ta, tb);
                t0 = std::max(t0, ta);
                t1 = std::min(t1, tb);
            }
            if (!(t0 <= t1)) return;
            const glm::dvec2 p0 = p + t0 * dd, q0 = p + t1 * dd;
            p = p0;
            q = q0;
        }
        const glm::dvec2 d = q - p;
        const double len2 = glm::dot(d, d);
        const bool xMajor = std::abs(d.x) >= std::abs(d.y);
        // A pixel is covered only when its centre lies within r of the segment.
        const double r = hw + 0.5;
        auto plot = [&](int i, int j) {
            if (i < 0 || j < 0 || i >= W || j >= H) return;
            const glm::dvec2 c(i + 0.5, j + 0.5);
            const double t = len2 > 0.0 ? std::clamp(glm::dot(c - p, d) / len2, 0.0, 1.0) : 0.0;
            const glm::dvec2 off = c - (p + t * d);
            const double dist2 = glm::dot(off, off);
            // r * r is exact (r has at most 25 significant bits) and sqrt is correctly rounded,
            // so dist2 >= r * r means dist >= r: no coverage, the same answer without the root.
            if (dist2 >= r * r) return;
            const double cv = std::clamp(r - std::sqrt(dist2), 0.0, 1.0);
            if (cv <= 0.0) return;
            const std::size_t k =
                static_cast<std::size_t>(j) * static_cast<std::size_t>(W) + static_cast<std::size_t>(i);
            const auto c8 = static_cast<std::uint8_t>(cv * 255.0 + 0.5);
            if (cov[k] == 0) touched.push_back(static_cast<std::uint32_t>(k));
            cov[k] = std::max(cov[k], c8);
        };
        // Walk the major axis over the columns whose centre lies within r of the segment's
        // extent (reach r + 0.5 from the extent to the column's left edge); in each, visit the
        // minor-axis pixels whose centre lies within r of the segment's line, measured along
        // the minor axis: r * sqrt(1 + slope^2) (the segment's points are on that line, so no
        // covered pixel is left out; 1e-3 px of slack for the rounding of `centre`).
        const int a = xMajor ? 0 : 1, b = 1 - a;
        const int lim = xMajor ? W : H;
        const double reach = r + 0.5;
        const double lo = std::max(std::min(p[a], q[a]) - reach, 0.0),
                     hi = std::min(std::max(p[a], q[a]) + reach, double(lim));
        const double slope = d[a] != 0.0 ? d[b] / d[a] : 0.0;  // |slope| <= 1 on the major axis
        if (!(hi > lo)) return;
        const double span = r * std::sqrt(1.0 + slope * slope) + 1e-3;
        const int limMinor = xMajor ? H : W;
        for (int m = static_cast<int>(std::floor(lo)); m < static_cast<int>(std::ceil(hi)); ++m) {
            const double centre = p[b] + (m + 0.5 - p[a]) * slope;  // the line at the column's centre
            // Pixel n is visited when its centre n + 0.5 may lie within span of `centre`.
            const int n0 = static_cast<int>(std::clamp(std::floor(centre - span - 0.5), -1.0, double(limMinor)));
            const int n1 = static_cast<int>(std::clamp(std::ceil(centre + span - 0.5), -1.0, double(limMinor)));
            for (int n = n0; n <= n1; ++n) xMajor ? plot(m, n) : plot(n, m);
        }
    };
    const auto& pts = line.points;
    if (line.pairs) {
        for (std::size_t i = 0; i + 1 < pts.size(); i += 2) {
            if ((i & 255) == 0 && isSet(cancel)) return;
            segment(toPx(pts[i]), toPx(pts[i + 1]));
        }
    } else {
        for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
            if ((i & 255) == 0 && isSet(cancel)) return;
            segment(toPx(pts[i]), toPx(pts[i + 1]));
        }
        if (line.closed && pts.size() > 2) segment(toPx(pts.back()), toPx(pts.front()));
    }
}

void blendLine(const Rgba8& colour, std::vector<std::uint8_t>& cov, std::vector<std::uint32_t>& touched,
               std::uint8_t* rgba) {
    const float ca = colour.a / 255.0f;
    for (std::uint32_t k : touched) {
        const float c = cov[k] / 255.0f * ca;
        cov[k] = 0;
        std::uint8_t* o = rgba + 4 * std::size_t(k);
        const float a = o[3] / 255.0f;
        const float oa = c + (1.0f - c) * a;
        if (oa <= 0.0f) continue;
        for (int ch = 0; ch < 3; ++ch) {
            const float src = (ch == 0 ? colour.r : ch == 1 ? colour.g : colour.b);
            const float v = (c * src + (1.0f - c) * a * o[ch]) / oa;
            o[ch] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f);
        }
        o[3] = static_cast<std::uint8_t>(oa * 255.0f + 0.5f);
    }
    touched.clear();
}

}  // namespace

Status rasterize(const FillRegion* regions, std::size_t regionCount, const FillLine* lines, std::size_t lineCount,
                 const PixelFrame& frame, const RasterOptions& options, SectionImage& out) {
    if (Status s = checkFrame(frame.rect, frame.width, frame.height); !s) return s;
    const int W = frame.width, H = frame.height;
    out.frame = frame;
    const ToPixel toPx(frame);
    const std::size_t pixels = std::size_t(W) * std::size_t(H);
    if (options.ids) {
        out.ids.assign(pixels, kNoRecord);
        std::vector<std::uint32_t> order(regionCount);
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return regions[a].depth < regions[b].depth; });
        thread_local ScanScratch scratch;  // kept per thread, as the colour buffers below
        for (std::uint32_t r : order) {
            fillRegionIds(regions[r], toPx, W, H, out.ids.data(), scratch, options.cancel);
            if (Status s = checkCancel(options.cancel); !s) return s;
        }
    } else {
        out.ids.clear();
    }
    if (options.colour) {
        // Kept per thread between images (as the line coverage below): its piece, order and
        // row buffers are reused, not allocated and faulted in again for every image.
        thread_local ColourRaster cr;
        cr.pieces.clear();
        cr.W = W;
        cr.H = H;
        for (std::size_t r = 0; r < regionCount; ++r) {
            const Float4 c = premultiplied(regions[r].colour);
            for (const auto& e : regions[r].edges) cr.addEdge(toPx(e[0]), toPx(e[1]), c);
        }
        out.rgba.resize(pixels * 4);
        cr.run(options.background, out.rgba.data(), options.cancel);
        if (Status s = checkCancel(options.cancel); !s) return s;
        if (options.traces && lineCount > 0) {
            // Line coverage per pixel, kept per thread between images: all zero between lines
            // (blendLine clears the pixels a line touched), so no image pays for a fresh,
            // zeroed, page-faulted megabyte.
            thread_local std::vector<std::uint8_t> cov;
            if (cov.size() < pixels) cov.assign(pixels, 0);
            thread_local std::vector<std::uint32_t> touched;
            for (std::uint32_t k : touched) cov[k] = 0;  // left by an image that threw mid-line
            touched.clear();
            const float w = std::clamp(options.traceWidthPx, 1.0f, 4.0f);
            for (std::size_t l = 0; l < lineCount; ++l) {
                if (Status s = checkCancel(options.cancel); !s) return s;
                drawLine(lines[l], toPx, w, W, H, cov, touched, options.cancel);
                blendLine(lines[l].colour, cov, touched, out.rgba.data());
            }
        }
    } else {
        out.rgba.clear();
    }
    return {};
}

void sectionFill(const SectionIndex& index, const Section& section, std::vector<FillRegion>& regions,
                 std::vector<FillLine>& lines) {
    regions.clear();
    lines.clear();
    for (const BodySection& b : section.bodies) {
        FillRegion r;
        const SectionPart& part = index.parts[b.part];
        r.record = b.record;
        r.colour = part.colour;
        r.depth = part.depth;
        auto addRing = [&](const Ring& ring) {
            for (std::size_t i = 0; i < ring.size(); ++i)
                r.edges.push_back({ring[i], ring[i + 1 == ring.size() ? 0 : i + 1]});
        };
        for (const SectionPolygon& p : b.polygons) {
            addRing(p.outer);
            for (const Ring& h : p.holes) addRing(h);
        }
        regions.push_back(std::move(r));
    }
    for (const SectionTrace& t : section.traces) {
        FillLine l;
        l.colour = index.parts[t.part].colour;
        l.points = t.points;
        l.closed = t.closed;
        lines.push_back(std::move(l));
    }
}

FrameRect fitFrame(const Section& section, int width, int height, double margin) {
    return fitRect(section.lo, section.hi, width, height, 1.0, margin);
}

Status rasterizeSection(const SectionIndex& index, const Section& section, const FrameRect& rect, int width, int height,
                        const RasterOptions& options, SectionImage& out) {
    std::vector<FillRegion> regions;
    std::vector<FillLine> lines;
    sectionFill(index, section, regions, lines);
    PixelFrame frame;
    frame.section = section.frame;
    frame.rect = rect;
    frame.width = width;
    frame.height = height;
    return rasterize(regions.data(), regions.size(), lines.data(), lines.size(), frame, options, out);
}

Result<SectionImage> rasterizeSection(const SectionIndex& index, const Section& section, const FrameRect& rect,
                                      int width, int height, const RasterOptions& options) {
    SectionImage img;
    if (Status s = rasterizeSection(index, section, rect, width, height, options, img); !s) return s.error();
    return img;
}

Result<SectionImage> renderTile(const SectionIndex& index, const Plane& plane, const FrameRect& rect, int width,
                                int height, const RasterOptions& options, TileTimings* timings) {
    auto checked = checkSectionPlane(index, plane);
    if (!checked) return checked.error();
    if (Status s = checkFrame(rect, width, height); !s) return s.error();
    PlaneCut cut;
    beginCut(index, checked.value(), cut);
    PlaneRect strip;
    strip.originLocal = cut.frame.originLocal;
    strip.u = cut.frame.u;
    strip.v = cut.frame.v;
    strip.u0 = -std::numeric_limits<double>::infinity();
    strip.u1 = rect.u1;
    strip.v0 = rect.v0;
    strip.v1 = rect.v1;
    CutStats cs;
    cutWithBvh(index, &strip, cut, 1, &cs);
    if (Status s = checkCancel(options.cancel); !s) return s.error();
    auto t2 = std::chrono::steady_clock::now();

    // Regions from raw segments: a body's own (interior on the left) plus its directly
    // nested bodies' reversed, so the nested body is a hole of its host.
    std::vector<FillRegion> regions(index.bodyCount);
    for (std::size_t b = 0; b < index.bodyCount; ++b) {
        regions[b].record = index.parts[b].record;
        regions[b].colour = index.parts[b].colour;
        regions[b].depth = index.parts[b].depth;
        for (const CutSegment& s : cut.parts[b]) regions[b].edges.push_back({s.a, s.b});
    }
    for (std::size_t b = 0; b < index.bodyCount; ++b) {
        const int parent = index.parts[b].parent;
        if (parent < 0 || static_cast<std::size_t>(parent) >= index.bodyCount) continue;
        for (const CutSegment& s : cut.parts[b]) regions[static_cast<std::size_t>(parent)].edges.push_back({s.b, s.a});
    }
    std::vector<FillLine> lines;
    for (std::size_t p = index.bodyCount; p < index.parts.size(); ++p) {
        if (cut.parts[p].empty()) continue;
        FillLine l;
        l.colour = index.parts[p].colour;
        l.pairs = true;
        for (const CutSegment& s : cut.parts[p]) {
            l.points.push_back(s.a);
            l.points.push_back(s.b);
        }
        lines.push_back(std::move(l));
    }
    PixelFrame frame;
    frame.section = cut.frame;
    frame.rect = rect;
    frame.width = width;
    frame.height = height;
    SectionImage img;
    if (Status s = rasterize(regions.data(), regions.size(), lines.data(), lines.size(), frame, options, img); !s)
        return s.error();
    if (timings) {
        timings->queryMs = cs.queryMs;
        timings->cutMs = cs.cutMs;
        timings->fillMs = msSince(t2);
        timings->trianglesTested = cs.trianglesTested;
    }
    return img;
}

}  // namespace geoslice
