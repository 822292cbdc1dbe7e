// libFuzzer target for the Surpac string and DTM reader (the input is split at the first
// line "@@" into a .dtm and its .str; without one, it is a string file): any bytes must give a model or an error, never
// a crash, a hang or an unbounded allocation.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/io/loaders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::size_t cut = bytes.find("\n@@\n");
    auto model = cut == std::string_view::npos
                     ? geoslice::parseSurpacString(bytes, "fuzz.str")
                     : geoslice::parseSurpacDtm(bytes.substr(0, cut), "fuzz.dtm", bytes.substr(cut + 4), "fuzz.str");
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
