// libFuzzer target for the block-model CSV reader (model/blocks/block_model.hpp): any bytes must give
// a block model or an error naming the line, never a crash, a hang or a huge allocation (the
// lattice is capped at kMaxBlockCells before any grid is allocated). A model it gives must
// answer cellAt at its own cell centres with those cells.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "model/blocks/block_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 65536) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto b = geoslice::blockModelFromCsv(text, "fuzz.csv");
    if (!b.ok()) return 0;
    const std::size_t n = b->cellCount();
    for (std::size_t c = 0; c < n && c < 64; ++c) {
        const auto ijk = b->ijk(c);
        const glm::dvec3 g{(double(ijk[0]) + 0.5) * b->size[0], (double(ijk[1]) + 0.5) * b->size[1],
                           (double(ijk[2]) + 0.5) * b->size[2]};
        if (b->cellAt(b->toWorld(g)) != c) __builtin_trap();
    }
    return 0;
}
