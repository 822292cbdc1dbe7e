#pragma once
// GOCAD binary sample files as the tests write them: IEEE float32, big-endian (the
// PROP_ESIZE 4 / POINTS_FILE layout that model/gocad_samples.cpp reads).
#include <cstring>
#include <string>
#include <vector>

namespace geoslice::test {

inline std::string bigEndianFloats(const std::vector<float>& v) {
    std::string out;
    out.reserve(v.size() * 4);
    for (float f : v) {
        unsigned char b[4];
        std::memcpy(b, &f, 4);
        for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>(b[k]));
    }
    return out;
}

}  // namespace geoslice::test
