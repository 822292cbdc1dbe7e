// The axes of a map frame: ticks out of all four sides at round steps (print/ticks.hpp),
// labels in metres (left and right: the vertical axis, bottom: the horizontal axis),
// axis titles, and optional grid lines across the map (elevation lines on a section, the
// coordinate grid on a horizontal slice). Page millimetres. Any thread.
#pragma once

#include <string>
#include <vector>

#include "print/map_frame.hpp"
#include "print/sheet.hpp"
#include "print/ticks.hpp"

namespace geoslice::print {

struct AxisSpec {
    std::string title;    // e.g. "Elevation (m)"
    double origin = 0.0;  // a tick's value = section coordinate - origin (distance from an end)
};

struct AxesSpec {
    AxisSpec horizontal, vertical;
    bool grid = false;  // grid lines at every tick across the map
};

struct PlacedTick {
    Tick tick;
    double pageMm = 0.0;  // page x (horizontal axis) or y (vertical axis) of the tick, mm
};

constexpr double kTickLabelPt = 7.0;

// The ticks drawAxes places: values at round steps inside the shown range, labels no
// closer than their width plus a gap (horizontal) or kMinTickSpacingMm.
std::vector<PlacedTick> horizontalTicks(const MapFrame& frame, const AxisSpec& axis);
std::vector<PlacedTick> verticalTicks(const MapFrame& frame, const AxisSpec& axis);

// Appends the grid (when asked), the frame's outline, ticks, labels and titles.
void drawAxes(Sheet& sheet, const MapFrame& frame, const AxesSpec& spec);

}  // namespace geoslice::print
