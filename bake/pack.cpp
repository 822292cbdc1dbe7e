// Shelf packing of chart rectangles (paper section 2.2: "shelf-packing ... with a mandatory
// 2-texel interchart margin"); the classic next-fit decreasing-height shelf algorithm (Coffman,
// Garey, Johnson, Tarjan 1980, "Performance bounds for level-oriented two-dimensional packing
// algorithms"), at one uniform texel density found by bisection.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

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

}  // namespace geoslice::bake
