// GOCAD reading: the binary sample files of voxets and grids (path beside the header file,
// element type and size, byte order, offset, no-data value), checked against the file size
// before anything is read. Part of what the GOCAD readers share (model/io/gocad/gocad_reader.hpp).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

Result<std::string> dataFilePath(const Context& cx, std::string_view name, std::size_t line) {
    std::string file(unquote(trim(name)));
    if (file.empty()) return cx.lines.failAt(line, "the data file name is empty");
    if (cx.baseDir.empty())
        return cx.lines.failAt(line,
                               "data file " + quoteToken(file) +
                                   " cannot be read: the input is not a file on disk (load the header file by path)",
                               ErrorCode::Unsupported);
    std::filesystem::path p(file);
    if (p.is_relative()) p = std::filesystem::path(cx.baseDir) / p;
    return p.string();
}

Result<std::vector<float>> readSampleFile(const std::string& path, const SampleFormat& format, std::size_t count,
                                          std::optional<double> noData, const std::string& what) {
    const std::size_t es = format.esize;
    const bool isFloat = format.etype == "IEEE";
    if (!((isFloat && (es == 4 || es == 8)) ||
          ((format.etype == "SIGNED_INT" || format.etype == "UNSIGNED_INT") && (es == 1 || es == 2 || es == 4))))
        return makeError(ErrorCode::Unsupported, what + ": element type " + format.etype + " of " + std::to_string(es) +
                                                     " bytes is not supported (IEEE 4 or 8, SIGNED_INT or "
                                                     "UNSIGNED_INT 1, 2 or 4)");
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return makeError(ErrorCode::NotFound, what + ": cannot read " + path + " (" + ec.message() + ")");
    if (count > (std::numeric_limits<std::uint64_t>::max() - format.offset) / es)
        return makeError(ErrorCode::ParseError, what + ": " + std::to_string(count) + " samples is too many");
    const std::uint64_t need = format.offset + static_cast<std::uint64_t>(count) * es;
    if (size < need)
        return makeError(ErrorCode::ParseError, what + ": " + path + " has " + std::to_string(size) +
                                                    " bytes, the header needs " + std::to_string(need) + " (" +
                                                    std::to_string(count) + " samples of " + std::to_string(es) +
                                                    " bytes from offset " + std::to_string(format.offset) +
                                                    "): truncated file or wrong AXIS_N / PROP_ESIZE?");
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorCode::IoError, what + ": cannot open " + path);
    in.seekg(static_cast<std::streamoff>(format.offset));
    std::vector<float> out(count);
    std::vector<unsigned char> buf(std::size_t(1) << 16);
    std::size_t done = 0;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    while (done < count) {
        const std::size_t n = std::min(count - done, buf.size() / es);
        if (!in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(n * es)))
            return makeError(ErrorCode::IoError, what + ": read failed in " + path);
        for (std::size_t i = 0; i < n; ++i) {
            unsigned char b[8];
            std::memcpy(b, buf.data() + i * es, es);
            if (format.littleEndian != (std::endian::native == std::endian::little)) std::reverse(b, b + es);
            double v = 0.0;
            if (isFloat && es == 4) {
                float f;
                std::memcpy(&f, b, 4);
                v = f;
            } else if (isFloat) {
                std::memcpy(&v, b, 8);
            } else if (format.etype == "SIGNED_INT") {
                if (es == 1) v = static_cast<std::int8_t>(b[0]);
                if (es == 2) {
                    std::int16_t x;
                    std::memcpy(&x, b, 2);
                    v = x;
                }
                if (es == 4) {
                    std::int32_t x;
                    std::memcpy(&x, b, 4);
                    v = x;
                }
            } else {
                if (es == 1) v = b[0];
                if (es == 2) {
                    std::uint16_t x;
                    std::memcpy(&x, b, 2);
                    v = x;
                }
                if (es == 4) {
                    std::uint32_t x;
                    std::memcpy(&x, b, 4);
                    v = x;
                }
            }
            if ((noData && v == *noData) || !std::isfinite(v) || std::fabs(v) > std::numeric_limits<float>::max())
                out[done + i] = nan;
            else
                out[done + i] = static_cast<float>(v);
        }
        done += n;
    }
    return out;
}

}  // namespace geoslice::gocad
