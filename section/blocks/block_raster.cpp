// Colouring a section's pixels by a block model (section/blocks/block_section.hpp
// colourPixelsByBlocks): the cell holding each pixel centre, found run by run along each row.
//
// The rule is per pixel: cell = BlockModel::cellAt(worldAt(i, j)), the function the pixel
// query calls. Asking it at every pixel costs a world point, a grid transform and three
// divisions per pixel (box cells), or six barycentric tests and at times a BVH descent
// (hexahedral cells), which was most of a coloured image's extra time (bench_blocks). When
// the caller says where a row's pixel centres lie on a line (RowLine: a plane's whole row, a
// polyline's columns on one leg), the cells along it are walked on that line instead:
//  - box cells: the grid coordinates are affine in i, so the pixels whose cell cannot differ
//    from a span's first pixel's are known in closed form and filled as one span;
//  - hexahedral cells: the barycentric coordinates in each of a cell's six tetrahedra are
//    affine in i, so the pixels that a tetrahedron holds with every coordinate above cellAt's
//    own "inside" threshold (1e-9: no other cell can then hold the point) are that cell's;
//    the next span's cell is guessed across the face the line leaves by, and checked.
// cellAt is asked only of pixels whose estimate lies within a margin of a cell face (box) or
// of that threshold (tetrahedra). The margin (kMarginRel x the largest coordinate involved,
// in metres, times the gradient of a barycentric coordinate) is far wider than the rounding
// of worldAt, toGrid, the coordinates and the estimate (a few ulps each), so a pixel filled
// without asking gets the answer cellAt would give: its real position lies between two
// pixels that the estimate puts inside the same box or tetrahedron by more than the margin,
// and both are convex. Same output, bit for bit, as asking cellAt everywhere
// (tests/unit/block_raster_test.cpp compares both on planes through cell faces, pixel centres
// on faces, lattice and bent SGrids, at Gauss-Kruger magnitudes). Rows are shared with the
// calling thread's partner thread (section/cut/partner_thread.hpp) in bands.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "model/model.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/partner_thread.hpp"

namespace geoslice {
namespace {

// The margin, relative to the largest coordinate magnitude of the row (2^-36: about 65,000
// double steps there; at a Gauss-Kruger easting of 3.5e7 m, 0.5 mm).
constexpr double kMarginRel = 0x1p-36;

// Below this many pixels the image is coloured on the calling thread alone (a hand-off to
// the partner costs tens of microseconds; a 256x256 tile colours in about that).
constexpr std::size_t kTwoThreadMinPixels = 1 << 16;

double maxAbs(const glm::dvec3& p) { return std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}); }

// The end of the run of `r` that starts at row[i] (the first x > i with row[x] != r, or n);
// four ids at a time, most runs being long.
int endOfRun(const std::uint32_t* row, int i, int n, std::uint32_t r) {
    const std::uint64_t rr = (std::uint64_t(r) << 32) | r;
    for (; i + 4 <= n; i += 4) {
        std::uint64_t a, b;
        std::memcpy(&a, row + i, 8);
        std::memcpy(&b, row + i + 2, 8);
        if (a != rr || b != rr) break;
    }
    while (i < n && row[i] == r) ++i;
    return i;
}

class RowPainter {
public:
    RowPainter(const BlockModel& blocks, const PropertyClasses& classes, std::uint8_t* rgba, std::uint32_t* cells)
        : classes_(classes),
          values_(blocks.properties[std::size_t(classes.property)].values),
          rgba_(rgba),
          cells_(cells) {}

    // Pixels [p0, p1) (linear indices) hold `cell` (kNoCell: none).
    void paint(std::size_t p0, std::size_t p1, std::size_t cell) {
        if (cells_) std::fill(cells_ + p0, cells_ + p1, cell == BlockModel::kNoCell ? 0u : std::uint32_t(cell + 1));
        if (!rgba_ || cell == BlockModel::kNoCell) return;
        if (cell != lastCell_) {
            lastCell_ = cell;
            const double v = values_[cell];
            hasValue_ = !std::isnan(v);
            if (hasValue_) {
                const Rgba8 c = classes_.colourOf(v);
                px_[0] = c.r;
                px_[1] = c.g;
                px_[2] = c.b;
                px_[3] = 255;
            }
        }
        if (!hasValue_) return;
        for (std::size_t p = p0; p < p1; ++p) std::memcpy(rgba_ + 4 * p, px_, 4);
    }

private:
    const PropertyClasses& classes_;
    const std::vector<double>& values_;
    std::uint8_t* rgba_;
    std::uint32_t* cells_;
    std::size_t lastCell_ = BlockModel::kNoCell;  // the cell whose colour px_ holds
    bool hasValue_ = false;
    std::uint8_t px_[4] = {0, 0, 0, 0};
};

