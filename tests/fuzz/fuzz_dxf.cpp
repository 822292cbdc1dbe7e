// libFuzzer target for the DXF reader: any bytes must give a model or an error, never a
// crash, a hang or an unbounded allocation.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/io/loaders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto model = geoslice::parseDxf(bytes, "fuzz.dxf");
    if (model.ok()) {
        // Touch the result so that a bad index or size shows up here, under ASan.
        for (const auto* list : {&model->bodies, &model->surfaces})
            for (const auto& part : *list)
                for (std::uint32_t i : part.mesh.indices)
                    if (i >= part.mesh.positions.size()) __builtin_trap();
        for (const auto& line : model->lines)
            for (std::uint32_t i : line.segments)
                if (i >= line.points.size()) __builtin_trap();
    }
    return 0;
}
