#include "print/ticks.hpp"

#include <cmath>

#include "model/result.hpp"
#include "print/round_numbers.hpp"

namespace geoslice::print {

double tickStep(double metresPerMm, double minSpacingMm) {
    return niceAtLeast(metresPerMm * minSpacingMm, {1.0, 2.0, 5.0});
}

std::vector<Tick> axisTicks(double lo, double hi, double step, std::size_t maxTicks) {
    GS_ASSERT(step > 0.0 && std::isfinite(step) && hi >= lo, "axisTicks: bad range or step");
    const double first = std::ceil(lo / step - 1e-9);
    const double last = std::floor(hi / step + 1e-9);
    GS_ASSERT(last - first + 1.0 <= double(maxTicks), "axisTicks: too many ticks for the step");
    const int decimals = decimalsFor(step);
    std::vector<Tick> out;
    for (double k = first; k <= last; k += 1.0) {
        const double v = k * step;
        out.push_back({v, formatGrouped(v, decimals)});
    }
    return out;
}

}  // namespace geoslice::print