// Box cells along pixels [i0, i1) of row j: per axis a, the grid coordinate g_a(i) is
// g0_a + (i - i0) B_a, and the cell index floor(g_a / size_a) changes only where it crosses
// a face. Each span starts at a pixel whose estimate lies inside its cell by more than the
// margin on every axis and ends before the first pixel that may not; the slab of the next
// span is found from the last one's (a step of one cell), so a span costs no division.
void boxRun(const BlockModel& blocks, const std::function<glm::dvec3(int, int)>& worldAt, const glm::dvec3& step, int j,
            int i0, int i1, std::size_t rowBase, RowPainter& painter) {
    const glm::dvec3 w0 = worldAt(i0, j);
    const glm::dvec3 g0 = blocks.toGrid(w0);
    const glm::dvec3 B{glm::dot(step, blocks.axis[0]), glm::dot(step, blocks.axis[1]), glm::dot(step, blocks.axis[2])};
    const glm::dvec3 s{blocks.size[0], blocks.size[1], blocks.size[2]};
    const glm::dvec3 extent{double(blocks.dims[0]) * s.x, double(blocks.dims[1]) * s.y, double(blocks.dims[2]) * s.z};
    const double M = std::max({maxAbs(w0), maxAbs(w0 + double(i1 - 1 - i0) * step), maxAbs(blocks.origin)}) +
                     maxAbs(extent) + maxAbs(g0) + double(i1 - i0) * maxAbs(B);
    const double margin = M * kMarginRel;
    glm::dvec3 invB;
    for (int a = 0; a < 3; ++a) invB[a] = B[a] != 0.0 ? 1.0 / B[a] : 0.0;
    double k[3] = {0.0, 0.0, 0.0}, lo[3], hi[3];
    bool slabs = false;  // whether k, lo, hi hold the last span's cell
    auto estimate = [&](int i, int a) { return g0[a] + double(i - i0) * B[a]; };
    // Whether pixel i's estimate lies inside the slabs [lo, hi) by more than the margin.
    auto inside = [&](int i) {
        for (int a = 0; a < 3; ++a) {
            const double g = estimate(i, a);
            if (!(g - lo[a] > margin && hi[a] - g > margin)) return false;
        }
        return true;
    };
    int i = i0;
    while (i < i1) {
        // The slabs of pixel i: a step from the last span's, else a division.
        for (int a = 0; a < 3; ++a) {
            const double g = estimate(i, a);
            if (slabs && g >= hi[a] && g < hi[a] + s[a]) {
                k[a] += 1.0;
            } else if (slabs && g < lo[a] && g >= lo[a] - s[a]) {
                k[a] -= 1.0;
            } else if (!slabs || !(g >= lo[a] && g < hi[a])) {
                k[a] = std::floor(g / s[a]);
            }
            lo[a] = k[a] * s[a];
            hi[a] = lo[a] + s[a];
        }
        slabs = true;
        if (!inside(i)) {
            const std::size_t p = rowBase + std::size_t(i);
            painter.paint(p, p + 1, blocks.cellAt(worldAt(i, j)));
            ++i;
            continue;
        }
        // Pixels i .. i + n - 1 stay inside every slab: g + q B within (lo + margin, hi - margin).
        double n = double(i1 - i);
        for (int a = 0; a < 3; ++a) {
            const double g = estimate(i, a);
            if (B[a] > 0.0) n = std::min(n, std::ceil((hi[a] - margin - g) * invB[a]));
            if (B[a] < 0.0) n = std::min(n, std::ceil((lo[a] + margin - g) * invB[a]));
        }
        int count = std::max(1, int(n));
        // The products round: step back to a pixel the test itself puts inside (the ends
        // decide, the estimate being affine in i).
        while (count > 1 && !inside(i + count - 1)) --count;
        bool inGrid = true;
        for (int a = 0; a < 3; ++a) inGrid = inGrid && k[a] >= 0.0 && k[a] < double(blocks.dims[std::size_t(a)]);
        const std::size_t cell =
            inGrid ? blocks.linear(std::size_t(k[0]), std::size_t(k[1]), std::size_t(k[2])) : BlockModel::kNoCell;
        painter.paint(rowBase + std::size_t(i), rowBase + std::size_t(i + count), cell);
        i += count;
    }
}

