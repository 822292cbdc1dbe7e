// VTK XML UnstructuredGrid (.vtu) reading: DataArray decoding. The VTK scalar types, ascii
// values, binary (base64) and appended (raw or base64) payloads with their UInt32 / UInt64
// size headers, vtkZLibDataCompressor blocks checked against the sizes their header
// declares, and byte order. Part of the reader in model/io/vtu/vtu_reader.hpp.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <zlib.h>

#include "model/io/vtu/vtu_reader.hpp"

namespace geoslice::vtu {
namespace {

std::optional<Scalar> scalarFromName(std::string_view s) {
    static const std::pair<std::string_view, Scalar> kNames[] = {
        {"Int8", Scalar::Int8},       {"UInt8", Scalar::UInt8},   {"Int16", Scalar::Int16},
        {"UInt16", Scalar::UInt16},   {"Int32", Scalar::Int32},   {"UInt32", Scalar::UInt32},
        {"Int64", Scalar::Int64},     {"UInt64", Scalar::UInt64}, {"Float32", Scalar::Float32},
        {"Float64", Scalar::Float64}, {"Char", Scalar::Int8},     {"UChar", Scalar::UInt8},
        {"Int", Scalar::Int32},       {"Float", Scalar::Float32}, {"Double", Scalar::Float64},
    };
    for (const auto& [name, type] : kNames)
        if (name == s) return type;
    return std::nullopt;
}

std::size_t scalarSize(Scalar t) {
    switch (t) {
        case Scalar::Int8:
        case Scalar::UInt8:
            return 1;
        case Scalar::Int16:
        case Scalar::UInt16:
            return 2;
        case Scalar::Int32:
        case Scalar::UInt32:
        case Scalar::Float32:
            return 4;
        case Scalar::Int64:
        case Scalar::UInt64:
        case Scalar::Float64:
            return 8;
    }
    return 0;
}

// Bytes in, either raw or base64 text (whitespace skipped; '=' padding ends a 4-character
// group, after which another group may start: VTK encodes a header and its data as two
// base64 streams). Reads never pass the end of the given text.
class ByteSource {
public:
    ByteSource(std::string_view text, bool base64) : text_(text), base64_(base64) {}

    // Upper bound of the bytes still available (exact for raw data).
    std::uint64_t available() const {
        const std::uint64_t rest = text_.size() - pos_;
        return base64_ ? rest / 4 * 3 + 3 + pending_.size() - pendingPos_ : rest;
    }

    // Appends n bytes to out; false when the input ends first or holds a bad character.
    bool take(std::uint64_t n, std::vector<std::uint8_t>& out) {
        if (n > available()) return false;
        const std::size_t start = out.size();
        out.resize(start + static_cast<std::size_t>(n));
        return take(out.data() + start, static_cast<std::size_t>(n));
    }
    bool take(std::uint8_t* dst, std::size_t n) {
        if (n == 0) return true;  // dst may be null (an empty array)
        if (!base64_) {
            if (n > text_.size() - pos_) return false;
            std::memcpy(dst, text_.data() + pos_, n);
            pos_ += n;
            return true;
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (pendingPos_ == pending_.size() && !decodeGroup()) return false;
            dst[i] = pending_[pendingPos_++];
        }
        return true;
    }
    std::string_view error() const { return error_; }

private:
    static int sextet(char c) {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    }
    // Decodes the next 4-character group into pending_.
    bool decodeGroup() {
        int v[4];
        int got = 0, pad = 0;
        while (got < 4) {
            if (pos_ >= text_.size()) {
                error_ = "base64 data ends in the middle of the array";
                return false;
            }
            const char c = text_[pos_++];
            if (isSpace(c)) continue;
            if (c == '=') {
                if (got < 2) {
                    error_ = "misplaced '=' in base64 data";
                    return false;
                }
                v[got++] = 0;
                ++pad;
                continue;
            }
            const int s = sextet(c);
            if (s < 0 || pad > 0) {
                error_ = "character '" + printable(std::string_view(&c, 1)) + "' is not base64";
                return false;
            }
            v[got++] = s;
        }
        const std::uint32_t bits = (std::uint32_t(v[0]) << 18) | (std::uint32_t(v[1]) << 12) |
                                   (std::uint32_t(v[2]) << 6) | std::uint32_t(v[3]);
        pending_.clear();
        pendingPos_ = 0;
        pending_.push_back(static_cast<std::uint8_t>(bits >> 16));
        if (pad < 2) pending_.push_back(static_cast<std::uint8_t>(bits >> 8));
        if (pad < 1) pending_.push_back(static_cast<std::uint8_t>(bits));
        return true;
    }

