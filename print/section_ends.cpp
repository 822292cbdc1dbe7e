#include "print/section_ends.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace geoslice::print {

double azimuthDeg(const glm::dvec2& dir) {
    double a = std::atan2(dir.x, dir.y) * 180.0 / std::numbers::pi;
    if (a < 0.0) a += 360.0;
    return a >= 360.0 ? a - 360.0 : a;
}

std::string compassPoint(double azimuth) {
    static constexpr std::array<const char*, 8> kPoints{"N", "NE", "E", "SE", "S", "SW", "W", "NW"};
    const double a = std::fmod(std::fmod(azimuth, 360.0) + 360.0, 360.0);
    return kPoints[std::size_t(std::lround(a / 45.0)) % 8];
}

std::string vertexLetter(std::size_t i) {
    std::string s;
    for (std::size_t n = i + 1; n > 0; n = (n - 1) / 26) s.insert(s.begin(), char('A' + (n - 1) % 26));
    return s;
}

}  // namespace geoslice::print
