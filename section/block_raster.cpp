// Colouring a section's pixels by a block model (section/block_section.hpp
// colourPixelsByBlocks): the cell holding each pixel centre, found run by run along each row.
//
// The rule is per pixel: cell = BlockModel::cellAt(worldAt(i, j)), the function the pixel
// query calls. Asking it at every pixel costs a world point, a grid transform and three
// divisions per pixel, which was most of a coloured image's extra time (bench_blocks). When
// the caller says that a row's pixel centres lie on a line (worldStepX: profile views of a
// plane) and the cells are boxes, the cells along a row are found by walking that line: the
// grid coordinates are affine in i, so the pixels whose cell cannot differ from a span's first
// pixel's are known in closed form and filled as one span, and cellAt is asked only of
// pixels whose estimate lies within a margin of a cell face. The margin (kMarginRel x the
// largest coordinate involved) is far wider than the rounding of worldAt, toGrid and the
// estimate (a few ulps each), so a pixel filled without asking gets the answer cellAt would
// give: its real position lies between two pixels that the estimate puts inside the same
// cell by more than the margin, and a box is convex. Same output, bit for bit, as asking
// cellAt everywhere (tests/unit/block_raster_test.cpp compares both on planes through cell
// faces, pixel centres on faces, at Gauss-Kruger magnitudes). Rows are shared with the
// calling thread's partner thread (section/partner_thread.hpp) in bands.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include "section/block_section.hpp"
#include "section/partner_thread.hpp"

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
        : blocks_(blocks),
          classes_(classes),
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
    const BlockModel& blocks_;
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

}  // namespace

void colourPixelsByBlocks(const BlockModel& blocks, const PropertyClasses& classes,
                          const std::vector<RecordId>& clipRecords, const std::function<glm::dvec3(int, int)>& worldAt,
                          int width, int height, const std::uint32_t* ids, std::uint8_t* rgba, std::uint32_t* cells,
                          const glm::dvec3* worldStepX) {
    const std::size_t W = std::size_t(width);
    const bool walk = worldStepX && blocks.shape == CellShape::Box && std::isfinite(maxAbs(*worldStepX));
    // Rows in bands of kBandRows taken from a common counter by this thread and its partner
    // (section/partner_thread.hpp), which may never start: then this thread takes them all.
    constexpr int kBandRows = 16;
    std::atomic<int> nextBand{0};
    auto work = [&] {
        RowPainter painter(blocks, classes, rgba, cells);
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
                    if (walk) {
                        boxRun(blocks, worldAt, *worldStepX, j, start, i, rowBase, painter);
                        continue;
                    }
                    for (int x = start; x < i; ++x) {
                        const std::size_t p = rowBase + std::size_t(x);
                        painter.paint(p, p + 1, blocks.cellAt(worldAt(x, j), hint));
                    }
                }
            }
    };
    if (std::size_t(height) * W >= kTwoThreadMinPixels && height > kBandRows) {
        PartnerThread::Job partner = PartnerThread::forThisThread().run(work);
        work();
        partner.wait();
    } else {
        work();
    }
}

}  // namespace geoslice
