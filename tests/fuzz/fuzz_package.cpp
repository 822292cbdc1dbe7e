// libFuzzer target for the baked-package reader (bake/package.hpp: manifest, GLB, zstd index
// texture, attribute table): any bytes must give a package or an error, never a crash, a hang
// or an unbounded allocation.
//
// Input layout (so one input drives all four files): byte 0 = flags (bit 0: verify the XXH64
// checksums; off lets the fuzzer reach the structural checks), then three sections each
// prefixed by a little-endian uint32 length (manifest.json, mesh.glb, ids.r32ui.zst; a length
// past the end is clamped), and the rest is attributes.json. Seeds: corpus/package/, written
// from real packages by the layout above.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

#include "bake/package.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const bool verify = data[0] & 1;
    std::size_t at = 1;
    std::span<const std::uint8_t> sections[3];
    for (auto& s : sections) {
        std::uint32_t n = 0;
        if (size - at >= 4) {
            std::memcpy(&n, data + at, 4);
            at += 4;
        } else {
            at = size;
        }
        const std::size_t len = std::min<std::size_t>(n, size - at);
        s = std::span<const std::uint8_t>(data + at, len);
        at += len;
    }
    const std::string_view attributes(reinterpret_cast<const char*>(data + at), size - at);
    geoslice::bake::PackageReadOptions options;
    options.verifyChecksums = verify;
    const std::string_view manifest(reinterpret_cast<const char*>(sections[0].data()), sections[0].size());
    auto pkg = geoslice::bake::parsePackage(manifest, sections[1], sections[2], attributes, options, "fuzz");
    if (pkg.ok()) {
        // Touch the result so that a bad index or size shows up here, under ASan.
        if (pkg->texels.size() != std::size_t(pkg->width) * pkg->height * pkg->pages) __builtin_trap();
        for (const auto& part : pkg->parts)
            for (std::size_t i = 0; i < part.indexCount; ++i) {
                const std::uint32_t v = part.indices[i];
                if (v >= part.vertexCount) __builtin_trap();
                volatile float sink = part.positions[3 * v] + part.uvs[2 * v + 1];
                (void)sink;
                (void)pkg->fetch({part.uvs[2 * v], part.uvs[2 * v + 1]});
            }
    }
    return 0;
}