    std::string_view text_;
    bool base64_;
    std::size_t pos_ = 0;
    std::vector<std::uint8_t> pending_;
    std::size_t pendingPos_ = 0;
    std::string error_;
};

template <class T>
T convertScalar(const std::uint8_t* p, Scalar type, bool swap) {
    std::uint8_t b[8];
    const std::size_t n = scalarSize(type);
    std::memcpy(b, p, n);
    if (swap) std::reverse(b, b + n);
    auto as = [&](auto v) {
        std::memcpy(&v, b, sizeof v);
        return static_cast<T>(v);
    };
    switch (type) {
        case Scalar::Int8:
            return as(std::int8_t{});
        case Scalar::UInt8:
            return as(std::uint8_t{});
        case Scalar::Int16:
            return as(std::int16_t{});
        case Scalar::UInt16:
            return as(std::uint16_t{});
        case Scalar::Int32:
            return as(std::int32_t{});
        case Scalar::UInt32:
            return as(std::uint32_t{});
        case Scalar::Int64:
            return as(std::int64_t{});
        case Scalar::UInt64: {
            std::uint64_t v;
            std::memcpy(&v, b, 8);
            if constexpr (std::is_integral_v<T>)
                return v > std::uint64_t(std::numeric_limits<std::int64_t>::max()) ? T(-1) : static_cast<T>(v);
            else
                return static_cast<T>(v);
        }
        case Scalar::Float32:
            return as(float{});
        case Scalar::Float64:
            return as(double{});
    }
    return T{};
}

}  // namespace

Result<ArrayDecl> VtuReader::declare(pugi::xml_node node, std::string_view role, bool strings) const {
    ArrayDecl a;
    a.node = node;
    // Names go into part names and JSON: invalid UTF-8 becomes U+FFFD.
    a.name = text::toUtf8(node.attribute("Name") ? std::string_view(node.attribute("Name").value()) : role);
    const char* type = node.attribute("type").value();
    // A String array's payload is its characters' bytes.
    auto t =
        strings && std::string_view(type) == "String" ? std::optional<Scalar>(Scalar::UInt8) : scalarFromName(type);
    if (!t)
        return failArray(a, "type '" + printable(type) + "' is not a VTK scalar type (Int8..UInt64, Float32, Float64)");
    a.type = *t;
    if (pugi::xml_attribute nc = node.attribute("NumberOfComponents")) {
        std::uint64_t n = 0;
        if (text::parseUnsigned(trimSpace(nc.value()), n) != text::IntStatus::Ok || n == 0 || n > 64)
            return failArray(a, "NumberOfComponents '" + printable(nc.value()) + "' is not a number from 1 to 64");
        a.components = static_cast<std::size_t>(n);
    }
    const std::string_view format = node.attribute("format").value();
    if (format == "ascii") {
        a.format = ArrayDecl::Format::Ascii;
    } else if (format == "binary") {
        a.format = ArrayDecl::Format::Binary;
    } else if (format == "appended") {
        a.format = ArrayDecl::Format::Appended;
        if (!haveAppended_) return failArray(a, "format is appended but the file has no <AppendedData>");
        std::string_view s = trimSpace(node.attribute("offset").value());
        if (text::parseUnsigned(s, a.offset) != text::IntStatus::Ok)
            return failArray(a, "appended array without a valid offset ('" + printable(s) + "')");
        if (a.offset >= appended_.size())
            return failArray(a, "offset " + std::to_string(a.offset) + " is past the end of the appended data (" +
                                    std::to_string(appended_.size()) + " bytes)");
    } else {
        return failArray(a, "format '" + printable(format) + "' is not ascii, binary or appended");
    }
    return a;
}

Status VtuReader::payload(const ArrayDecl& a, std::uint64_t bytes, std::vector<std::uint8_t>& out) const {
    std::string_view text;
    bool base64 = true;
    std::string inlineText;
    if (a.format == ArrayDecl::Format::Binary) {
        text = a.node.child_value();
    } else {
        text = appended_.substr(static_cast<std::size_t>(a.offset));
        base64 = appendedBase64_;
    }
    ByteSource src(text, base64);
    const std::size_t hsize = header64_ ? 8 : 4;
    auto readHeader = [&](std::uint64_t& v) {
        std::uint8_t b[8];
        if (!src.take(b, hsize)) return false;
        if (bigEndian_ != (std::endian::native == std::endian::big)) std::reverse(b, b + hsize);
        if (hsize == 8) {
            std::memcpy(&v, b, 8);
        } else {
            std::uint32_t v32;
            std::memcpy(&v32, b, 4);
            v = v32;
        }
        return true;
    };
    auto truncated = [&](const std::string& what) {
        return failArray(
            a, what + (src.error().empty() ? std::string(" (data truncated)") : ": " + std::string(src.error())));
    };

    if (!zlib_) {
        std::uint64_t declared = 0;
        if (!readHeader(declared)) return truncated("no size header");
        if (bytes == kLengthFromHeader) bytes = declared;
        if (declared != bytes)
            return failArray(a, "its header says " + std::to_string(declared) + " bytes, the declared counts need " +
                                    std::to_string(bytes));
        if (bytes > src.available())
            return failArray(a, std::to_string(bytes) + " bytes of data declared, at most " +
                                    std::to_string(src.available()) + " present");
        out.clear();
        if (!src.take(bytes, out)) return truncated("data shorter than declared");
        return {};
    }

    // vtkZLibDataCompressor: [blocks][block size][last block size][compressed size]*blocks,
    // then the blocks, each a zlib stream of block size bytes (the last: last block size,
    // or block size when that is 0).
    std::uint64_t blocks = 0, blockSize = 0, lastSize = 0;
    if (!readHeader(blocks) || !readHeader(blockSize) || !readHeader(lastSize))
        return truncated("incomplete compression header");
    auto headerBytes = mulChecked(blocks, hsize);
    if (!headerBytes || *headerBytes > src.available())
        return failArray(a,
                         "compression header declares " + std::to_string(blocks) + " blocks, more than the data holds");
    std::vector<std::uint64_t> csize(static_cast<std::size_t>(blocks));
    std::uint64_t ctotal = 0;
    for (auto& c : csize) {
        if (!readHeader(c)) return truncated("incomplete compression header");
        ctotal += c;  // each c <= available (checked below), so no overflow in practice
        if (c > src.available() || ctotal > src.available())
            return failArray(a, "compressed blocks of " + std::to_string(ctotal) + " bytes declared, at most " +
                                    std::to_string(src.available()) + " present");
    }
    if (blocks > 0 && (blockSize == 0 || lastSize > blockSize))
        return failArray(a, "compression header has block size " + std::to_string(blockSize) + " and last block size " +
                                std::to_string(lastSize));
    std::uint64_t total = 0;
    if (blocks > 0) {
        auto full = mulChecked(blocks - 1, blockSize);
        if (!full) return failArray(a, "compression header sizes overflow");
        total = *full + (lastSize ? lastSize : blockSize);
        if (total < *full) return failArray(a, "compression header sizes overflow");
    }
    if (bytes == kLengthFromHeader) bytes = total;
    if (total != bytes)
        return failArray(a, "compressed data holds " + std::to_string(total) + " bytes, the declared counts need " +
                                std::to_string(bytes));
    if (total > ctotal * kMaxZlibRatio + 1024)
        return failArray(a, std::to_string(total) + " bytes cannot come from " + std::to_string(ctotal) +
                                " compressed bytes (zlib compresses at most ~1032:1)");
    out.assign(static_cast<std::size_t>(total), 0);
    std::vector<std::uint8_t> block;
    std::uint64_t at = 0;
    for (std::size_t b = 0; b < csize.size(); ++b) {
        const std::uint64_t want = (b + 1 == csize.size() && lastSize) ? lastSize : blockSize;
        block.clear();
        if (!src.take(csize[b], block)) return truncated("block " + std::to_string(b) + " is shorter than declared");
        uLongf got = static_cast<uLongf>(want);
        const int rc = uncompress(out.data() + at, &got, block.data(), static_cast<uLong>(block.size()));
        if (rc != Z_OK || got != want)
            return failArray(a, "zlib block " + std::to_string(b) + " of " + std::to_string(csize.size()) +
                                    " does not decompress to " + std::to_string(want) + " bytes (" +
                                    (rc == Z_OK ? std::to_string(got) + " bytes" : std::string(zError(rc))) + ")");
        at += want;
    }
    return {};
}

template <class T>
Status VtuReader::read(const ArrayDecl& a, std::uint64_t count, std::vector<T>& out) const {
    out.clear();
    if constexpr (std::is_integral_v<T>) {
        if (!isIntegerScalar(a.type)) return failArray(a, "must have an integer type");
    }
    if (a.format == ArrayDecl::Format::Ascii) {
        const char* p = a.node.child_value();
        const char* end = p + std::strlen(p);
        // Each value takes at least two characters (digit + separator), so this bounds the
        // allocation by the text present.
        out.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(count, std::uint64_t(end - p) / 2 + 1)));
        while (true) {
            while (p < end && isSpace(*p)) ++p;
            if (p == end) break;
            const char* tokEnd = p;
            while (tokEnd < end && !isSpace(*tokEnd)) ++tokEnd;
            if (out.size() == count)
                return failArray(a, "more than the " + std::to_string(count) + " values the declared counts need");
            const std::optional<T> v = text::parseNumber<T>({p, static_cast<std::size_t>(tokEnd - p)});
            if (!v)
                return failArray(a, "value " + std::to_string(out.size() + 1) + " '" +
                                        printable({p, std::size_t(tokEnd - p)}) + "' is not " +
                                        (std::is_integral_v<T> ? "an integer" : "a number"));
            out.push_back(*v);
            p = tokEnd;
        }
        if (out.size() != count)
            return failArray(a,
                             std::to_string(out.size()) + " values, the declared counts need " + std::to_string(count));
        return {};
    }
    const std::size_t size = scalarSize(a.type);
    auto bytes = mulChecked(count, size);
    if (!bytes) return failArray(a, "declared size overflows");
    std::vector<std::uint8_t> raw;
    if (Status s = payload(a, *bytes, raw); !s) return s;
    const bool swap = bigEndian_ != (std::endian::native == std::endian::big);
    out.resize(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = convertScalar<T>(raw.data() + i * size, a.type, swap);
    return {};
}