// A hexahedral cell's six tetrahedra as seen along the rows of one image: for each, its first
// corner, the gradients of its barycentric coordinates (world metres^-1), their change per
// pixel step and the threshold each must exceed (cellAt's "inside" 1e-9 plus the margin in
// that coordinate's units). Kept in a small per-thread table by cell and step, as the rows
// below cross the same cells.
struct TetLines {
    std::size_t cell = BlockModel::kNoCell;
    glm::dvec3 step{0.0};  // the line's step they were made for (a polyline has one a leg)
    bool flat[6];
    glm::dvec3 a[6];
    glm::dvec3 g[6][3];  // coordinates 1..3; coordinate 0 = 1 - their sum
    double dlam[6][4], invDlam[6][4], tau[6][4];
};

void makeTetLines(const BlockModel& blocks, std::size_t cell, const glm::dvec3& step, double margin, TetLines& out) {
    constexpr double kInside = BlockModel::kInsideHint;  // cellAt's threshold for keeping a hint
    out.cell = cell;
    out.step = step;
    const auto k = blocks.cellCorners(cell);
    for (std::size_t t = 0; t < 6; ++t) {
        const auto& tet = kCellTets[t];
        const glm::dvec3 a = k[std::size_t(tet[0])], e1 = k[std::size_t(tet[1])] - a, e2 = k[std::size_t(tet[2])] - a,
                         e3 = k[std::size_t(tet[3])] - a;
        const double v = glm::dot(e1, glm::cross(e2, e3));
        out.flat[t] = !(std::abs(v) > 0.0);
        if (out.flat[t]) continue;
        const double inv = 1.0 / v;
        out.a[t] = a;
        out.g[t][0] = glm::cross(e2, e3) * inv;
        out.g[t][1] = glm::cross(e3, e1) * inv;
        out.g[t][2] = glm::cross(e1, e2) * inv;
        const glm::dvec3 g0 = -(out.g[t][0] + out.g[t][1] + out.g[t][2]);
        // |g| <= its L1 norm: a wider margin, no square root.
        auto l1 = [](const glm::dvec3& x) { return std::abs(x.x) + std::abs(x.y) + std::abs(x.z); };
        out.dlam[t][0] = glm::dot(step, g0);
        out.tau[t][0] = kInside + margin * l1(g0);
        for (int c = 1; c < 4; ++c) {
            out.dlam[t][c] = glm::dot(step, out.g[t][c - 1]);
            out.tau[t][c] = kInside + margin * l1(out.g[t][c - 1]);
        }
        for (int c = 0; c < 4; ++c) out.invDlam[t][c] = out.dlam[t][c] != 0.0 ? 1.0 / out.dlam[t][c] : 0.0;
    }
}

// The barycentric coordinates of w in each tetrahedron of tl's cell; whether one of them holds
// w with every coordinate above its threshold (then cellAt gives that cell: see hexRun).
bool tetCoordinates(const TetLines& tl, const glm::dvec3& w, double (&lam)[6][4]) {
    bool inside = false;
    for (std::size_t t = 0; t < 6; ++t) {
        if (tl.flat[t]) continue;
        const glm::dvec3 r = w - tl.a[t];
        lam[t][1] = glm::dot(r, tl.g[t][0]);
        lam[t][2] = glm::dot(r, tl.g[t][1]);
        lam[t][3] = glm::dot(r, tl.g[t][2]);
        lam[t][0] = 1.0 - lam[t][1] - lam[t][2] - lam[t][3];
        inside = inside || (lam[t][0] > tl.tau[t][0] && lam[t][1] > tl.tau[t][1] && lam[t][2] > tl.tau[t][2] &&
                            lam[t][3] > tl.tau[t][3]);
    }
    return inside;
}

