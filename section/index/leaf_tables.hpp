// The plane cut's own table of each BVH leaf: what section/cut/plane_cut.cpp reads to cut a
// leaf, packed so that one leaf is one short run of memory reached in one step from the
// leaf's node.
//
// Without it the cut follows a chain of dependent loads per triangle: the leaf's triangle
// ids (Bvh::triangles) -> the id's part (a search of Bvh::meshFirst) -> the part's three
// vertex indices -> the three vertices, and it measures each corner's distance to the
// plane once per triangle. A table lists the leaf's triangles as runs of consecutive ids of
// one part, the distinct welded vertices of each run once, and each triangle's corners as
// one byte each into that list: the cut reads the table, loads each distinct vertex once
// (from the model: positions are not copied) and tests the triangles with bytes.
//
// Layout (32-bit words, at words[tableOf[node]] for a leaf node):
//   word 0            runs R | distinct vertices V << 8 | triangles T << 16
//   R x 3 words       part; the run's first triangle (index within the part);
//                     its triangle count | its vertex count << 8
//   V words           welded vertex index within the part (SectionPart::weld), run by run
//   ceil(3T / 4)      corner bytes, 3 per triangle: indices into the leaf's V vertices
// A welded vertex has the position of every vertex welded to it (the weld is by exact
// position), so the cut computes the same bits as from the triangle's own vertices.
// Triangles whose welded corners repeat (degenerate: no edge of their own, so never cut)
// are left out; so are those the BVH leaves out. With leaves of at most 64 triangles a
// leaf has at most 192 vertices: every count fits its byte.
//
// Memory (L4, 10M triangles, measured): with leaves of <= 64 (the default) 78 MB, 7.8 bytes
// a triangle, built in 149 ms on 2 threads (245 ms on one); with leaves of <= 8, 174 MiB
// (2.1M leaves of 4.8 triangles, 9.5 distinct vertices and 1.8 runs on average). At leaves
// of 8 the cut of a new L4 plane took 0.73-0.76x the time of the per-triangle path
// (bench/section.cpp, A/B in one run; README "Performance").
// Thread-safety: build once; read from any number of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "model/result.hpp"
#include "section/index/bvh.hpp"

namespace geoslice {

struct SectionPart;

// One leaf's table read through the layout above.
struct LeafTable {
    struct Run {
        std::uint32_t part, first, triangles, vertices;
    };
    explicit LeafTable(const std::uint32_t* words)
        : runs(words[0] & 0xFFu),
          vertexCount((words[0] >> 8) & 0xFFu),
          triangleCount((words[0] >> 16) & 0xFFu),
          runWords(words + 1),
          vertices(runWords + 3 * runs),
          cornerWords(vertices + vertexCount) {}

    std::uint32_t runs, vertexCount, triangleCount;
    const std::uint32_t* runWords;     // 3 words a run
    const std::uint32_t* vertices;     // welded vertex indices, run by run
    const std::uint32_t* cornerWords;  // corner bytes, 4 a word

    Run run(std::uint32_t r) const {
        const std::uint32_t* w = runWords + 3 * r;
        return {w[0], w[1], w[2] & 0xFFu, w[2] >> 8};
    }
    // Corner c of the leaf (triangle c / 3, in run order): an index into `vertices`.
    std::uint32_t corner(std::uint32_t c) const { return (cornerWords[c >> 2] >> (8 * (c & 3u))) & 0xFFu; }
    std::size_t words() const {
        return 1 + 3 * std::size_t(runs) + vertexCount + (3 * std::size_t(triangleCount) + 3) / 4;
    }
};

struct LeafTables {
    std::unique_ptr<std::uint32_t[]> words;  // every leaf's table (wordCount of them)
    std::size_t wordCount = 0;
    std::vector<std::uint32_t> tableOf;  // node index -> its table's first word (leaves only)

    const std::uint32_t* table(std::size_t node) const { return words.get() + tableOf[node]; }
    std::size_t memoryBytes() const { return wordCount * 4 + tableOf.capacity() * 4; }

    static constexpr std::size_t kMaxVertices = 192;  // 3 x the largest leaf (BvhOptions::maxLeafSize)
};

// Builds the tables of every leaf of `bvh` over `parts` (SectionIndex::parts, welds made),
// on `threads` threads (1 or 2; the output does not depend on it).
// Errors: OutOfRange when the tables would pass 2^32 words (offsets are 32-bit).
Result<LeafTables> buildLeafTables(const Bvh& bvh, const std::vector<SectionPart>& parts, unsigned threads = 2);

}  // namespace geoslice
