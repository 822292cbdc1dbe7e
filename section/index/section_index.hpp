// Everything the section engine precomputes for one model: the part table (bodies then
// surfaces, with records, colours and nesting), welded vertex ids per part (so that
// contour chaining follows mesh edges, not float matching), the triangle BVH and the
// cut's table of each of its leaves.
//
// Part p < model.bodies.size() is model.bodies[p]; the others are model.surfaces in order.
// Triangle ids are global: part p owns [bvh.meshFirst[p], bvh.meshFirst[p + 1]).
// The index points into the model's meshes: the model must outlive it and stay unchanged.
// Thread-safety: build once; read from any number of threads.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/result.hpp"
#include "section/index/bvh.hpp"
#include "section/index/leaf_tables.hpp"

namespace geoslice {

struct SectionPart {
    const Part* part = nullptr;
    PartKind kind = PartKind::Body;
    RecordId record = kNoRecord;
    Rgba8 colour;     // from the attribute table, grey when the record has none
    int parent = -1;  // part index of the innermost body containing this body, or -1
    int depth = 0;    // nesting depth (validation's)
    bool closed = false;
    // Welded vertex id per vertex (equal positions share the smallest index); empty when
    // every vertex of the part already has a distinct position (identity), and for closed
    // bodies, whose indices validation made the split 2-manifold (pinch-outs kept apart).
    std::vector<std::uint32_t> canon;

    std::uint32_t weld(std::uint32_t v) const { return canon.empty() ? v : canon[v]; }
};

struct SectionIndex {
    const Model* model = nullptr;
    glm::dvec3 origin{0.0};  // Model::origin
    Aabb bounds;             // model bounds, world
    std::vector<SectionPart> parts;
    std::vector<BvhMesh> meshes;  // one per part, for the BVH
    Bvh bvh;
    LeafTables leafTables;  // the cut's table of each BVH leaf (section/index/leaf_tables.hpp)
    std::size_t bodyCount = 0;

    std::size_t memoryBytes() const;
};

// Builds the index. The model should be validated (outward bodies, nesting parents).
// Errors: from buildBvh (too many triangles).
Result<std::unique_ptr<SectionIndex>> buildSectionIndex(const Model& model, const BvhOptions& options = {});

// The same index with the BVH read from saveBvh() bytes made for this model (a baked
// package's section.bvh) instead of built: the sections are the same, bit for bit.
// Errors: loadBvh's (ParseError naming `source`).
Result<std::unique_ptr<SectionIndex>> loadSectionIndex(const Model& model, std::span<const std::uint8_t> savedBvh,
                                                       const std::string& source);

}  // namespace geoslice
