#include "section/index/section_index.hpp"

#include <atomic>
#include <cstring>
#include <thread>

namespace geoslice {
namespace {

std::uint64_t bitsOf(double x) {
    x += 0.0;  // -0.0 -> +0.0: equal positions must hash equally
    std::uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
}

std::uint64_t hashPosition(const glm::dvec3& p) {
    std::uint64_t h = bitsOf(p.x) * 0x9E3779B97F4A7C15ull;
    h ^= bitsOf(p.y) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= bitsOf(p.z) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 29);
}

// Exact-position weld with an open-addressing table; empty result when nothing merges.
std::vector<std::uint32_t> weld(const std::vector<glm::dvec3>& pos) {
    const std::size_t n = pos.size();
    std::size_t cap = 16;
    while (cap < 2 * n) cap <<= 1;
    constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
    std::vector<std::uint32_t> table(cap, kEmpty);
    std::vector<std::uint32_t> canon(n);
    bool merged = false;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t h = static_cast<std::size_t>(hashPosition(pos[i])) & (cap - 1);
        for (;;) {
            const std::uint32_t e = table[h];
            if (e == kEmpty) {
                table[h] = static_cast<std::uint32_t>(i);
                canon[i] = static_cast<std::uint32_t>(i);
                break;
            }
            if (pos[e] == pos[i]) {
                canon[i] = e;
                merged = true;
                break;
            }
            h = (h + 1) & (cap - 1);
        }
    }
    if (!merged) canon.clear();
    return canon;
}

}  // namespace

std::size_t SectionIndex::memoryBytes() const {
    std::size_t b = bvh.memoryBytes() + leafTables.memoryBytes() + meshes.capacity() * sizeof(BvhMesh) +
                    parts.capacity() * sizeof(SectionPart);
    for (const auto& p : parts) b += p.canon.capacity() * 4;
    return b;
}

namespace {

// Everything but the BVH: parts, meshes; `makeBvh` gets the index and returns its tree. The
// welds run on a second thread while it works (they touch different memory).
template <class MakeBvh>
Result<std::unique_ptr<SectionIndex>> makeIndex(const Model& model, MakeBvh&& makeBvh) {
    auto index = std::make_unique<SectionIndex>();
    index->model = &model;
    index->origin = model.origin;
    index->bounds = model.bounds();
    index->bodyCount = model.bodies.size();
    for (const auto* list : {&model.bodies, &model.surfaces})
        for (const Part& p : *list) {
            SectionPart sp;
            sp.part = &p;
            sp.kind = list == &model.bodies ? PartKind::Body : PartKind::Surface;
            sp.record = p.record;
            if (const AttributeRecord* r = model.attributes.find(p.record)) sp.colour = r->colour;
            if (sp.kind == PartKind::Body) {
                sp.parent = p.report.parent;
                sp.depth = p.report.nestingDepth;
                sp.closed = p.report.closed;
            }
            index->parts.push_back(std::move(sp));
            index->meshes.push_back(BvhMesh{p.mesh.positions.data(), p.mesh.positions.size(), p.mesh.indices.data(),
                                            p.mesh.triangleCount()});
        }

    std::atomic<std::size_t> next{0};
    auto weldAll = [&] {
        for (std::size_t i = next++; i < index->parts.size(); i = next++) {
            // A validated closed body's indices are its 2-manifold (model/mesh/validate.hpp):
            // welding by position again would merge the shells split at its pinch-outs.
            const SectionPart& sp = index->parts[i];
            if (sp.kind == PartKind::Body && sp.part->report.closed) continue;
            index->parts[i].canon = weld(sp.part->mesh.positions);
        }
    };
    std::thread welder(weldAll);
    Result<Bvh> bvh = makeBvh(*index);
    weldAll();
    welder.join();
    if (!bvh) return bvh.error();
    index->bvh = std::move(bvh).value();
    auto tables = buildLeafTables(index->bvh, index->parts);
    if (!tables) return tables.error();
    index->leafTables = std::move(tables).value();
    return index;
}

}  // namespace

Result<std::unique_ptr<SectionIndex>> buildSectionIndex(const Model& model, const BvhOptions& options) {
    return makeIndex(model, [&](const SectionIndex& index) {
        return buildBvh(index.meshes.data(), index.meshes.size(), model.origin, options);
    });
}

Result<std::unique_ptr<SectionIndex>> loadSectionIndex(const Model& model, std::span<const std::uint8_t> savedBvh,
                                                       const std::string& source) {
    return makeIndex(model, [&](const SectionIndex& index) {
        return loadBvh(savedBvh, index.meshes.data(), index.meshes.size(), model.origin, source);
    });
}

}  // namespace geoslice
