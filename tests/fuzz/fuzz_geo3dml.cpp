// libFuzzer target for the Geo3DML (XML) loader: any bytes must give a model or an error,
// never a crash, a hang or an unbounded allocation.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/io/loaders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view text(reinterpret_cast<const char*>(data), size);
    auto model = geoslice::parseGeo3dml(text, "fuzz.xml");
    if (model.ok()) {
        // Touch the result so that a bad index or size shows up here, under ASan, and check
        // the contracts callers rely on: indices in range, finite coordinates, and text that
        // serialises to JSON (which throws on invalid UTF-8).
        for (const auto* list : {&model->bodies, &model->surfaces})
            for (const auto& part : *list) {
                if (part.mesh.indices.empty() || part.mesh.indices.size() % 3 != 0) __builtin_trap();
                for (std::uint32_t i : part.mesh.indices)
                    if (i >= part.mesh.positions.size()) __builtin_trap();
                for (const auto& p : part.mesh.positions)
                    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
                if (!model->attributes.find(part.record)) __builtin_trap();
            }
        try {
            (void)model->attributes.toJson().dump();
            (void)nlohmann::json(model->name).dump();
        } catch (...) {
            __builtin_trap();
        }
    } else {
        try {
            (void)nlohmann::json(model.error().message).dump();
        } catch (...) {
            __builtin_trap();
        }
    }
    return 0;
}
