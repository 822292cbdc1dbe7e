#include "section/index/leaf_order.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include "section/index/bvh.hpp"

namespace geoslice {
namespace {

constexpr std::uint32_t kUnset = 0xFFFFFFFFu;

// Permutes one mesh: `order` lists the old triangle numbers in their new order (each once,
// a prefix of all of them); the rest follow in their old order.
void reorderMesh(Mesh& mesh, const std::vector<std::uint32_t>& order) {
    const std::size_t triangles = mesh.triangleCount(), vertices = mesh.vertexCount();
    std::vector<char> placed(triangles, 0);
    std::vector<std::uint32_t> triOrder = order;
    triOrder.reserve(triangles);
    for (std::uint32_t t : order) placed[t] = 1;
    for (std::uint32_t t = 0; t < triangles; ++t)
        if (!placed[t]) triOrder.push_back(t);

    std::vector<std::uint32_t> newVertex(vertices, kUnset);  // old -> new
    std::vector<std::uint32_t> oldVertex;                    // new -> old
    oldVertex.reserve(vertices);
    std::vector<std::uint32_t> indices(mesh.indices.size());
    for (std::size_t i = 0; i < triOrder.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.indices[3 * std::size_t(triOrder[i]) + std::size_t(k)];
            if (newVertex[v] == kUnset) {
                newVertex[v] = static_cast<std::uint32_t>(oldVertex.size());
                oldVertex.push_back(v);
            }
            indices[3 * i + std::size_t(k)] = newVertex[v];
        }
    for (std::uint32_t v = 0; v < vertices; ++v)
        if (newVertex[v] == kUnset) oldVertex.push_back(v);

    std::vector<glm::dvec3> positions(vertices);
    for (std::size_t v = 0; v < vertices; ++v) positions[v] = mesh.positions[oldVertex[v]];
    const std::size_t columns = mesh.propertyNames.size();
    if (columns > 0 && mesh.propertyValues.size() == vertices * columns) {
        std::vector<float> values(mesh.propertyValues.size());
        for (std::size_t v = 0; v < vertices; ++v)
            std::copy_n(mesh.propertyValues.begin() + std::ptrdiff_t(oldVertex[v] * columns), columns,
                        values.begin() + std::ptrdiff_t(v * columns));
        mesh.propertyValues = std::move(values);
    }
    mesh.positions = std::move(positions);
    mesh.indices = std::move(indices);
}

}  // namespace

Status reorderForSection(Model& model) {
    std::vector<Part*> parts;
    std::vector<BvhMesh> meshes;
    for (auto* list : {&model.bodies, &model.surfaces})
        for (Part& p : *list) {
            parts.push_back(&p);
            meshes.push_back(BvhMesh{p.mesh.positions.data(), p.mesh.positions.size(), p.mesh.indices.data(),
                                     p.mesh.triangleCount()});
        }
    auto bvh = buildBvh(meshes.data(), meshes.size(), model.origin);
    if (!bvh) return bvh.error();
    const Bvh& tree = bvh.value();
    std::vector<std::vector<std::uint32_t>> order(parts.size());
    for (std::size_t p = 0; p < parts.size(); ++p) order[p].reserve(parts[p]->mesh.triangleCount());
    // Leaves in tree order (depth first, left before right): the order the ids are stored in.
    for (std::uint32_t id : tree.triangles) {
        const std::uint32_t p = tree.meshOf(id);
        order[p].push_back(id - tree.meshFirst[p]);
    }
    for (std::size_t p = 0; p < parts.size(); ++p) reorderMesh(parts[p]->mesh, order[p]);
    return {};
}

}  // namespace geoslice