// Where pixel q steps along the row from a span's first pixel probably lies: in the
// tetrahedron that comes closest to holding it (largest smallest coordinate), beyond its
// face of the most negative coordinate; when that face lies on the cell's face (its three
// corners share a lattice bit), in the neighbour across it. Only a hint for
// BlockModel::cellAt, which checks it (a wrong one costs the locator's search).
std::size_t nextCellGuess(const BlockModel& blocks, const TetLines& tl, const double (&lam)[6][4], double q) {
    int bestTet = -1, exitVertex = 0;
    double best = -std::numeric_limits<double>::infinity();
    for (int t = 0; t < 6; ++t) {
        if (tl.flat[t]) continue;
        int low = 0;
        double lowest = std::numeric_limits<double>::infinity();
        for (int c = 0; c < 4; ++c) {
            const double l = lam[t][c] + q * tl.dlam[t][c];
            if (l < lowest) {
                lowest = l;
                low = c;
            }
        }
        if (lowest > best) {
            best = lowest;
            bestTet = t;
            exitVertex = low;
        }
    }
    if (bestTet < 0 || !(best < 0.0)) return tl.cell;
    int f[3], n = 0;
    for (int c = 0; c < 4; ++c)
        if (c != exitVertex) f[n++] = kCellTets[std::size_t(bestTet)][std::size_t(c)];
    const int common = ~(f[0] ^ f[1]) & ~(f[0] ^ f[2]) & 7;
    if (common == 0) return tl.cell;  // an inner face: another tetrahedron of the cell
    const int axis = common & 1 ? 0 : common & 2 ? 1 : 2;
    auto ijk = blocks.ijk(tl.cell);
    if (f[0] & (1 << axis)) {
        if (++ijk[std::size_t(axis)] >= blocks.dims[std::size_t(axis)]) return BlockModel::kNoCell;
    } else {
        if (ijk[std::size_t(axis)]-- == 0) return BlockModel::kNoCell;
    }
    return blocks.linear(ijk[0], ijk[1], ijk[2]);
}

// Hexahedral cells along pixels [i0, i1) of row j. Each span starts at a pixel whose cell
// cellAt gives (`hint`: the neighbour the last span ran towards, tried first); along the row,
// the barycentric coordinates of the pixel centres in each of that cell's six tetrahedra are
// affine in i, so the pixels that some tetrahedron holds with every coordinate above cellAt's
// own "inside" threshold (1e-9, where no other cell can hold the point: model/blocks/block_model.hpp)
// plus the margin are that cell's without asking, as far as they run on from the span's first
// pixel. `table` caches TetLines by cell (its size a power of two).
constexpr int kWalkSteps = 3;

