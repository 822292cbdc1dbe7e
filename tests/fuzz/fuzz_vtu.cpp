// libFuzzer target for the VTK XML UnstructuredGrid (.vtu) loader: any bytes must give a
// model or an error, never a crash, a hang or an unbounded allocation (sizes in the file
// are checked against the bytes present; zlib blocks against their declared sizes).
// Seeds (tests/fuzz/corpus/vtu): one small grid (a hexahedron, a tetrahedron, a wedge, a
// triangle; point and cell data) in every encoding of tests/common/vtu_writer.hpp.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/io/loaders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto model = geoslice::parseVtu(bytes, "fuzz.vtu");
    if (model.ok()) {
        // Contracts callers rely on: indices in range, finite coordinates, a record per
        // part, per-vertex properties sized to the vertices, text that serialises to JSON.
        for (const auto* list : {&model->bodies, &model->surfaces})
            for (const auto& part : *list) {
                if (part.mesh.indices.empty() || part.mesh.indices.size() % 3 != 0) __builtin_trap();
                for (std::uint32_t i : part.mesh.indices)
                    if (i >= part.mesh.positions.size()) __builtin_trap();
                for (const auto& p : part.mesh.positions)
                    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
                if (part.mesh.propertyValues.size() != part.mesh.positions.size() * part.mesh.propertyNames.size())
                    __builtin_trap();
                if (!model->attributes.find(part.record)) __builtin_trap();
            }
        try {
            (void)model->attributes.toJson().dump();
            for (const auto& [k, v] : model->notes) (void)nlohmann::json(v).dump();
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
