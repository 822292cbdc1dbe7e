#include "section/leaf_tables.hpp"

#include <algorithm>
#include <string>
#include <thread>

#include "section/section_index.hpp"

namespace geoslice {
namespace {

// Appends the tables of the leaves among nodes [lo, hi) to `words` (offsets from its
// start) and records them in tableOf.
void buildRange(const Bvh& bvh, const std::vector<SectionPart>& parts, std::size_t lo, std::size_t hi,
                std::vector<std::uint32_t>& words, std::vector<std::uint32_t>& tableOf) {
    struct Run {
        std::uint32_t part, first, triangles, vertices;
    };
    std::vector<Run> runs;
    std::vector<std::uint32_t> vertices;  // welded, run by run
    std::vector<std::uint8_t> corners;
    for (std::size_t n = lo; n < hi; ++n) {
        const BvhNode& nd = bvh.nodes[n];
        if (nd.count == 0) continue;
        runs.clear();
        vertices.clear();
        corners.clear();
        std::size_t runVertices = 0;  // the current run's first entry in `vertices`
        std::uint32_t prevPart = 0, prevLocal = 0;
        for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
            const std::uint32_t id = bvh.triangles[i];
            const std::uint32_t p = bvh.meshOf(id);
            const std::uint32_t t = id - bvh.meshFirst[p];
            const SectionPart& sp = parts[p];
            const std::uint32_t* tri = sp.part->mesh.indices.data() + 3 * std::size_t(t);
            const std::uint32_t w[3] = {sp.weld(tri[0]), sp.weld(tri[1]), sp.weld(tri[2])};
            if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;  // degenerate: never cut
            if (runs.empty() || p != prevPart || t != prevLocal + 1) {
                runs.push_back(Run{p, t, 0, 0});
                runVertices = vertices.size();
            }
            prevPart = p;
            prevLocal = t;
            ++runs.back().triangles;
            for (std::uint32_t v : w) {
                const auto begin = vertices.begin() + static_cast<std::ptrdiff_t>(runVertices);
                const auto at = static_cast<std::size_t>(std::find(begin, vertices.end(), v) - vertices.begin());
                if (at == vertices.size()) {
                    vertices.push_back(v);
                    ++runs.back().vertices;
                }
                corners.push_back(static_cast<std::uint8_t>(at));
            }
        }
        tableOf[n] = static_cast<std::uint32_t>(words.size());
        const std::size_t triangles = corners.size() / 3;
        words.push_back(static_cast<std::uint32_t>(runs.size() | vertices.size() << 8 | triangles << 16));
        for (const Run& r : runs) {
            words.push_back(r.part);
            words.push_back(r.first);
            words.push_back(r.triangles | r.vertices << 8);
        }
        words.insert(words.end(), vertices.begin(), vertices.end());
        const std::size_t at = words.size();
        words.resize(at + (corners.size() + 3) / 4, 0);
        for (std::size_t c = 0; c < corners.size(); ++c)
            words[at + c / 4] |= std::uint32_t(corners[c]) << (8 * (c % 4));
    }
}

}  // namespace

Result<LeafTables> buildLeafTables(const Bvh& bvh, const std::vector<SectionPart>& parts, unsigned threads) {
    LeafTables t;
    t.tableOf.assign(bvh.nodes.size(), 0);
    if (bvh.nodes.empty()) return t;
    // About 20 words a leaf on the generator's models: reserve for that.
    const std::size_t mid = threads >= 2 ? bvh.nodes.size() / 2 : bvh.nodes.size();
    t.words.reserve(bvh.triangles.size() * 5);
    std::vector<std::uint32_t> second;
    std::thread worker;
    if (mid < bvh.nodes.size()) {
        second.reserve(bvh.triangles.size() * 5 / 2);
        worker = std::thread([&] { buildRange(bvh, parts, mid, bvh.nodes.size(), second, t.tableOf); });
    }
    buildRange(bvh, parts, 0, mid, t.words, t.tableOf);
    if (worker.joinable()) worker.join();
    if (t.words.size() + second.size() > 0xFFFFFFFFull)
        return Error{ErrorCode::OutOfRange, "the section cut's leaf tables would pass 2^32 words (" +
                                                std::to_string(bvh.triangles.size()) + " triangles)"};
    if (!second.empty()) {
        const auto shift = static_cast<std::uint32_t>(t.words.size());
        for (std::size_t n = mid; n < bvh.nodes.size(); ++n)
            if (bvh.nodes[n].count != 0) t.tableOf[n] += shift;
        t.words.insert(t.words.end(), second.begin(), second.end());
    }
    t.words.shrink_to_fit();
    return t;
}

}  // namespace geoslice