void hexRun(const BlockModel& blocks, const std::function<glm::dvec3(int, int)>& worldAt, const glm::dvec3& step,
            double margin, int j, int i0, int i1, std::size_t rowBase, RowPainter& painter, std::size_t& hint,
            std::vector<TetLines>& table) {
    auto linesOf = [&](std::size_t cell) -> TetLines& {
        TetLines& tl = table[cell & (table.size() - 1)];
        if (tl.cell != cell || tl.step != step) makeTetLines(blocks, cell, step, margin, tl);
        return tl;
    };
    double lam[6][4];
    int i = i0;
    while (i < i1) {
        const glm::dvec3 w = worldAt(i, j);
        // The guess's own tetrahedra first: inside one of them by the threshold, the pixel is
        // that cell's (what cellAt would answer); else a step on to the neighbour across the
        // face the pixel lies beyond (a walk of at most kWalkSteps cells: crossings near a
        // cell's edge or corner), and where that ends nowhere, cellAt decides.
        std::size_t cell = BlockModel::kNoCell;
        for (int steps = 0; steps < kWalkSteps && hint != BlockModel::kNoCell; ++steps) {
            const TetLines& tl = linesOf(hint);
            if (tetCoordinates(tl, w, lam)) {
                cell = hint;
                break;
            }
            const std::size_t next = nextCellGuess(blocks, tl, lam, 0.0);
            if (next == hint) break;  // inside it, near a face: cellAt's tie rule decides
            hint = next;
        }
        if (cell == BlockModel::kNoCell) {
            cell = blocks.cellAt(w);
            if (cell != BlockModel::kNoCell) tetCoordinates(linesOf(cell), w, lam);
        }
        hint = cell;
        const std::size_t p = rowBase + std::size_t(i);
        painter.paint(p, p + 1, cell);
        ++i;
        if (cell == BlockModel::kNoCell || i >= i1) continue;
        const TetLines& tl = linesOf(cell);
        // Per tetrahedron: the pixels (span start) + q, q in [lo, hi], held with every
        // coordinate above its threshold (integers, checked at both ends; empty when lo > hi).
        int lo[6], hi[6];
        for (std::size_t t = 0; t < 6; ++t) {
            lo[t] = 1;
            hi[t] = 0;
            if (tl.flat[t]) continue;
            double qlo = 1.0, qhi = double(i1 - i);
            for (int c = 0; c < 4; ++c) {
                const double room = lam[t][c] - tl.tau[t][c], d = tl.dlam[t][c];  // room at q = 0
                if (d > 0.0)
                    qlo = std::max(qlo, std::ceil(-room * tl.invDlam[t][c]));
                else if (d < 0.0)
                    qhi = std::min(qhi, std::floor(-room * tl.invDlam[t][c]));
                else if (!(room > 0.0))
                    qhi = 0.0;
            }
            if (!(qlo <= qhi)) continue;
            // The products round: move each end inwards until the estimate itself holds there.
            auto holds = [&](double q) {
                for (int c = 0; c < 4; ++c)
                    if (!(lam[t][c] + q * tl.dlam[t][c] > tl.tau[t][c])) return false;
                return true;
            };
            while (qlo <= qhi && !holds(qlo)) qlo += 1.0;
            while (qhi >= qlo && !holds(qhi)) qhi -= 1.0;
            if (qlo <= qhi) {
                lo[t] = int(qlo);
                hi[t] = int(qhi);
            }
        }
        // The union of the tetrahedra's runs that continues from the span's start without a gap.
        int end = 0;  // pixels p + 1 .. p + end are the cell's
        for (bool grew = true; grew;) {
            grew = false;
            for (int t = 0; t < 6; ++t)
                if (lo[t] <= end + 1 && hi[t] > end) {
                    end = hi[t];
                    grew = true;
                }
        }
        if (end > 0) {
            painter.paint(p + 1, p + 1 + std::size_t(end), cell);
            i += end;
        }
        if (i < i1) hint = nextCellGuess(blocks, tl, lam, double(end + 1));
    }
}

}  // namespace

std::vector<RowLine> polylineRowLines(const SectionLine& line, const std::function<double(int)>& chainageAt, int width,
                                      double pixelChainage) {
    std::vector<RowLine> out;
    if (line.points.size() < 2) return out;
    for (int i = 0; i < width; ++i) {
        const std::size_t k = line.legAt(chainageAt(i));
        const glm::dvec2 d =
            (line.points[k + 1] - line.points[k]) / (line.chainage[k + 1] - line.chainage[k]) * pixelChainage;
        const glm::dvec3 step{d.x, d.y, 0.0};
        if (!out.empty() && out.back().end == i && out.back().step == step)
            ++out.back().end;
        else
            out.push_back({i, i + 1, step});
    }
    return out;
}

