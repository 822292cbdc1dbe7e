// Drillholes on a section: the part of every hole within a window of the section, projected
// perpendicularly onto it (section/holes/hole_section.cpp). The index finds the chords near
// the plane (model/drillholes/hole_index.hpp); each chord is clipped to the window, split
// where it pierces the plane, and mapped to section coordinates.
//
// Frames: plane sections give plane u/v metres (SectionFrame, view/plane.hpp); polyline
// sections give (chainage s, elevation z), each leg's part of a hole projected onto that
// leg's vertical plane and kept where its chainage falls within the leg. `offset` is the
// signed distance from the plane (or the leg's plane), metres, positive on the kept side:
// a viewer of a section stands on the removed side, so offset < 0 is IN FRONT of the
// section (between the viewer and the cut face) and offset >= 0 BEHIND it (inside the kept
// rock; a point exactly on the plane counts as behind, the engine's Simulation of
// Simplicity rule). Depths are metres along the hole. Pure functions, any thread.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "model/drillholes/hole_index.hpp"
#include "section/cut/polyline.hpp"
#include "view/plane.hpp"

namespace geoslice {

// A straight piece of a hole's projection, wholly in front of or behind the section.
struct HoleTracePiece {
    std::uint32_t hole = 0;
    double from = 0.0, to = 0.0;  // depths of its ends
    glm::dvec2 a{0.0}, b{0.0};    // section coordinates of its ends (depth from, to)
    double offsetA = 0.0, offsetB = 0.0;
    bool front = false;     // offset < 0 along the whole piece
    std::uint32_t leg = 0;  // polyline sections: the leg; plane sections: 0
};

// Where a hole crosses the section (offset changes sign).
struct HolePierce {
    std::uint32_t hole = 0;
    double depth = 0.0;
    glm::dvec2 at{0.0};
    std::uint32_t leg = 0;
};

// The shallowest drawn point of each hole shown (where its id is written): the collar when
// the collar is within the window (`collar` true), else where the hole enters the window.
struct HoleLabel {
    std::uint32_t hole = 0;
    double depth = 0.0;
    glm::dvec2 at{0.0};
    bool collar = false;
};

struct HoleSection {
    std::vector<HoleTracePiece> pieces;  // by hole, then depth (polyline: by leg, then hole, then depth)
    std::vector<HolePierce> pierces;
    std::vector<HoleLabel> labels;  // one per hole shown, ascending hole
};

// The holes within `window` metres (>= 0) of a plane section with frame `frame`.
HoleSection holesOnPlane(const HoleIndex& index, const SectionFrame& frame, double window);
// The holes within `window` metres of the legs of a vertical polyline section.
HoleSection holesOnLine(const HoleIndex& index, const SectionLine& line, double window);

}  // namespace geoslice
