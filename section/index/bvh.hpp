// An AABB tree over the triangles of several meshes, for plane and plane+rectangle
// queries (the section engine's only acceleration structure; rays go to Embree).
//
// Build: object-median split on the longest axis of the centroid bounds (bounding volume
// hierarchies after Kay & Kajiya, "Ray tracing complex scenes", SIGGRAPH 1986; the split is
// PBRT's "equal counts" method, Pharr, Jakob & Humphreys, Physically Based Rendering,
// 3rd ed., section 4.3.1). Centroids are
// quantised to 16 bits per axis over the model bounds and ties break by triangle id, so
// the tree is deterministic (same input, same tree, any thread count). Because a median
// split's shape depends only on triangle counts, every node's index is known before its
// subtree is built and the two top subtrees are built in parallel.
//
// Frames: node bounds are float32 in the local frame (world - origin), rounded outward
// from the double vertices, so a node's box always contains its triangles exactly.
// Queries take the plane in the local frame (double) and test each candidate triangle
// with the exact sign rule of view/plane.hpp.
//
// Leaves hold up to 64 triangles by default: the cut reads a leaf through its table
// (section/index/leaf_tables.hpp), where a triangle costs three byte tests, so a shallower tree
// with fewer nodes to visit wins. L4, cold planes (bench_section, load 1.5-1.7): leaves of
// 8 / 16 / 32 / 64 gave traversal 0.57 / 0.41 / 0.31 / 0.22 ms and cut + contours
// 1.99 / 1.81 / 1.76-1.81 / 1.68-1.72 ms, the cut itself about equal.
//
// Memory (L4, 10M triangles, leaves of <= 64, measured): 524k nodes x 32 B = 17 MB plus
// 40 MB of triangle ids (with leaves of <= 8: 4.19M nodes, 134 MB).
// Thread-safety: build once; queries are const and may run on any number of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "model/result.hpp"
#include "view/plane.hpp"

namespace geoslice {

// One mesh as plain arrays (world coordinates, 3 indices per triangle). The arrays must
// outlive the Bvh; queries read them.
struct BvhMesh {
    const glm::dvec3* positions = nullptr;
    std::size_t vertexCount = 0;
    const std::uint32_t* indices = nullptr;
    std::size_t triangleCount = 0;
};

struct BvhNode {
    float lo[3];          // local frame, metres
    std::uint32_t first;  // internal: index of the left child (right = first + 1); leaf: into Bvh::triangles
    float hi[3];
    std::uint32_t count;  // 0: internal node; else the leaf's triangle count
};
static_assert(sizeof(BvhNode) == 32);

// Allocates 64-byte aligned storage: two sibling nodes share one cache line.
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64))); }
    void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(64)); }
    template <class U>
    bool operator==(const CacheLineAllocator<U>&) const {
        return true;
    }
};

struct Bvh {
    // nodes[0] is the root (absent when empty), nodes[1] unused padding; every pair of
    // siblings starts at an even index, so it fills one 64-byte cache line.
    std::vector<BvhNode, CacheLineAllocator<BvhNode>> nodes;
    std::vector<std::uint32_t> triangles;  // global triangle ids in leaf order, ascending within a leaf
    std::vector<std::uint32_t> meshFirst;  // mesh m owns global ids [meshFirst[m], meshFirst[m + 1])
    glm::dvec3 origin{0.0};                // world point of the local frame

    std::size_t meshCount() const { return meshFirst.empty() ? 0 : meshFirst.size() - 1; }
    // Mesh of a global triangle id (binary search over meshFirst).
    std::uint32_t meshOf(std::uint32_t globalTriangle) const;
    std::size_t memoryBytes() const {
        return nodes.capacity() * sizeof(BvhNode) + triangles.capacity() * 4 + meshFirst.capacity() * 4;
    }
};

// Global triangle id -> mesh, remembering the last two meshes' id ranges: ids met in
// ascending runs per mesh (a leaf lists its ids in ascending order, and a leaf on the
// boundary of two bodies holds both bodies' copies of the shared faces) cost a binary search
// of Bvh::meshFirst only at a new pair of meshes. After a call, [lo, hi) is the returned
// mesh's id range.
struct BvhMeshCursor {
    const Bvh* bvh = nullptr;
    std::uint32_t mesh = 0, lo = 0, hi = 0;     // empty ranges until the first lookups
    std::uint32_t mesh2 = 0, lo2 = 0, hi2 = 0;  // the mesh before
    std::uint32_t operator()(std::uint32_t id) {
        if (id - lo < hi - lo) return mesh;  // unsigned: lo <= id < hi
        std::swap(mesh, mesh2);
        std::swap(lo, lo2);
        std::swap(hi, hi2);
        if (id - lo < hi - lo) return mesh;
        mesh = bvh->meshOf(id);
        lo = bvh->meshFirst[mesh];
        hi = bvh->meshFirst[mesh + 1];
        return mesh;
    }
};

