#include "section/index/leaf_tables.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <thread>

#include "section/index/section_index.hpp"

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
    BvhMeshCursor partOf{&bvh};
    for (std::size_t n = lo; n < hi; ++n) {
        const BvhNode& nd = bvh.nodes[n];
        // Node 1 is padding (section/index/bvh.hpp): never read, and not checked in a loaded tree.
        if (nd.count == 0 || n == 1) continue;
        runs.clear();
        vertices.clear();
        corners.clear();
        std::size_t runVertices = 0;  // the current run's first entry in `vertices`
        std::uint32_t prevLocal = 0;
        for (std::uint32_t i = nd.first; i < nd.first + nd.count; ++i) {
            const std::uint32_t id = bvh.triangles[i];
            const std::uint32_t part = partOf(id), t = id - partOf.lo;
            const SectionPart& sp = parts[part];
            const std::uint32_t* tri = sp.part->mesh.indices.data() + 3 * std::size_t(t);
            const std::uint32_t w[3] = {sp.weld(tri[0]), sp.weld(tri[1]), sp.weld(tri[2])};
            if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;  // degenerate: never cut
            if (runs.empty() || part != runs.back().part || t != prevLocal + 1) {
                runs.push_back(Run{part, t, 0, 0});
                runVertices = vertices.size();
            }
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
        for (std::size_t c = 0; c < corners.size(); c += 4) {
            std::uint32_t packed = 0;
            for (std::size_t k = c; k < std::min(c + 4, corners.size()); ++k)
                packed |= std::uint32_t(corners[k]) << (8 * (k - c));
            words.push_back(packed);
        }
    }
}

}  // namespace

Result<LeafTables> buildLeafTables(const Bvh& bvh, const std::vector<SectionPart>& parts, unsigned threads) {
    LeafTables t;
    const std::size_t nodes = bvh.nodes.size();
    t.tableOf.assign(nodes, 0);
    // Two threads take the nodes before and after the one where half the triangles are
    // behind (the leaves are not spread evenly over the node array).
    std::size_t mid = nodes;
    if (threads >= 2) {
        std::size_t acc = 0;
        for (std::size_t n = 0; n < nodes; ++n)
            if (n != 1 && (acc += bvh.nodes[n].count) * 2 >= bvh.triangles.size()) {
                mid = n + 1;
                break;
            }
    }
    // About 4.1 words a triangle on the generator's models: reserved so that no table moves
    // while it is built (reserved pages never written cost no memory).
    auto reserveFor = [&](std::size_t triangles) { return triangles * 5 + 1024; };
    std::vector<std::uint32_t> first, second;
    first.reserve(reserveFor(mid < nodes ? bvh.triangles.size() / 2 : bvh.triangles.size()));
    std::thread worker;
    if (mid < nodes)
        worker = std::thread([&] {
            second.reserve(reserveFor(bvh.triangles.size() / 2));
            buildRange(bvh, parts, mid, nodes, second, t.tableOf);
        });
    buildRange(bvh, parts, 0, mid, first, t.tableOf);
    if (worker.joinable()) worker.join();
    t.wordCount = first.size() + second.size();
    if (t.wordCount > 0xFFFFFFFFull)
        return Error{ErrorCode::OutOfRange, "the section cut's leaf tables would pass 2^32 words (" +
                                                std::to_string(bvh.triangles.size()) + " triangles)"};
    // One block of exactly the tables' size, each half copied in by the thread that built it.
    t.words.reset(new std::uint32_t[std::max<std::size_t>(t.wordCount, 1)]);
    const auto shift = static_cast<std::uint32_t>(first.size());
    if (!second.empty())
        worker = std::thread([&] {
            std::memcpy(t.words.get() + shift, second.data(), second.size() * 4);
            for (std::size_t n = mid; n < nodes; ++n)
                if (bvh.nodes[n].count != 0 && n != 1) t.tableOf[n] += shift;
        });
    if (!first.empty()) std::memcpy(t.words.get(), first.data(), first.size() * 4);
    if (worker.joinable()) worker.join();
    return t;
}

}  // namespace geoslice
