// Writing rendered images and ID buffers to files: RGBA as PNG through the one PNG encoder
// (image/image_encode.hpp, libpng, alpha kept), record ids as 16-bit binary PGM. Rows top
// first. Any thread.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "model/attributes.hpp"
#include "model/result.hpp"

namespace geoslice {

Status writePngRgba(const std::string& path, const std::vector<std::uint8_t>& rgba, int width, int height);
// Record ids as a 16-bit PGM (big-endian samples, maxval 65535); OutOfRange when an id
// does not fit in 16 bits.
Status writeIdsPgm16(const std::string& path, const std::vector<RecordId>& ids, int width, int height);

}  // namespace geoslice