void colourPixelsByBlocks(const BlockModel& blocks, const PropertyClasses& classes,
                          const std::vector<RecordId>& clipRecords, const std::function<glm::dvec3(int, int)>& worldAt,
                          int width, int height, const std::uint32_t* ids, std::uint8_t* rgba, std::uint32_t* cells,
                          const std::vector<RowLine>& rowLines) {
    const std::size_t W = std::size_t(width);
    // The usable lines, clamped to the image and in column order.
    std::vector<RowLine> lines;
    for (RowLine l : rowLines) {
        l.begin = std::max(l.begin, 0);
        l.end = std::min(l.end, width);
        if (l.begin < l.end && std::isfinite(maxAbs(l.step))) lines.push_back(l);
    }
    std::sort(lines.begin(), lines.end(), [](const RowLine& a, const RowLine& b) { return a.begin < b.begin; });
    const bool hex = blocks.shape == CellShape::Hexahedron;
    // Rows in bands of kBandRows taken from a common counter by this thread and its partner
    // (section/cut/partner_thread.hpp), which may never start: then this thread takes them all.
    constexpr int kBandRows = 16;
    std::atomic<int> nextBand{0};
    // Hexahedral cells: one margin for the image, from the largest coordinate of its corners'
    // pixel centres and of the grid (the pixel centres are affine in i and j on each line).
    double hexMargin = 0.0;
    if (!lines.empty() && hex) {
        const Aabb box = blocks.bounds();
        double M = std::max(maxAbs(box.min), maxAbs(box.max));
        for (const RowLine& l : lines)
            for (int c = 0; c < 4; ++c)
                M = std::max(M, maxAbs(worldAt(c & 1 ? l.end - 1 : l.begin, c & 2 ? height - 1 : 0)));
        hexMargin = M * kMarginRel;
    }
    auto work = [&] {
        RowPainter painter(blocks, classes, rgba, cells);
        // TetLines of the cells met lately (hexahedral walk), per thread, emptied for each image.
        thread_local std::vector<TetLines> table;
        if (!lines.empty() && hex) {
            table.resize(512);
            for (TetLines& t : table) t.cell = BlockModel::kNoCell;
        }
        std::size_t hint = BlockModel::kNoCell;  // the last cell: neighbouring pixels share it
        RecordId lastRecord = kNoRecord;
        bool lastClips = false;
        auto clips = [&](RecordId r) {
            if (r != lastRecord) {
                lastRecord = r;
                lastClips = r != kNoRecord && std::binary_search(clipRecords.begin(), clipRecords.end(), r);
            }
            return lastClips;
        };
        // Pixels [a, b) of row j, all of clipping bodies: walked where a line covers them.
        auto colourRun = [&](int j, std::size_t rowBase, int a, int b) {
            std::size_t l = 0;
            while (a < b) {
                while (l < lines.size() && lines[l].end <= a) ++l;
                const int lineBegin = l < lines.size() ? lines[l].begin : b;
                if (a < lineBegin) {  // no line: the rule at every pixel
                    const int e = std::min(b, lineBegin);
                    for (int x = a; x < e; ++x) {
                        const std::size_t p = rowBase + std::size_t(x);
                        painter.paint(p, p + 1, blocks.cellAt(worldAt(x, j), hint));
                    }
                    a = e;
                    continue;
                }
                const int e = std::min(b, lines[l].end);
                if (hex)
                    hexRun(blocks, worldAt, lines[l].step, hexMargin, j, a, e, rowBase, painter, hint, table);
                else
                    boxRun(blocks, worldAt, lines[l].step, j, a, e, rowBase, painter);
                a = e;
            }
        };
        for (int band = nextBand++; band * kBandRows < height; band = nextBand++)
            for (int j = band * kBandRows; j < std::min(height, (band + 1) * kBandRows); ++j) {
                const std::size_t rowBase = std::size_t(j) * W;
                const std::uint32_t* row = ids + rowBase;
                int i = 0;
                while (i < width) {
                    const RecordId r = row[i];
                    const int start = i;
                    i = endOfRun(row, i, width, r);
                    if (!clips(r)) {
                        if (cells)
                            std::fill(cells + rowBase + std::size_t(start), cells + rowBase + std::size_t(i), 0u);
                        continue;
                    }
                    // A run of pixels of clipping bodies (one or more).
                    while (i < width && row[i] != r && clips(row[i])) i = endOfRun(row, i, width, row[i]);
                    colourRun(j, rowBase, start, i);
                }
            }
    };
    // Help only while a core is idle (section/cut/partner_thread.hpp): beside other requests
    // a partner would compete with them for the cores.
    if (std::size_t(height) * W >= kTwoThreadMinPixels && height > kBandRows && PartnerThread::coreIdle()) {
        PartnerThread::Job partner = PartnerThread::forThisThread().run(work);
        work();
        partner.wait();
    } else {
        work();
    }
}

}  // namespace geoslice
