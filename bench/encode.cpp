// bench_encode [--size 1024] [--reps 15]: the image encoders of image/image_encode.hpp on
// a section-like RGBA8 frame (size x size): wavy strata of flat colour with a light shading
// ramp, dark fault traces, and a transparent background outside the cut face. Prints JSON:
// per format and setting the median and min wall time (ms) and the encoded bytes, and for
// the default setting of each format how long an encode runs on after it is cancelled
// (`cancel`: the flag set at 5 %, 25 % and 50 % of the median encode; the figure is
// the time from setting it to the encoder's return: what a vanished client or a deadline
// still costs a render worker).
//
// Why the codec libraries directly and not OpenImageIO: OIIO calls the same libjpeg-turbo,
// libpng and libwebp, but every write goes through ImageOutput::create (plugin lookup by
// name), an ImageSpec, its format-conversion layer and an IOProxy for in-memory output
// (an extra copy of the frame), and OIIO 2.4 does not expose libwebp's `method`, the
// setting that makes WebP usable on a hot path. Measured once on this 1024x1024 image with
// a throwaway program (OIIO 2.4.7, IOVecOutput, median of 9, shared 2-core machine):
//   OIIO jpeg q85 3.1 ms (alpha dropped, no matte) | direct 2.7-4.9 ms (alpha flattened)
//   OIIO png zlib1 SUB 11.2 ms, NONE 9.9 ms       | direct 7.4-7.7 ms, 6.3 ms
//   OIIO png defaults 33.2 ms                      | direct zlib6 SUB 13.4 ms
//   OIIO webp q80 494 ms                           | direct q80 method 0 18.4 ms
// JPEG is a tie (the direct path also flattens alpha on the matte); PNG and WebP are
// faster direct. So OIIO is not linked.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "image/image_encode.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

// Deterministic section-like frame; rows top first, straight alpha.
std::vector<std::uint8_t> sectionLikeImage(int side) {
    const std::uint8_t strata[6][3] = {{201, 167, 110}, {142, 170, 96},  {180, 96, 80},
                                       {96, 120, 176},  {160, 150, 140}, {110, 84, 60}};
    std::vector<std::uint8_t> px(std::size_t(side) * side * 4, 0);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const double u = double(x) / side, v = double(y) / side;
            // The cut face: a convex-ish blob; outside is transparent background.
            const double r = std::hypot(u - 0.5, (v - 0.5) * 1.3);
            if (r > 0.46 + 0.03 * std::sin(9.0 * u)) continue;
            const double depth = v + 0.06 * std::sin(7.0 * u) + 0.03 * std::sin(23.0 * u + 1.0);
            int layer = std::clamp(int(depth * 6.0), 0, 5);
            // A normal fault: strata offset on one side of a dipping line.
            const double fault = u - 0.62 - 0.25 * (v - 0.5);
            if (fault > 0) layer = std::clamp(int((depth + 0.07) * 6.0), 0, 5);
            const double shade = 0.85 + 0.15 * (1.0 - v);
            std::uint8_t* p = &px[(std::size_t(y) * side + x) * 4];
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(strata[layer][c] * shade));
            p[3] = 255;
            if (std::abs(fault) * side < 1.5) p[0] = p[1] = p[2] = 30;  // the fault trace
        }
    return px;
}

}  // namespace

