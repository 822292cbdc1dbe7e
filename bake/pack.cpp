// The two chart packers of bake/, both over plain arrays of chart extents:
// - packCharts: shelf packing of chart rectangles (paper section 2.2: "shelf-packing ... with a
//   mandatory 2-texel interchart margin"); the classic next-fit decreasing-height shelf
//   algorithm (Coffman, Garey, Johnson, Tarjan 1980, "Performance bounds for level-oriented
//   two-dimensional packing algorithms"), at one uniform texel density found by bisection.
// - packIntoFreeSpace: the incremental re-bake's packer, first fit (tallest chart first) into
//   the free rectangles a shelf packing leaves, kept sorted by page, y, x; a placed chart splits
//   its free rectangle in two, guillotine style (the GUILLOTINE family of Jylanki 2010, "A
//   thousand ways to pack the bin"): the part to its right, as tall as the chart plus margin,
//   and the part above it, as wide as the free rectangle.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "bake/bake.hpp"

namespace geoslice::bake {
namespace {

// Packs at `density`; returns the number of pages used, or 0 when some chart cannot fit an
// empty page or more than maxPages pages would be needed. Fills placements when not null.
std::uint32_t shelfPack(const glm::dvec2* extents, const std::vector<std::uint32_t>& order, double density,
                        const PackOptions& o, std::uint32_t maxPages, std::vector<Placement>* placements) {
    const std::uint32_t border = o.margin / 2;  // room for seam padding at page edges
    const std::uint64_t limitX = o.width - border, limitY = o.height - border;
    std::uint32_t page = 0;
    std::uint64_t x = border, y = border, shelfH = 0;
    for (std::uint32_t i : order) {
        const std::uint64_t w = chartCells(extents[i].x, density), h = chartCells(extents[i].y, density);
        if (border + w > limitX || border + h > limitY) return 0;
        if (x + w > limitX) {  // next shelf
            x = border;
            y += shelfH + o.margin;
            shelfH = 0;
        }
        if (y + h > limitY) {  // next page
            if (++page >= maxPages) return 0;
            x = border;
            y = border;
            shelfH = 0;
        }
        if (placements)
            (*placements)[i] = {page, static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h)};
        x += w + o.margin;
        shelfH = std::max(shelfH, h);
    }
    return page + 1;
}

}  // namespace

std::uint32_t chartCells(double extent, double density) {
    return static_cast<std::uint32_t>(std::ceil(std::max(0.0, extent) * density + 1.0));
}

