// True north on a map in a projected CRS: the azimuth of the meridian through a point,
// measured from grid north (the CRS's +y axis), degrees clockwise; negative when true
// north lies west of grid north (east of a Transverse Mercator zone's central meridian).
// Found numerically from the CRS's own inverse and forward projection (model/crs/crs.hpp):
// the point, and the point 0.001 degree of latitude north of it on the same meridian.
// Pure function, any thread.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "model/crs/crs.hpp"

namespace geoslice::print {

// nullopt for a local or geographic CRS, or where the projection fails at `world` (x, y).
std::optional<double> trueNorthDeg(const Crs& crs, const glm::dvec2& world);

}  // namespace geoslice::print
