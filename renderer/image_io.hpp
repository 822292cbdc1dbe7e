// Writing rendered images to files (a stop-gap until the fast JPEG/PNG/WebP encoders of
// issue 3 section 5 exist): PNG through stb_image_write at zlib level 1, and ID buffers
// as 16-bit binary PGM. Rows top first. Any thread.
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