template Status VtuReader::read<double>(const ArrayDecl&, std::uint64_t, std::vector<double>&) const;
template Status VtuReader::read<std::int64_t>(const ArrayDecl&, std::uint64_t, std::vector<std::int64_t>&) const;

}  // namespace geoslice::vtu

namespace geoslice::vtu {

Result<StringArray> VtuReader::readStrings(pugi::xml_node node, std::uint64_t count, std::string_view role) const {
    auto a = declare(node, role, /*strings=*/true);
    if (!a) return a.error();
    std::vector<std::uint8_t> bytes;
    if (a->format == ArrayDecl::Format::Ascii) {
        // Character codes, signed (VTK writes -27 for 0xE5) or not.
        const std::string_view t = node.child_value();
        std::size_t i = 0;
        while (i < t.size()) {
            while (i < t.size() && isSpace(t[i])) ++i;
            if (i >= t.size()) break;
            std::size_t j = i;
            while (j < t.size() && !isSpace(t[j])) ++j;
            std::int64_t v = 0;
            if (text::parseInt(t.substr(i, j - i), v) != text::IntStatus::Ok || v < -128 || v > 255)
                return failArray(*a,
                                 "value '" + printable(t.substr(i, j - i)) + "' is not a character code (-128..255)");
            bytes.push_back(static_cast<std::uint8_t>(v & 0xff));
            i = j;
        }
    } else if (Status s = payload(*a, kLengthFromHeader, bytes); !s) {
        return s.error();
    }
    StringArray out;
    out.name = a->name;
    std::string cur;
    for (const std::uint8_t b : bytes) {
        if (b == 0) {
            out.values.push_back(text::toUtf8(cur));
            cur.clear();
            if (count && out.values.size() == count) break;
        } else {
            cur += static_cast<char>(b);
        }
    }
    if (!cur.empty() && (!count || out.values.size() < count)) out.values.push_back(text::toUtf8(cur));
    if (count && out.values.size() != count)
        return failArray(
            *a, "holds " + std::to_string(out.values.size()) + " strings, " + std::to_string(count) + " declared");
    return out;
}

}  // namespace geoslice::vtu
