// libFuzzer target for the request parsers: the bytes are a query string ("k=v&k=v...",
// as the HTTP layer hands it over after percent-decoding). Any input gives a plan or an
// error naming the parameter, never a crash. Invariant checked: a parsed section
// definition survives its stateless id (encode -> decode) with the same canonical text.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "api/params.hpp"
#include "api/plan.hpp"
#include "model/crs/crs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice;
    static const Crs crs = Crs::fromEpsg(4523).value();
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    api::Params params;
    std::string_view rest = text;
    while (!rest.empty()) {
        const std::size_t amp = rest.find('&');
        const std::string_view item = rest.substr(0, amp);
        const std::size_t eq = item.find('=');
        if (eq != std::string_view::npos) params[std::string(item.substr(0, eq))] = std::string(item.substr(eq + 1));
        if (amp == std::string_view::npos) break;
        rest.remove_prefix(amp + 1);
    }
    auto plan = api::parseViewPlan(params, "m", crs);
    if (plan) {
        const std::string canonical = plan.value().section.canonical();
        auto back =
            api::decodeSectionId(api::encodeSectionId(plan.value().section), [](const std::string&) { return &crs; });
        if (!back || back.value().canonical() != canonical) __builtin_trap();
    }
    (void)api::base64UrlDecode(text);
    (void)api::decodeSectionId(text, [](const std::string&) { return &crs; });
    return 0;
}
