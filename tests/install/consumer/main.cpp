// Cuts the built-in demo mine through the installed geoslice libraries and prints what the
// section holds; exits 1 when it holds nothing (tests/install/run.sh checks the output).
#include <cmath>
#include <cstdio>

#include "api/catalog.hpp"
#include "section/cut/contours.hpp"
#include "view/plane.hpp"

int main() {
    auto demo = geoslice::api::makeDemoModel(20000);
    if (!demo) {
        std::fprintf(stderr, "consumer: %s\n", demo.error().message.c_str());
        return 1;
    }
    const auto& index = *demo.value()->index;
    const double y = std::round(0.5 * (index.bounds.min.y + index.bounds.max.y));
    auto plane = geoslice::makePlane(0.0, 1.0, 0.0, -y);
    if (!plane) return 1;
    auto section = geoslice::computeSection(index, plane.value());
    if (!section) {
        std::fprintf(stderr, "consumer: %s\n", section.error().message.c_str());
        return 1;
    }
    std::printf("consumer: %zu bodies cut at northing %.0f\n", section.value().bodies.size(), y);
    return section.value().bodies.empty() ? 1 : 0;
}
