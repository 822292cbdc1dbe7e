// libFuzzer target for the request parsers of api/request.hpp, on what a client sends as a
// whole: the first byte picks the parser, the rest is its input —
//   0: a POST /query body (parseQueryBatch, then parseBatchPixels and the view's plan),
//   1: a POST /sections body (parseSectionBody, then the section definition),
//   2: a tile address "z/x/y" (parseTileAddress), 3: a Content-Type value (mediaType).
// Any input gives a value or an error, never a crash. Invariants checked: a batch never
// holds more than kMaxBatchPixels pixels and its pixels are exactly the body's; a parsed
// tile address is in range; a media type is lower case with no parameters.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/plan.hpp"
#include "api/request.hpp"
#include "model/crs/crs.hpp"
#include "view/view_limits.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice;
    if (size == 0) return 0;
    static const Crs crs = Crs::fromEpsg(4523).value();
    const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
    switch (data[0] % 4) {
        case 0: {
            auto batch = api::parseQueryBatch(text, api::viewParamNames());
            if (!batch) break;
            if (!batch.value().pixels.is_array() || batch.value().pixels.size() > kMaxBatchPixels) __builtin_trap();
            auto pixels = api::parseBatchPixels(batch.value().pixels);
            if (pixels && pixels.value().size() != batch.value().pixels.size()) __builtin_trap();
            (void)api::parseViewPlan(batch.value().view, "m", crs);
            break;
        }
        case 1: {
            auto params = api::parseSectionBody(text);
            if (params) (void)api::parseSectionDef(params.value(), "m", crs);
            break;
        }
        case 2: {
            const std::size_t a = text.find('/'), b = a == std::string_view::npos ? a : text.find('/', a + 1);
            if (b == std::string_view::npos) break;
            auto t = api::parseTileAddress(text.substr(0, a), text.substr(a + 1, b - a - 1), text.substr(b + 1));
            if (t && (t.value().z < 0 || t.value().z > 30)) __builtin_trap();
            break;
        }
        default: {
            const std::string type = api::mediaType(text);
            if (type.find(';') != std::string::npos) __builtin_trap();
            for (char c : type)
                if (c >= 'A' && c <= 'Z') __builtin_trap();
            (void)api::isJsonMediaType(type);
        }
    }
    return 0;
}
