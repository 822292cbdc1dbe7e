// Exact vertex welding and part assembly shared by the readers of formats that repeat a
// vertex per face (STL facets, DXF 3DFACEs) or give faces per region (PLY, Surpac DTM).
//
// Welding is exact: two corners are one vertex when their coordinates are bit-for-bit the
// same double (-0 and +0 are the same). A wireframer's closed shell written per facet
// becomes a closed mesh again; nothing is snapped by a tolerance (a tolerance would merge
// distinct vertices of a fine mesh and hide real gaps).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"

namespace geoslice {

class VertexWelder {
public:
    // Index (into positions) of the vertex with exactly these coordinates, added if new.
    std::uint32_t add(const glm::dvec3& p) {
        Key k{bits(p.x), bits(p.y), bits(p.z)};
        auto [it, inserted] = index_.try_emplace(k, static_cast<std::uint32_t>(positions.size()));
        if (inserted) positions.push_back(p);
        return it->second;
    }
    std::vector<glm::dvec3> positions;  // world, metres, first-use order

private:
    struct Key {
        std::uint64_t x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
            h ^= k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
            h ^= k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
            return static_cast<std::size_t>(h);
        }
    };
    static std::uint64_t bits(double v) {
        v += 0.0;  // -0 -> +0
        std::uint64_t b = 0;
        std::memcpy(&b, &v, sizeof b);
        return b;
    }
    std::unordered_map<Key, std::uint32_t, KeyHash> index_;
};

// A part under construction: welded vertices and triangles (3 indices each).
struct WeldedPart {
    std::string name;
    VertexWelder welder;
    std::vector<std::uint32_t> indices;
    void addTriangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        indices.push_back(welder.add(a));
        indices.push_back(welder.add(b));
        indices.push_back(welder.add(c));
    }
};

// Moves built parts into `model` (as undeclared parts: finishLoadedModel() classifies them
// by closure), each with its own attribute record named after it; parts with no triangles
// are skipped.
inline void addWeldedParts(Model& model, std::vector<WeldedPart>& parts) {
    for (WeldedPart& b : parts) {
        if (b.indices.empty()) continue;
        Part part;
        part.name = b.name;
        part.mesh.positions = std::move(b.welder.positions);
        part.mesh.indices = std::move(b.indices);
        AttributeRecord rec;
        rec.name = part.name;
        part.record = model.attributes.add(std::move(rec));
        model.bodies.push_back(std::move(part));
    }
}

// After finishLoadedModel(): the records' kind follows the classification.
inline void setRecordKinds(Model& model) {
    for (auto* list : {&model.bodies, &model.surfaces})
        for (Part& p : *list)
            if (AttributeRecord* r = model.attributes.find(p.record); r && r->kind.empty())
                r->kind = p.kind == PartKind::Body ? "body" : "surface";
}

}  // namespace geoslice