Result<Packing> packCharts(const glm::dvec2* extents, std::size_t count, const PackOptions& options) {
    if (options.width < 8 || options.height < 8 || options.width > 16384 || options.height > 16384)
        return makeError(ErrorCode::InvalidArgument, "texture size " + std::to_string(options.width) + "x" +
                                                         std::to_string(options.height) + " is outside 8..16384");
    if (options.margin > 64) return makeError(ErrorCode::InvalidArgument, "margin above 64 texels");
    if (!(options.minDensity > 0.0) || !std::isfinite(options.minDensity))
        return makeError(ErrorCode::InvalidArgument,
                         "minimum texel density must be a positive number of texels per metre");
    if (options.maxPages == 0) return makeError(ErrorCode::InvalidArgument, "maximum page count must be at least 1");
    Packing out;
    out.placements.resize(count);
    if (count == 0) {
        out.pages = 1;
        out.density = options.minDensity;
        return out;
    }
    double area = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        if (!std::isfinite(extents[i].x) || !std::isfinite(extents[i].y) || extents[i].x < 0 || extents[i].y < 0)
            return makeError(ErrorCode::InvalidArgument,
                             "chart " + std::to_string(i) + " has a non-finite or negative extent");
        area += extents[i].x * extents[i].y;
    }
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return extents[a].y != extents[b].y ? extents[a].y > extents[b].y : a < b;
    });
    // Largest density that fits one page: bisection between a density that fits (or 0) and
    // the one at which the charts' area alone fills the page.
    const double pageTexels = double(options.width) * double(options.height);
    double hi = area > 0.0 ? std::sqrt(pageTexels / area) : 1e6;
    double lo = 0.0;
    if (shelfPack(extents, order, hi, options, 1, nullptr) == 1) lo = hi;
    for (int it = 0; it < 48 && lo < hi * (1.0 - 1e-4); ++it) {
        const double mid = lo > 0.0 ? std::sqrt(lo * hi) : hi * 0.5;
        if (mid <= 1e-9 * hi) break;
        if (shelfPack(extents, order, mid, options, 1, nullptr) == 1)
            lo = mid;
        else
            hi = mid;
        if (lo == 0.0 && hi < options.minDensity * 1e-3) break;
    }
    if (lo >= options.minDensity) {
        out.density = lo;
        out.pages = shelfPack(extents, order, lo, options, 1, &out.placements);
        GS_ASSERT(out.pages == 1, "a density found to fit one page must pack into one page");
        return out;
    }
    out.density = options.minDensity;
    out.pages = shelfPack(extents, order, out.density, options, options.maxPages, &out.placements);
    if (out.pages == 0) {
        // Say what would be needed.
        std::uint32_t need = 0;
        for (std::uint32_t p = options.maxPages + 1; p <= 65536 && !need; p *= 2)
            need = shelfPack(extents, order, out.density, options, p, nullptr);
        std::string what = need ? "needs " + std::to_string(need) + " pages" : "has a chart larger than a page";
        char density[32];
        std::snprintf(density, sizeof density, "%g", options.minDensity);
        return makeError(ErrorCode::OutOfRange,
                         "the model does not fit the texture budget: at the minimum density of " +
                             std::string(density) + " texels/m it " + what + " of " + std::to_string(options.width) +
                             "x" + std::to_string(options.height) + " texels, the budget is " +
                             std::to_string(options.maxPages) +
                             " pages (raise the texture size or the page budget, or lower the minimum density)");
    }
    return out;
}

