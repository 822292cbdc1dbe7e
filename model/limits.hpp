// Limits on what a model may hold, in one place: the largest coordinate any geometry, frame
// or query may have. Views add their own limits on top (view/view_limits.hpp).
#pragma once

namespace geoslice {

// The largest |coordinate| of a frame (plane u/v, chainage, elevation), a camera point, a
// plane offset, an elevation, a line vertex or a block centre, metres: beyond any real
// model (Gauss-Kruger eastings with a zone prefix reach 4.6e7 m).
constexpr double kMaxCoordinateMetres = 1e8;

}  // namespace geoslice
