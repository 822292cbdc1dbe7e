#include "model/model.hpp"

#include <cmath>

namespace geoslice {

Aabb Mesh::bounds() const {
    Aabb b;
    for (const auto& p : positions)
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.extend(p);
    return b;
}

Aabb Model::bounds() const {
    Aabb b;
    for (const auto& p : bodies) b.extend(p.mesh.bounds());
    for (const auto& p : surfaces) b.extend(p.mesh.bounds());
    return b;
}

std::size_t Model::triangleCount() const {
    std::size_t n = 0;
    for (const auto& p : bodies) n += p.mesh.triangleCount();
    for (const auto& p : surfaces) n += p.mesh.triangleCount();
    return n;
}

void Model::recentre() {
    Aabb b = bounds();
    origin = b.valid() ? glm::round(b.centre()) : glm::dvec3(0.0);
}

std::vector<glm::vec3> Model::localPositions(const Mesh& mesh) const {
    std::vector<glm::vec3> out(mesh.positions.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = glm::vec3(mesh.positions[i] - origin);
    return out;
}

}  // namespace geoslice
