// libFuzzer target for the glTF 2.0 / GLB loader (geoslice's container and JSON checks,
// tinygltf, libdraco for KHR_draco_mesh_compression): any bytes must give a model or an
// error that starts with the input's name, never a crash, a hang or an unbounded
// allocation. There is no model folder, so every external buffer must be refused.
// Seeds: tests/fuzz/corpus/gltf; binary ones are named *.glb.seed because .gitignore drops *.glb.
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/io/loaders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string kSource = "fuzz.glb";
    auto model = geoslice::parseGltf(data, size, kSource, /*baseDir=*/"");
    if (model.ok()) {
        // Touch the result so that a bad index or size shows up here, under ASan.
        for (const auto* list : {&model->bodies, &model->surfaces})
            for (const auto& part : *list) {
                if (part.mesh.indices.size() % 3 != 0) __builtin_trap();
                for (std::uint32_t i : part.mesh.indices)
                    if (i >= part.mesh.positions.size()) __builtin_trap();
            }
    } else if (model.error().message.compare(0, kSource.size() + 2, kSource + ": ") != 0) {
        __builtin_trap();  // every error names the input first
    }
    return 0;
}
