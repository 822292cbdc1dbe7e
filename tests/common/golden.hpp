// The one golden-image comparator of the test suites (MapLibre render tests, Magnum's image
// comparison): a case is a folder tests/data/goldens/<case>/ holding request.json (what to
// render, read by the suite that runs the case's "runner", and one entry per output under
// "outputs" with the expected file, its tolerance and the reason for that tolerance) and the
// expected PNGs. A pixel fails when one of its compared channels differs by more than
// maxChannelDiff (0: exact, as record ids must be); a comparison fails when more than
// maxFailingFraction of the pixels fail. UPDATE_GOLDENS=1 rewrites the expected files; a
// failing comparison writes <case>.<output>.actual.png and .diff.png (red: failing pixel,
// grey: the expected image dimmed) into the caller's failure folder.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image_encode.hpp"

namespace geoslice::test {

inline std::string goldenDir() {
#ifdef GEOSLICE_GOLDEN_DIR
    return GEOSLICE_GOLDEN_DIR;
#else
    return std::string(GEOSLICE_TEST_DATA_DIR) + "/goldens";
#endif
}

inline bool updatingGoldens() {
    const char* u = std::getenv("UPDATE_GOLDENS");
    return u && std::string(u) == "1";
}

// request.json of a case (a parse failure is a test failure and an empty object).
inline nlohmann::json goldenRequest(const std::string& name) {
    const std::string path = goldenDir() + "/" + name + "/request.json";
    std::ifstream f(path);
    nlohmann::json j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
    EXPECT_TRUE(j.is_object()) << path << " is not a JSON object";
    return j.is_object() ? j : nlohmann::json::object();
}

// The cases whose request.json names `runner`, sorted (a parameterised suite's values).
inline std::vector<std::string> goldenCases(const std::string& runner) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(goldenDir(), ec)) {
        const auto request = entry.path() / "request.json";
        if (!std::filesystem::exists(request)) continue;
        std::ifstream f(request);
        const nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
        if (j.is_object() && j.value("runner", "") == runner) out.push_back(entry.path().filename().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

struct GoldenTolerance {
    std::string file;               // the expected image in the case folder
    int maxChannelDiff = 0;         // of 255; 0: exact
    double maxFailingFraction = 0;  // of all pixels
    int channels = 4;               // 3: RGB, 4: RGBA
    std::string reason;             // why this tolerance (stated in request.json)
};

// outputs.<output> of a request: {"expected", "maxChannelDiff", "maxFailingFraction",
// "channels": "rgb"|"rgba", "reason"}; "exact": true stands for 0 and 0.
inline GoldenTolerance goldenTolerance(const nlohmann::json& request, const std::string& output) {
    GoldenTolerance t;
    const nlohmann::json o = request.value("outputs", nlohmann::json::object()).value(output, nlohmann::json());
    EXPECT_TRUE(o.is_object()) << "request.json has no outputs." << output;
    if (!o.is_object()) return t;
    t.file = o.value("expected", "");
    t.reason = o.value("reason", "");
    t.channels = o.value("channels", "rgba") == "rgb" ? 3 : 4;
    if (!o.value("exact", false)) {
        t.maxChannelDiff = o.value("maxChannelDiff", -1);
        t.maxFailingFraction = o.value("maxFailingFraction", -1.0);
    }
    EXPECT_FALSE(t.file.empty()) << output << ": no expected file";
    EXPECT_FALSE(t.reason.empty()) << output << ": every tolerance states its reason";
    EXPECT_TRUE(t.maxChannelDiff >= 0 && t.maxChannelDiff <= 255 && t.maxFailingFraction >= 0.0 &&
                t.maxFailingFraction <= 1.0)
        << output << ": tolerance missing or out of range";
    return t;
}

// Compares an RGBA8 image (row 0 first) with the case's expected file.
inline void compareGolden(const std::string& name, const std::string& output, const std::uint8_t* rgba, int w, int h,
                          const GoldenTolerance& t, const std::string& failureDir) {
    const std::string path = goldenDir() + "/" + name + "/" + t.file;
    if (updatingGoldens()) {
        ASSERT_TRUE(writeImage(path, rgba, w, h).ok()) << path;
        std::printf("[ golden   ] rewrote %s\n", path.c_str());
        return;
    }
    auto expected = readPngRgba(path);
    ASSERT_TRUE(expected.ok()) << expected.error().message << " (run with UPDATE_GOLDENS=1 to create it)";
    ASSERT_EQ(expected->width, w) << path;
    ASSERT_EQ(expected->height, h) << path;
    const std::size_t n = std::size_t(w) * std::size_t(h) * 4;
    std::vector<std::uint8_t> diff(n);
    std::size_t failing = 0;
    int maxDiff = 0;
    for (std::size_t i = 0; i < n; i += 4) {
        int d = 0;
        for (int c = 0; c < t.channels; ++c) d = std::max(d, std::abs(int(rgba[i + c]) - int(expected->rgba[i + c])));
        maxDiff = std::max(maxDiff, d);
        const bool fail = d > t.maxChannelDiff;
        failing += fail;
        const auto grey =
            std::uint8_t((expected->rgba[i] / 4 + expected->rgba[i + 1] / 4 + expected->rgba[i + 2] / 4) / 3 * 2 + 64);
        diff[i] = fail ? 255 : grey;
        diff[i + 1] = fail ? 0 : grey;
        diff[i + 2] = fail ? 0 : grey;
        diff[i + 3] = 255;
    }
    const double fraction = double(failing) / double(std::size_t(w) * std::size_t(h));
    const bool ok = fraction <= t.maxFailingFraction;
    std::printf("[ golden   ] %s.%s: %zu failing pixels (%.3f%%), max channel diff %d\n", name.c_str(), output.c_str(),
                failing, 100.0 * fraction, maxDiff);
    if (!ok) {
        std::filesystem::create_directories(failureDir);
        const std::string base = failureDir + "/" + name + "." + output;
        EXPECT_TRUE(writeImage(base + ".actual.png", rgba, w, h).ok());
        EXPECT_TRUE(writeImage(base + ".diff.png", diff.data(), w, h).ok());
        std::printf("[ golden   ] wrote %s.actual.png and %s.diff.png\n", base.c_str(), base.c_str());
    }
    EXPECT_TRUE(ok) << name << "." << output << ": " << failing << " pixels differ by more than " << t.maxChannelDiff
                    << " (at most " << t.maxFailingFraction * 100.0 << " % may; " << t.reason << ")";
}

}  // namespace geoslice::test
