// 16-bit buffers the geoslice executable writes (`render --ids/--cells x.pgm`) and the
// two-engine agreement rule the tests compare them by.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace geoslice::test {

inline std::string readFileBytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// A 16-bit binary PGM (big-endian samples); empty when it is not one. Sets w and h.
inline std::vector<std::uint32_t> readPgm16(const std::filesystem::path& p, int& w, int& h) {
    const std::string bytes = readFileBytes(p);
    int maxval = 0, consumed = 0;
    if (std::sscanf(bytes.c_str(), "P5 %d %d %d%n", &w, &h, &maxval, &consumed) != 3 || maxval != 65535) return {};
    const std::size_t start = std::size_t(consumed) + 1, n = std::size_t(w) * std::size_t(h);
    if (bytes.size() < start + 2 * n) return {};
    std::vector<std::uint32_t> v(n);
    for (std::size_t i = 0; i < n; ++i)
        v[i] = (std::uint32_t(std::uint8_t(bytes[start + 2 * i])) << 8) | std::uint8_t(bytes[start + 2 * i + 1]);
    return v;
}

// Two engines' w x h buffers (row 0 at the top) compared where the exact one's 3x3
// neighbourhood holds one value (the rasteriser samples triangle coverage, the exact engine
// polygon coverage, so edge pixels may differ); `withZero` false: pixels of value 0 are skipped.
struct Agreement {
    std::size_t compared = 0, agree = 0;
};
inline Agreement agreeWhereUniform(const std::vector<std::uint32_t>& exact, const std::vector<std::uint32_t>& other,
                                   int w, int h, bool withZero) {
    Agreement a;
    auto at = [w](const std::vector<std::uint32_t>& v, int x, int y) {
        return v[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    };
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const std::uint32_t value = at(exact, x, y);
            bool uniform = withZero || value != 0;
            for (int dy = -1; dy <= 1 && uniform; ++dy)
                for (int dx = -1; dx <= 1 && uniform; ++dx) uniform = at(exact, x + dx, y + dy) == value;
            if (!uniform) continue;
            ++a.compared;
            a.agree += at(other, x, y) == value;
        }
    return a;
}

}  // namespace geoslice::test
