// libFuzzer target for the saved section BVH (section/index/bvh.hpp loadBvh, a baked package's
// section.bvh): any bytes must give a tree whose traversal stays in bounds and ends, and whose
// leaf tables (built by loadSectionIndex) cut in bounds, or an error, never a crash, a hang or
// an unbounded allocation. The mesh is fixed (a quad of two
// triangles and a triangle, two meshes, origin 0); seeds (corpus/bvh/) are saved trees of it:
// a root leaf and a root with two leaf children.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "model/model.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/plane_cut.hpp"
#include "section/index/section_index.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice;
    static const glm::dvec3 positions[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 1}, {0, 1, 1}, {2, 0, 0}, {3, 0, 1}, {2, 1, 2}};
    static const std::uint32_t quad[] = {0, 1, 2, 0, 2, 3};
    static const std::uint32_t tri[] = {4, 5, 6};
    static const BvhMesh meshes[] = {{positions, 4, quad, 2}, {positions, 7, tri, 1}};
    auto bvh = loadBvh(std::span<const std::uint8_t>(data, size), meshes, 2, glm::dvec3(0.0), "fuzz");
    if (!bvh) return 0;
    // Traverse with planes that cross everything and nothing: ids must be real triangles.
    std::vector<std::uint32_t> out, leaves;
    for (double z : {0.5, -10.0}) {
        const LocalPlane plane = toLocal(Plane{glm::dvec3(0, 0, 1), -z}, glm::dvec3(0.0));
        out.clear();
        queryPlane(bvh.value(), meshes, plane, out);
        for (std::uint32_t id : out)
            if (id >= 3) __builtin_trap();
        leaves.clear();
        queryPlaneLeaves(bvh.value(), plane, nullptr, leaves);
        for (std::uint32_t leaf : leaves)
            if (leaf >= bvh->nodes.size()) __builtin_trap();
    }
    // The same bytes as a model's stored tree: the section index builds the cut's leaf tables
    // from it (section/index/leaf_tables.hpp), and cuts through them on one and two threads must
    // stay in bounds (the sanitizers watch) and give at most one segment per listed triangle
    // (a stored tree's leaves may list an id twice: the package's checksums vouch for it).
    static const Model model = [] {
        Model m;
        Part a, b;
        a.kind = b.kind = PartKind::Surface;
        a.mesh.positions.assign(positions, positions + 4);
        a.mesh.indices.assign(quad, quad + 6);
        b.mesh.positions.assign(positions + 4, positions + 7);
        b.mesh.indices = {0, 1, 2};
        m.surfaces = {a, b};
        return m;
    }();
    auto index = loadSectionIndex(model, std::span<const std::uint8_t>(data, size), "fuzz");
    if (!index) return 0;
    for (double z : {0.5, 1.5, -10.0})
        for (unsigned threads : {1u, 2u}) {
            PlaneCut cut;
            beginCut(**index, Plane{glm::dvec3(0, 0, 1), -z}, cut);
            cutWithBvh(**index, nullptr, cut, threads);
            if (cut.segments > 64 * (*index)->bvh.nodes.size()) __builtin_trap();  // leaves may share ids
            Section section;
            assembleContours(**index, cut, section, threads);
        }
    return 0;
}
