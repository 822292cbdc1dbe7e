#include "renderer/image_io.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

// Debian's header, compiled once here (model/ builds tinygltf without stb_image_write).
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wcast-align"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace geoslice {

Status writePngRgba(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height) {
    if (rgba.size() != std::size_t(width) * std::size_t(height) * 4)
        return makeError(ErrorCode::InvalidArgument,
                         path + ": RGBA buffer does not match " + std::to_string(width) + "x" + std::to_string(height));
    stbi_write_png_compression_level = 1;
    if (!stbi_write_png(path.c_str(), width, height, 4, rgba.data(), width * 4))
        return makeError(ErrorCode::IoError, "cannot write PNG " + path);
    return {};
}

Status writeIdsPgm16(const std::string& path, const std::vector<RecordId>& ids, int width, int height) {
    if (ids.size() != std::size_t(width) * std::size_t(height))
        return makeError(ErrorCode::InvalidArgument, path + ": ID buffer does not match the size");
    std::vector<unsigned char> data(ids.size() * 2);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] > 0xffff)
            return makeError(ErrorCode::OutOfRange,
                             path + ": record id " + std::to_string(ids[i]) + " does not fit a 16-bit PGM");
        data[2 * i] = static_cast<unsigned char>(ids[i] >> 8);
        data[2 * i + 1] = static_cast<unsigned char>(ids[i] & 0xff);
    }
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + ": " + std::strerror(errno));
    std::fprintf(f, "P5\n%d %d\n65535\n", width, height);
    const bool ok = std::fwrite(data.data(), 1, data.size(), f) == data.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

}  // namespace geoslice