struct BvhOptions {
    unsigned maxLeafSize = 64;  // 1..64
    unsigned threads = 0;       // 0 = hardware concurrency (at most 2 subtrees run at once per level)
};

// Triangles with a non-finite vertex are left out (they cannot cross a plane).
// Errors: more than 2^32 - 2 triangles in all; maxLeafSize outside 1..64.
Result<Bvh> buildBvh(const BvhMesh* meshes, std::size_t meshCount, const glm::dvec3& origin,
                     const BvhOptions& options = {});

// The tree as flat arrays, for baked packages (bake/package.hpp stores it as section.bvh, so
// a server loads it instead of building it): a 64-byte header ("GSBVH001", node size 32,
// node / triangle-id / mesh counts, origin as 3 doubles), then the nodes (32 bytes each, as in
// memory), the triangle ids (uint32) and meshFirst (uint32, meshCount + 1); little-endian,
// every array 4-byte aligned. Deterministic: the same tree gives the same bytes.
std::vector<std::uint8_t> saveBvh(const Bvh& bvh);

// Reads saveBvh's bytes for `meshes` (the meshes the tree was built over, in the same order)
// and `origin`. Checked before use, so that no bytes can make a query read out of bounds or
// loop: the header, sizes, the origin, meshFirst against the meshes' triangle counts, every
// triangle id, every leaf range, and every internal node's children (an even pair after the
// node, each pair the child of one node only: a tree). Box values are taken as stored (a
// package's checksums vouch for them). Errors: ParseError naming `source` and the defect.
Result<Bvh> loadBvh(std::span<const std::uint8_t> bytes, const BvhMesh* meshes, std::size_t meshCount,
                    const glm::dvec3& origin, const std::string& source);

// A rectangle in a section plane, local frame: points originLocal + s*u + t*v with
// s in [u0, u1], t in [v0, v1] (metres); u, v unit and orthogonal to the plane normal.
struct PlaneRect {
    glm::dvec3 originLocal{0.0};
    glm::dvec3 u{1.0, 0.0, 0.0}, v{0.0, 1.0, 0.0};
    double u0 = 0.0, u1 = 0.0, v0 = 0.0, v1 = 0.0;  // u0 may be -infinity (a strip open to the left)
};

struct BvhQueryStats {
    std::size_t nodesVisited = 0;
    std::size_t trianglesTested = 0;
    std::size_t trianglesCrossing = 0;
};

// Appends to `out` the global ids of the triangles that cross the plane under the sign
// rule of view/plane.hpp (some vertex at distance < 0 and some at >= 0), visiting only
// nodes whose box straddles the plane. Output order is deterministic (traversal order).
void queryPlane(const Bvh& bvh, const BvhMesh* meshes, const LocalPlane& plane, std::vector<std::uint32_t>& out,
                BvhQueryStats* stats = nullptr);

// The leaves (indices into Bvh::nodes) whose boxes straddle the plane (and, when `rect` is
// not null, overlap it): node traversal only, no triangle is read. The section cut tests
// the leaves' triangles itself, so each vertex is fetched once (section/cut/plane_cut.hpp).
void queryPlaneLeaves(const Bvh& bvh, const LocalPlane& plane, const PlaneRect* rect,
                      std::vector<std::uint32_t>& leaves, BvhQueryStats* stats = nullptr);

// Work units for a parallel traversal: the straddling (and rectangle-overlapping) nodes of
// a breadth-first descent from the root that stops once at least `minUnits` are known or
// only leaves are left, in that order. The leaves queryPlaneLeavesUnder finds under each
// unit, unit by unit, are exactly the leaves of queryPlaneLeaves (in another order).
void queryPlaneUnits(const Bvh& bvh, const LocalPlane& plane, const PlaneRect* rect, std::size_t minUnits,
                     std::vector<std::uint32_t>& units, BvhQueryStats* stats = nullptr);
// Appends the straddling leaves under node `unit` (breadth first, as queryPlaneLeaves).
void queryPlaneLeavesUnder(const Bvh& bvh, std::uint32_t unit, const LocalPlane& plane, const PlaneRect* rect,
                           std::vector<std::uint32_t>& leaves, BvhQueryStats* stats = nullptr);

// As queryPlane, and also skips nodes and triangles whose extent along u or v misses
// [u0, u1] x [v0, v1] (conservative: a triangle returned may still miss the rectangle).
void queryPlaneRect(const Bvh& bvh, const BvhMesh* meshes, const LocalPlane& plane, const PlaneRect& rect,
                    std::vector<std::uint32_t>& out, BvhQueryStats* stats = nullptr);

}  // namespace geoslice
