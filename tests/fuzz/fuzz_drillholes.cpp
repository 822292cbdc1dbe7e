// libFuzzer target for the drillhole tables (model/drillholes): any bytes, cut into a collar,
// a survey and an interval table at form feeds ('\f'), must give a desurveyed database or an
// error, never a crash, a hang or an unbounded allocation. The first byte picks the dip
// convention of the collar and survey tables.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/drillholes/drillholes.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice;
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const DipConvention dip =
        !bytes.empty() && (bytes[0] & 1) ? DipConvention::PositiveDown : DipConvention::NegativeDown;
    std::string_view parts[3];
    for (int k = 0; k < 3; ++k) {
        const std::size_t at = k < 2 ? bytes.find('\f') : std::string_view::npos;
        parts[k] = bytes.substr(0, at);
        bytes = at == std::string_view::npos ? std::string_view() : bytes.substr(at + 1);
    }
    DrillholeSources s;
    s.source = "fuzz";
    s.collar = {"collar", "collar.csv", std::string(parts[0]), {}, {}, dip};
    if (!parts[1].empty()) s.survey = DrillholeTableSource{"survey", "survey.csv", std::string(parts[1]), {}, {}, dip};
    if (!parts[2].empty())
        s.intervals.push_back(
            {"lithology", "lithology.csv", std::string(parts[2]), {}, {}, DipConvention::NegativeDown});
    auto db = buildDrillholes(std::move(s));
    if (!db.ok()) return 0;
    // Touch the result: indices in range, paths finite and in depth order.
    for (const Drillhole& h : db->holes) {
        const HolePath& p = h.path;
        if (p.depth.size() != p.position.size() || p.depth.size() != p.direction.size()) __builtin_trap();
        for (std::size_t i = 0; i < p.depth.size(); ++i) {
            if (!std::isfinite(p.position[i].x) || !std::isfinite(p.position[i].z)) __builtin_trap();
            if (i > 0 && !(p.depth[i] >= p.depth[i - 1])) __builtin_trap();
        }
        if (!p.depth.empty()) (void)p.at(0.5 * p.depth.back());
    }
    for (const IntervalTable& t : db->intervals)
        for (std::size_t i = 0; i < t.size(); ++i)
            if (t.hole[i] >= db->holes.size() || !(t.from[i] < t.to[i])) __builtin_trap();
    return 0;
}
