// Deterministic synthetic mine models: folded strata cut by two dipping normal faults,
// a terrain top, and a silica-sandstone orebody lens, every body a watertight outward shell.
//
// Construction (all in a "param" frame, then one smooth shear): the domain is 6 km (east)
// x 4 km (north). Horizons are smooth functions (an anticline and a syncline, a gentle
// plunge, thickness variations); two faults split the domain into three blocks (a
// graben: the central block is thrown down). Each stratum in each block is a heightfield
// prism (top, bottom and four walls sharing vertices), so it is closed by construction.
// The faults are vertical in the param frame; the map x = x' + K(x') (z - zRef), with K
// piecewise linear, zero at the domain's sides and +-cot(70 deg) at the faults, tilts the
// fault walls to a 70-degree dip. It is monotone in x' (|dK/dx' (z - zRef)| < 1), hence a
// bijection that keeps every shell closed and outward.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

enum class OreVariant {
    Nested,     // host stratum has no hole; the lens lies inside it (nesting depth 1)
    Partition,  // host stratum has a matching cavity; bodies partition space
};

struct SyntheticOptions {
    std::size_t triangles = 20000;  // target total, met within 5% (minimum 2000)
    std::uint64_t seed = 1;         // varies fold phases, thickness and terrain
    OreVariant ore = OreVariant::Nested;
    Crs crs;                             // local when not projected
    std::optional<glm::dvec2> atLonLat;  // model centre; default: central meridian, 30.6 N
};

// Named sizes of the paper's Table 1.
std::optional<std::size_t> namedModelSize(const std::string& name);  // "L1".."L4"

Result<Model> generateSynthetic(const SyntheticOptions& options);

}  // namespace geoslice
