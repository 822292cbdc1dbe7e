#include "image/image_io.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "image/image_encode.hpp"

namespace geoslice {

Status writePngRgba(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height) {
    if (rgba.size() != std::size_t(width) * std::size_t(height) * 4)
        return makeError(ErrorCode::InvalidArgument,
                         path + ": RGBA buffer does not match " + std::to_string(width) + "x" + std::to_string(height));
    auto png = encodeImage(rgba, width, height, ImageFormat::Png);  // the one PNG writer (libpng)
    if (!png) return makeError(png.error().code, path + ": " + png.error().message);
    return writeFile(path, png.value());
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
