// Names for the ends and bends of a printed section: compass points for a straight
// section (its left end W and right end E when the section runs west to east), letters
// A, B, C... for the vertices of a polyline section. Azimuths are degrees clockwise from
// grid north (the +y axis of the model's CRS), 0..360. Pure functions, any thread.
#pragma once

#include <cstddef>
#include <string>

#include <glm/glm.hpp>

namespace geoslice::print {

// Azimuth of a map direction (x east, y north): 0 = north, 90 = east. `dir` non-zero.
double azimuthDeg(const glm::dvec2& dir);

// The nearest of the 8 compass points: N, NE, E, SE, S, SW, W, NW.
std::string compassPoint(double azimuthDeg);

// Letter of vertex i of a polyline: A..Z, then AA, AB, ... (spreadsheet columns).
std::string vertexLetter(std::size_t i);

}  // namespace geoslice::print
