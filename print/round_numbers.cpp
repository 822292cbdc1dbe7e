#include "print/round_numbers.hpp"

#include <cmath>
#include <cstdio>

namespace geoslice::print {

double niceAtLeast(double x, std::initializer_list<double> mantissas) {
    const double decade = std::pow(10.0, std::floor(std::log10(x)));
    for (int k = 0; k < 2; ++k) {
        const double d = decade * (k == 0 ? 1.0 : 10.0);
        for (double m : mantissas)
            if (m * d * (1.0 + 1e-9) >= x) return m * d;
    }
    return 10.0 * decade * *mantissas.begin();  // unreachable for mantissas in [1, 10)
}

double niceAtMost125(double x) {
    const double decade = std::pow(10.0, std::floor(std::log10(x)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * decade <= x * (1.0 + 1e-9)) return m * decade;
    return decade;  // unreachable: x >= decade
}

int decimalsFor(double step) {
    int decimals = 0;
    // A multiple of step prints exactly with d decimals when step x 10^d is a whole number.
    while (decimals < 6 && std::abs(step * std::pow(10.0, decimals) - std::round(step * std::pow(10.0, decimals))) >
                               1e-6 * step * std::pow(10.0, decimals))
        ++decimals;
    return decimals;
}

std::string formatGrouped(double value, int decimals, double groupFrom) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
    std::string s = buf;
    if (s.find_first_not_of("-0.") == std::string::npos) s = decimals > 0 ? "0." + std::string(decimals, '0') : "0";
    if (std::abs(value) < groupFrom) return s;
    const std::size_t sign = s[0] == '-' ? 1 : 0;
    std::size_t end = s.find('.');
    if (end == std::string::npos) end = s.size();
    for (std::size_t i = end; i > sign + 3; i -= 3) s.insert(i - 3, ",");
    return s;
}

}  // namespace geoslice::print