namespace {

// Free space (x1, y1 exclusive; a chart of w x h cells needs (w + margin) x (h + margin)).
struct Free {
    std::uint32_t page, x0, y0, x1, y1;
};

bool freeBefore(const Free& a, const Free& b) {
    return a.page != b.page ? a.page < b.page : (a.y0 != b.y0 ? a.y0 < b.y0 : a.x0 < b.x0);
}

// The charts on the pages, each as its rectangle plus its trailing margin ([x, x + w + margin)
// x [y, y + h + margin)): two charts keep `margin` texels apart exactly when these are
// disjoint. A uniform grid of kCell texels finds the ones near a candidate.
class Occupancy {
public:
    explicit Occupancy(std::uint32_t margin) : margin_(margin) {}
    void add(const Placement& p) {
        const auto id = static_cast<std::uint32_t>(rects_.size());
        rects_.push_back(p);
        forCells(p.page, p.x, p.y, p.w, p.h, [&](std::uint64_t key) {
            cells_[key].push_back(id);
            return true;
        });
    }
    bool isFree(std::uint32_t page, std::uint32_t x, std::uint32_t y, std::uint32_t w, std::uint32_t h) const {
        return forCells(page, x, y, w, h, [&](std::uint64_t key) {
            const auto it = cells_.find(key);
            if (it == cells_.end()) return true;
            for (std::uint32_t id : it->second) {
                const Placement& r = rects_[id];
                if (x < r.x + r.w + margin_ && r.x < x + w + margin_ && y < r.y + r.h + margin_ &&
                    r.y < y + h + margin_)
                    return false;
            }
            return true;
        });
    }

private:
    static constexpr std::uint32_t kCell = 128;
    // Calls fn(cell key) for the cells the padded rectangle touches while fn returns true.
    template <class Fn>
    bool forCells(std::uint32_t page, std::uint32_t x, std::uint32_t y, std::uint32_t w, std::uint32_t h,
                  Fn&& fn) const {
        const std::uint64_t x1 = (std::uint64_t(x) + w + margin_ - 1) / kCell,
                            y1 = (std::uint64_t(y) + h + margin_ - 1) / kCell;
        for (std::uint64_t cy = y / kCell; cy <= y1; ++cy)
            for (std::uint64_t cx = x / kCell; cx <= x1; ++cx)
                if (!fn(std::uint64_t(page) << 32 | cy << 16 | cx)) return false;
        return true;
    }
    std::uint32_t margin_;
    std::vector<Placement> rects_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

Result<Packing> packIntoFreeSpace(const Placement* placed, const std::uint8_t* replaced, std::size_t placedCount,
                                  std::uint32_t pages, const glm::dvec2* extents, std::size_t count, double density,
                                  const PackOptions& po) {
    const std::uint32_t m = po.margin, border = po.margin / 2;
    struct Shelf {
        std::uint32_t page, y, height = 0, end = 0;
    };
    std::vector<Shelf> shelves;
    auto shelfOf = [&](std::uint32_t page, std::uint32_t y) -> Shelf& {
        for (auto& s : shelves)
            if (s.page == page && s.y == y) return s;
        shelves.push_back({page, y});
        return shelves.back();
    };
    for (std::size_t c = 0; c < placedCount; ++c) {
        const Placement& r = placed[c];
        Shelf& s = shelfOf(r.page, r.y);
        s.height = std::max(s.height, r.h);
        s.end = std::max(s.end, r.x + r.w);
    }
    std::vector<Free> free;
    for (std::size_t c = 0; c < placedCount; ++c) {
        const Placement& r = placed[c];
        const Shelf& s = shelfOf(r.page, r.y);
        const std::uint32_t x1 = r.x + r.w + m, top = r.y + s.height + m;
        if (replaced[c])
            free.push_back({r.page, r.x, r.y, x1, top});
        else if (r.y + r.h + m < top)
            free.push_back({r.page, r.x, r.y + r.h + m, x1, top});
    }
    // The free rectangles above assume a shelf layout, which an earlier re-bake breaks (its
    // charts sit in the room above shorter charts and at shelf ends): a place is taken only
    // where it keeps the margin from every chart that stays and every chart placed here.
    Occupancy occupied(m);
    for (std::size_t c = 0; c < placedCount; ++c)
        if (!replaced[c]) occupied.add(placed[c]);
    std::vector<std::uint32_t> pageTop(pages, border);
    for (const auto& s : shelves) {
        if (s.end + m < po.width - border + m)
            free.push_back({s.page, s.end + m, s.y, po.width - border + m, s.y + s.height + m});
        pageTop[s.page] = std::max(pageTop[s.page], s.y + s.height + m);
    }
    for (std::uint32_t pg = 0; pg < pages; ++pg)
        if (pageTop[pg] < po.height - border)
            free.push_back({pg, border, pageTop[pg], po.width - border + m, po.height - border + m});
    std::sort(free.begin(), free.end(), freeBefore);

    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return extents[a].y != extents[b].y ? extents[a].y > extents[b].y : a < b;
    });
    Packing out;
    out.density = density;
    out.placements.resize(count);
    for (std::size_t i : order) {
        const std::uint32_t cw = chartCells(extents[i].x, density);
        const std::uint32_t ch = chartCells(extents[i].y, density);
        auto it = std::find_if(free.begin(), free.end(), [&](const Free& f) {
            return f.x1 - f.x0 >= cw + m && f.y1 - f.y0 >= ch + m && occupied.isFree(f.page, f.x0, f.y0, cw, ch);
        });
        if (it == free.end()) {
            // No room: open a new page, within the page budget.
            if (pages >= po.maxPages || border + cw > po.width - border || border + ch > po.height - border)
                return makeError(ErrorCode::OutOfRange, "its new charts do not fit the free texture space within " +
                                                            std::to_string(po.maxPages) +
                                                            " pages; bake the model in full again");
            free.push_back({pages++, border, border, po.width - border + m, po.height - border + m});
            it = free.end() - 1;
        }
        const Free f = *it;
        out.placements[i] = {f.page, f.x0, f.y0, cw, ch};
        occupied.add(out.placements[i]);
        free.erase(it);
        const Free right{f.page, f.x0 + cw + m, f.y0, f.x1, f.y0 + ch + m},
            top{f.page, f.x0, f.y0 + ch + m, f.x1, f.y1};
        for (const Free& r : {right, top})
            if (r.x1 > r.x0 && r.y1 > r.y0) free.insert(std::upper_bound(free.begin(), free.end(), r, freeBefore), r);
    }
    out.pages = pages;
    return out;
}

}  // namespace geoslice::bake
