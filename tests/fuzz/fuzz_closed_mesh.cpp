// libFuzzer target for closed meshes with closed-form answers (tests/common/closed_mesh_cases.hpp):
// the bytes choose the generator's parameters (shape, extents, offset, axis map, winding per
// shell, welding, grid lines, variant, and the seed of the triangulation and the shuffles)
// and every property of checkCase must hold: analyseMesh closed with the right shells and
// volume, cavities inward, the split 2-manifold written back; the model path's classify,
// section areas and reserves equal to the closed forms. A failure is printed and traps.
//
// Bytes: 0 shape, 1 offset kind (bits 0-1) and weld (bits 2-3), 2 axis permutation (low 3
// bits) and mirrors (next 3), 3 winding flips (low 4 bits) and extra grid lines (high 4),
// 4 polygon sides, 5 variant, 6-11 the three extents (16-bit, log scale 0.5 .. 3000 m),
// 12-19 the seed; any further bytes are folded into the seed. Missing bytes read as 0.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <random>

#include "tests/common/closed_mesh_cases.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice::test::closed;
    auto byte = [&](std::size_t i) -> unsigned { return i < size ? data[i] : 0u; };
    CaseParams p;
    p.shape = static_cast<Shape>(byte(0) % kShapeCount);
    p.offsetKind = static_cast<int>(byte(1) & 3u);
    p.weld = static_cast<Weld>((byte(1) >> 2) & 3u);
    p.axisPerm = static_cast<int>(byte(2) & 7u);
    p.mirror = static_cast<int>((byte(2) >> 3) & 7u);
    p.windingFlips = byte(3) & 15u;
    p.extraLines = static_cast<int>(byte(3) >> 4);
    p.sides = static_cast<int>(byte(4));
    p.variant = static_cast<int>(byte(5));
    for (int k = 0; k < 3; ++k) {
        const double u = double(byte(6 + 2 * std::size_t(k)) | (byte(7 + 2 * std::size_t(k)) << 8)) / 65535.0;
        p.size[k] = 0.5 * std::exp(u * std::log(6000.0));
    }
    std::uint64_t seed = 0;
    for (std::size_t i = 0; i < 8; ++i) seed |= std::uint64_t(byte(12 + i)) << (8 * i);
    for (std::size_t i = 20; i < size; ++i) seed = (seed ^ data[i]) * 0x100000001B3ull;  // FNV-1a step
    p.seed = seed;

    const Case cs = makeCase(p);
    std::mt19937_64 rng(seed ^ 0x9E3779B97F4A7C15ull);
    const auto fails = checkCase(cs, rng);
    if (!fails.empty()) {
        std::fprintf(stderr, "closed mesh case failed: %s\n", cs.params.text().c_str());
        for (const auto& f : fails) std::fprintf(stderr, "  %s\n", f.c_str());
        __builtin_trap();
    }
    return 0;
}
