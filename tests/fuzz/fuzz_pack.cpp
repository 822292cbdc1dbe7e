// libFuzzer target for bake/'s two chart packers (bake/pack.cpp): random charts packed by
// packCharts, then a random subset of them replaced twice in a row by new charts through
// packIntoFreeSpace (as repeated incremental re-bakes do), must never overlap: every
// rectangle lies on a page within the page border (margin / 2) and keeps `margin` texels from
// every other rectangle on its page; every page index is below the page count, the count
// within the budget. Errors are fine (a chart larger than a page, over budget), crashes and
// overlaps are not.
//
// Input: byte 0 = page size (64..512) and margin (2..9), byte 1 = page budget (1..8) and
// minimum density, byte 2 = chart count (1..64), then 2 bytes per chart extent (metres, 0..255
// each, 0 included), then per re-bake round one byte of replaced-flags seed and the new
// charts' count and extents in the same form; bytes reused cyclically.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bake/bake.hpp"

namespace {

using namespace geoslice::bake;

struct Bytes {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t at = 0;
    std::uint8_t next() { return size ? data[at++ % size] : 0; }
};

std::vector<glm::dvec2> extents(Bytes& in) {
    std::vector<glm::dvec2> out(1 + in.next() % 64);
    for (auto& e : out) {
        e.x = double(in.next());
        e.y = double(in.next());
    }
    return out;
}

// Traps when two rectangles of one page are closer than `margin` or one leaves its page.
void checkLayout(const std::vector<Placement>& all, std::uint32_t pages, const PackOptions& o) {
    const std::uint32_t border = o.margin / 2;
    if (pages > o.maxPages) __builtin_trap();
    for (std::size_t i = 0; i < all.size(); ++i) {
        const Placement& a = all[i];
        if (a.page >= pages || a.w == 0 || a.h == 0) __builtin_trap();
        if (a.x < border || a.y < border || a.x + a.w > o.width - border || a.y + a.h > o.height - border)
            __builtin_trap();
        for (std::size_t j = i + 1; j < all.size(); ++j) {
            const Placement& b = all[j];
            if (a.page != b.page) continue;
            const bool apart = a.x + a.w + o.margin <= b.x || b.x + b.w + o.margin <= a.x ||
                               a.y + a.h + o.margin <= b.y || b.y + b.h + o.margin <= a.y;
            if (!apart) __builtin_trap();
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    Bytes in{data, size};
    PackOptions o;
    const std::uint8_t b0 = in.next(), b1 = in.next();
    o.width = o.height = 64u << (b0 % 4);
    o.margin = 2 + (b0 / 4) % 8;
    o.maxPages = 1 + b1 % 8;
    o.minDensity = 0.05 * (1 + b1 / 8);
    const std::vector<glm::dvec2> first = extents(in);
    auto packing = packCharts(first.data(), first.size(), o);
    if (!packing) return 0;
    if (packing->placements.size() != first.size() || !(packing->density >= o.minDensity)) __builtin_trap();
    std::vector<Placement> placed = packing->placements;
    checkLayout(placed, packing->pages, o);
    std::uint32_t pages = packing->pages;
    for (int round = 0; round < 2; ++round) {
        std::vector<std::uint8_t> replaced(placed.size());
        const std::uint8_t seed = in.next();
        for (std::size_t i = 0; i < placed.size(); ++i) replaced[i] = ((seed >> (i % 8)) & 1) != 0;
        const std::vector<glm::dvec2> next = extents(in);
        auto more = packIntoFreeSpace(placed.data(), replaced.data(), placed.size(), pages, next.data(), next.size(),
                                      packing->density, o);
        if (!more) return 0;
        if (more->pages < pages || more->placements.size() != next.size()) __builtin_trap();
        std::vector<Placement> kept;
        for (std::size_t i = 0; i < placed.size(); ++i)
            if (!replaced[i]) kept.push_back(placed[i]);
        kept.insert(kept.end(), more->placements.begin(), more->placements.end());
        placed = std::move(kept);
        pages = more->pages;
        checkLayout(placed, pages, o);
    }
    return 0;
}
