// Reserves: the volume of each closed body, whole or on the kept side of a plane, and the
// tonnage and metal it holds.
//
// Volumes (divergence theorem): for a closed, outward shell, V = 1/6 sum over triangles
// of (a - o) . ((b - o) x (c - o)) for any reference point o; o is taken near the body
// (its bounding-box centre, in double) so the products stay small.
//   gross  = the body's own shell volume (a cavity in the shell is already subtracted).
//   net    = gross minus the gross volume of the bodies nested directly inside it
//            (validation's nesting parent): an orebody lens is not counted in its host.
// Kept side of a plane (a point p is kept when n . p + d >= 0, shared/DESIGN.md): every
// triangle is clipped to the kept half-space and the same sum is taken with o ON the
// plane. The cut leaves the shell open along the section; the cap that would close it (the
// section polygons, section/cut/contours.hpp) lies in the plane, so each of its tetrahedra
// with apex o has zero volume: the clipped sum is exactly the closed volume, with no need
// to build the cap. (Closing with the polygons and summing them would add 0 up to rounding.)
//
// Tonnage and metal: tonnage (t) = net volume (m³) x density (t/m³, the attribute
// record's `density`); metal = tonnage x grade, in a unit that follows the record's
// gradeUnit: "%..." -> t (x grade / 100); "g/t" or "ppm" -> g; "kg/t" -> kg; "ppb" or
// "mg/t" -> mg; anything else -> "t x <gradeUnit>" (tonnage times grade, unit stated).
// Without a density (or grade) those figures are absent.
// Thread-safety: pure function of the model.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/model.hpp"
#include "model/result.hpp"
#include "view/plane.hpp"

namespace geoslice {

struct BodyReserves {
    std::uint32_t body = 0;  // index into Model::bodies
    RecordId record = kNoRecord;
    double grossVolume = 0.0;       // m³
    double netVolume = 0.0;         // m³, nested bodies subtracted
    std::optional<double> density;  // t/m³
    std::optional<double> tonnage;  // t, netVolume x density
    std::optional<double> grade;    // in gradeUnit
    std::string gradeUnit;
    std::optional<double> metal;  // in metalUnit
    std::string metalUnit;
};

struct Reserves {
    std::optional<Plane> plane;         // when the volumes are of the kept side only
    std::vector<BodyReserves> bodies;   // closed bodies, Model::bodies order
    std::size_t skippedOpenBodies = 0;  // bodies that are not closed shells (no volume)
};

// Volume (m³) of one closed, outward mesh; with `plane`, of its part on the kept side.
double meshVolume(const Mesh& mesh, const Plane* plane = nullptr);

// Metal content from tonnage, grade and its unit (see above): {amount, unit}.
std::pair<double, std::string> metalContent(double tonnage, double grade, const std::string& gradeUnit);

// Reserves of every closed body of a validated model (closed flags, nesting parents).
// Errors: InvalidArgument for a bad plane (non-finite, zero normal).
Result<Reserves> computeReserves(const Model& model, const std::optional<Plane>& plane = std::nullopt);

}  // namespace geoslice
