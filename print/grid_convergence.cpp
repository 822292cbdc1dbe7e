#include "print/grid_convergence.hpp"

#include <cmath>
#include <numbers>

namespace geoslice::print {

std::optional<double> trueNorthDeg(const Crs& crs, const glm::dvec2& world) {
    if (!crs.isProjected()) return std::nullopt;
    auto ll = crs.toLonLat(world.x, world.y);
    if (!ll) return std::nullopt;
    auto north = crs.fromLonLat(ll.value().x, ll.value().y + 1e-3);
    if (!north) return std::nullopt;
    const glm::dvec2 d = north.value() - world;
    if (!(glm::dot(d, d) > 0.0)) return std::nullopt;
    return std::atan2(d.x, d.y) * 180.0 / std::numbers::pi;
}

}  // namespace geoslice::print
