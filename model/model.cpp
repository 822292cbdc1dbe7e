#include "model/model.hpp"

#include <cmath>

namespace geoslice {

Aabb Mesh::bounds() const {
    Aabb b;
    for (const auto& p : positions)
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.extend(p);
    return b;
}

Aabb Grid::bounds() const {
    Aabb b;
    if (!points.empty()) {
        for (const auto& p : points)
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.extend(p);
        return b;
    }
    if (sampleCount() == 0) return b;
    for (int c = 0; c < 8; ++c) {
        glm::dvec3 p = origin;
        for (int a = 0; a < 3; ++a)
            if (c & (1 << a)) p += step[a] * static_cast<double>(dims[a] - 1);
        b.extend(p);
    }
    return b;
}

Aabb Model::bounds() const {
    Aabb b;
    for (const auto& p : bodies) b.extend(p.mesh.bounds());
    for (const auto& p : surfaces) b.extend(p.mesh.bounds());
    for (const auto& g : grids) b.extend(g.bounds());
    for (const auto& l : lines)
        for (const auto& p : l.points)
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) b.extend(p);
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
