// Axis ticks of a printed section: round steps (1, 2, 5 x 10^k metres) no closer than a
// given paper spacing, and the tick values inside an axis range with their labels.
// Units: metres of ground (distance, elevation, easting, northing). Pure functions, any thread.
#pragma once

#include <string>
#include <vector>

namespace geoslice::print {

struct Tick {
    double value = 0.0;  // metres, a whole multiple of the step
    std::string label;   // the value, round: "1200", "-50", "35,502,000", "2.5"
};

// The smallest 1-2-5 step (metres) whose ticks lie at least `minSpacingMm` apart on paper
// when one paper millimetre is `metresPerMm` metres. Both > 0 and finite.
double tickStep(double metresPerMm, double minSpacingMm);

// Every multiple of `step` in [lo, hi] (ends included within 1e-9 of the step), ascending,
// at most `maxTicks` (a larger count is an invariant break: the caller chose the step).
std::vector<Tick> axisTicks(double lo, double hi, double step, std::size_t maxTicks = 1000);

}  // namespace geoslice::print