int main(int argc, char** argv) {
    int side = 1024, reps = 15;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            side = std::atoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--reps"))
            reps = std::atoi(argv[i + 1]);
    }
    if (side <= 0 || side > 8192 || reps <= 0) {
        std::fprintf(stderr, "bench_encode: --size must be 1..8192 and --reps positive\n");
        return 2;
    }
    const std::vector<std::uint8_t> img = sectionLikeImage(side);

    struct Case {
        const char* name;
        ImageFormat format;
        EncodeOptions options;
    };
    std::vector<Case> cases;
    auto add = [&](const char* name, ImageFormat f, auto tweak) {
        EncodeOptions o;
        tweak(o);
        cases.push_back({name, f, o});
    };
    add("jpeg q85", ImageFormat::Jpeg, [](EncodeOptions&) {});
    add("jpeg q75", ImageFormat::Jpeg, [](EncodeOptions& o) { o.jpegQuality = 75; });
    add("jpeg q95", ImageFormat::Jpeg, [](EncodeOptions& o) { o.jpegQuality = 95; });
    add("png zlib1 sub", ImageFormat::Png, [](EncodeOptions&) {});
    add("png zlib1 none", ImageFormat::Png, [](EncodeOptions& o) { o.pngFilter = PngFilter::None; });
    add("png zlib2 sub", ImageFormat::Png, [](EncodeOptions& o) { o.pngLevel = 2; });
    add("png zlib6 sub", ImageFormat::Png, [](EncodeOptions& o) { o.pngLevel = 6; });
    add("png zlib1 sub rgb", ImageFormat::Png, [](EncodeOptions& o) { o.keepAlpha = false; });
    add("webp q80 m0", ImageFormat::Webp, [](EncodeOptions&) {});
    add("webp q80 m2", ImageFormat::Webp, [](EncodeOptions& o) { o.webpMethod = 2; });
    add("webp q80 m4", ImageFormat::Webp, [](EncodeOptions& o) { o.webpMethod = 4; });
    add("webp lossless m0", ImageFormat::Webp, [](EncodeOptions& o) { o.webpLossless = true; });

    json results = json::array();
    for (const Case& c : cases) {
        std::vector<double> wall;
        std::size_t bytes = 0;
        for (int r = 0; r < reps + 1; ++r) {
            const double t0 = bench::nowSeconds();
            auto out = encodeImage(img, side, side, c.format, c.options);
            const double ms = (bench::nowSeconds() - t0) * 1000.0;
            if (!out) {
                std::fprintf(stderr, "bench_encode: %s: %s\n", c.name, out.error().message.c_str());
                return 1;
            }
            bytes = out->size();
            if (r > 0) wall.push_back(ms);  // the first call warms caches and allocators
        }
        results.push_back({{"format", extension(c.format)},
                           {"setting", c.name},
                           {"median_ms", bench::median(wall)},
                           {"min_ms", *std::min_element(wall.begin(), wall.end())},
                           {"bytes", bytes}});
    }
    // Cancel latency: encode on a thread, cancel at a fraction of the median encode.
    json cancels = json::array();
    for (const Case& c : cases) {
        const std::string name = c.name;
        if (name != "jpeg q85" && name != "png zlib1 sub" && name != "webp q80 m0") continue;
        double medianMs = 0.0;
        for (const json& r : results)
            if (r["setting"] == name) medianMs = r["median_ms"].get<double>();
        for (const double fraction : {0.05, 0.25, 0.5}) {
            std::vector<double> after;
            int cancelledRuns = 0;
            for (int r = 0; r < reps; ++r) {
                std::atomic<bool> cancel{false};
                EncodeOptions o = c.options;
                o.cancel = &cancel;
                bool cancelled = false;
                double returnedAt = 0.0;
                std::thread worker([&] {
                    auto out = encodeImage(img, side, side, c.format, o);
                    returnedAt = bench::nowSeconds();
                    cancelled = !out && out.error().code == ErrorCode::DeadlineExceeded;
                });
                std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(medianMs * fraction));
                const double setAt = bench::nowSeconds();
                cancel.store(true);
                worker.join();
                after.push_back(std::max(0.0, (returnedAt - setAt) * 1000.0));
                cancelledRuns += cancelled ? 1 : 0;
            }
            cancels.push_back({{"format", extension(c.format)},
                               {"setting", name},
                               {"cancelled_at_fraction", fraction},
                               {"runs_cancelled", cancelledRuns},
                               {"runs", reps},
                               {"return_after_cancel_median_ms", bench::median(after)},
                               {"return_after_cancel_max_ms", *std::max_element(after.begin(), after.end())}});
        }
    }
    json doc = {{"bench", "encode"},
                {"width", side},
                {"height", side},
                {"reps", reps},
                {"image", "section-like RGBA8: 6 strata, fault, trace line, transparent background"},
                {"results", results},
                {"cancel", cancels}};
    std::printf("%s\n", doc.dump(2).c_str());
    return 0;
}
