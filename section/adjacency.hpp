// Triangle adjacency of closed bodies, for the section engine's edge walk
// (section/contours.hpp): from a triangle the plane crosses, the contour is followed across
// the shared edge it leaves by, so each crossing point is computed once and the rings come
// out in order, with no table to join segments (a walk over the twins of a half-edge
// mesh, stored as 3 neighbours per triangle).
//
// Layout: 3 uint32 per triangle of the bodies, global triangle ids [0, bvh.meshFirst[bodyCount])
// of section/section_index.hpp; entry 3 t + k describes edge k of t (vertex k -> k + 1):
// 4 t' + k', t' the triangle of the same part whose edge k' runs the other way (vertex
// k + 1 -> k), t' a part-local id. Parts that cannot be walked (not closed, an edge not
// shared by exactly two opposite triangles, a degenerate or non-finite triangle, 2^30
// triangles or more) hold kNoNeighbour everywhere and are chained from segments as before.
// For a walkable part, the walk follows exactly the joins the segment chaining would make
// (a closed, consistently oriented 2-manifold pairs each exit edge with one entry edge), so
// its rings are the same point for point.
//
// Memory: 12 bytes a body triangle (120 MB at L4). Thread-safety: build once, read anywhere.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "model/result.hpp"

namespace geoslice {

struct SectionIndex;

constexpr std::uint32_t kNoNeighbour = 0xFFFFFFFFu;

struct TriangleAdjacency {
    std::vector<std::uint32_t> across;   // 3 per body triangle (see above); empty: nothing walkable
    std::vector<std::uint8_t> walkable;  // per body: 1 when its entries are filled
    bool walkablePart(std::size_t part) const { return part < walkable.size() && walkable[part] != 0; }
    std::size_t memoryBytes() const { return across.capacity() * 4 + walkable.capacity(); }
};

// Builds the table for `index`'s bodies (its parts, meshes and BVH mesh ranges must be set);
// `threads` bodies at once (0 = hardware concurrency).
TriangleAdjacency buildTriangleAdjacency(const SectionIndex& index, unsigned threads = 0);

// The table as bytes, for baked packages: a 32-byte header ("GSADJ001", uint32 body count,
// uint32 0, uint64 entry count, uint64 0), the walkable flags (one byte a body, zero-padded
// to a multiple of 4), then the entries (uint32); little-endian. Deterministic.
std::vector<std::uint8_t> saveTriangleAdjacency(const TriangleAdjacency& adjacency);

// Reads saveTriangleAdjacency's bytes for `index`: the header and sizes against the index's
// bodies, and that only bodies that can be walked (closed, unwelded, < 2^30 triangles) are
// marked so. The entries are taken as stored (a package's checksums vouch for them): the
// walk checks each step itself (the neighbour is in range and holds the edge it left by,
// the other way round) and falls back to chaining segments when one does not, so no bytes
// can make it read out of bounds, loop or give other rings.
// Errors: ParseError naming `source` and the defect.
Result<TriangleAdjacency> loadTriangleAdjacency(std::span<const std::uint8_t> bytes, const SectionIndex& index,
                                                const std::string& source);

}  // namespace geoslice
