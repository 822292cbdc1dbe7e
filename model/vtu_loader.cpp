// VTK XML UnstructuredGrid (.vtu) loader: volume cells with a formation per cell -> one
// closed body per formation (regionBoundaries in model/volume_mesh.hpp).
//
// File format: https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html (XML
// formats). What is read:
//  - <VTKFile type="UnstructuredGrid"> with byte_order LittleEndian | BigEndian, header_type
//    UInt32 (the default, also for version 0.1) | UInt64, compressor absent or
//    vtkZLibDataCompressor; every <Piece> (pieces are concatenated);
//  - DataArray format ascii | binary (base64 of header + data; the header may be encoded
//    on its own, as VTK does for compressed data) | appended (offset into <AppendedData>,
//    encoding raw | base64); types Int8..UInt64, Float32, Float64;
//  - Points (3 components), Cells connectivity / offsets (end offsets, as in every VTK XML
//    file) / types, PointData and CellData arrays;
//  - cells: tetrahedron (10), voxel (11, reordered to a hexahedron), hexahedron (12), wedge
//    (13), pyramid (14); quadratic tetra / hexahedron / wedge / pyramid (24-27) as their
//    linear corners (a warning says so); points, lines and faces (types 1-9, e.g. Gmsh's
//    boundary triangles) are skipped with a note. Polyhedra (42) and other cells are an
//    Unsupported error: they are volumes, and dropping them would change the model.
// The formation of a cell comes from a one-component cell-data array: the one named by
// VtuOptions::regionArray, else the first integer-typed one, else the first whose values
// are all whole numbers; a grid with no such array is one formation. Formation value v
// becomes the body "<array> <v>", whose record id is v when every value lies in
// [1, kMaxDirectRecordId] (so an attributes sidecar with those ids names them), else the
// rank of v among the values (a note says so). Cell arrays that are constant over a
// formation go into its record's extra fields; point arrays become per-vertex properties of
// the boundary meshes (float32).
//
// Robustness: every count, size and offset read from the file is checked against the
// bytes present before anything is allocated or read; zlib data is checked block by block
// against the sizes its header declares. Errors name the file, the array and the problem.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <zlib.h>
#include <pugixml.hpp>

#include "model/loaders.hpp"
#include "model/text_scan.hpp"
#include "model/volume_mesh.hpp"

namespace geoslice {
namespace {

// Largest formation value used directly as a record id (ids stay readable, and far from
// the 32-bit limit of RecordId).
constexpr std::int64_t kMaxDirectRecordId = 1000000000;
// zlib's deflate never compresses better than about 1032:1; a header that claims more is
// corrupt (and would make us allocate for data that is not there).
constexpr std::uint64_t kMaxZlibRatio = 1040;

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

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

bool isIntegerScalar(Scalar t) { return t != Scalar::Float32 && t != Scalar::Float64; }

using text::isSpace;
using text::printable;
using text::trimSpace;

// Checked a * b for sizes.
std::optional<std::uint64_t> mulChecked(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::nullopt;
    return a * b;
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

// One DataArray element, as declared.
struct ArrayDecl {
    pugi::xml_node node;
    std::string name;  // Name attribute, or the role ("Points") when it has none
    Scalar type = Scalar::Float64;
    std::size_t components = 1;
    enum class Format { Ascii, Binary, Appended } format = Format::Ascii;
    std::uint64_t offset = 0;  // appended only
};

// A decoded array: values as double (exact for every integer below 2^53) or int64.
struct CellArray {
    std::string name;
    bool integerType = false;
    std::size_t components = 1;
    std::vector<double> values;
};

class VtuReader {
public:
    VtuReader(std::string_view bytes, const std::string& source, const VtuOptions& options)
        : bytes_(bytes), source_(source), options_(options) {}
    Result<Model> run();

private:
    Error fail(const std::string& what, ErrorCode code = ErrorCode::ParseError) const {
        return makeError(code, source_ + ": " + what);
    }
    Error failArray(const ArrayDecl& a, const std::string& what) const {
        return fail("array '" + printable(a.name) + "' (" + where(a.node) + "): " + what);
    }
    std::string where(pugi::xml_node n) const;

    Result<ArrayDecl> declare(pugi::xml_node node, std::string_view role) const;
    // Decodes `count` values of the array (components included) as T (double or int64).
    template <class T>
    Status read(const ArrayDecl& a, std::uint64_t count, std::vector<T>& out) const;
    // The array's payload bytes (binary / appended), exactly `bytes` long after any
    // decompression, in file byte order.
    Status payload(const ArrayDecl& a, std::uint64_t bytes, std::vector<std::uint8_t>& out) const;
    Status readPiece(pugi::xml_node piece);

    std::string_view bytes_;
    const std::string& source_;
    const VtuOptions& options_;
    std::string xmlText_;           // the XML part (the file, or its part before raw appended data)
    std::size_t xmlDocOffset_ = 0;  // byte offset of xmlText_ in the file (always 0)
    bool bigEndian_ = false;
    bool header64_ = false;
    bool zlib_ = false;
    std::string_view appended_;  // after the '_' marker
    bool appendedBase64_ = false;
    bool haveAppended_ = false;

    // Accumulated over pieces.
    std::vector<glm::dvec3> points_;
    std::vector<std::int64_t> connectivity_;
    std::vector<std::int64_t> offsets_;  // end offsets, global into connectivity_
    std::vector<std::uint8_t> types_;
    std::vector<CellArray> cellArrays_;
    std::vector<CellArray> pointArrays_;
    std::size_t pieces_ = 0;
};

std::string VtuReader::where(pugi::xml_node n) const {
    const std::ptrdiff_t off = n.offset_debug();
    return off >= 0 ? "byte " + std::to_string(static_cast<std::size_t>(off) + xmlDocOffset_) : std::string("?");
}

Result<ArrayDecl> VtuReader::declare(pugi::xml_node node, std::string_view role) const {
    ArrayDecl a;
    a.node = node;
    // Names go into part names and JSON: invalid UTF-8 becomes U+FFFD.
    a.name = text::toUtf8(node.attribute("Name") ? std::string_view(node.attribute("Name").value()) : role);
    const char* type = node.attribute("type").value();
    auto t = scalarFromName(type);
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

Status VtuReader::readPiece(pugi::xml_node piece) {
    auto count = [&](const char* attr, std::uint64_t& n) -> Status {
        std::string_view s = trimSpace(piece.attribute(attr).value());
        if (text::parseUnsigned(s, n) != text::IntStatus::Ok)
            return fail("<Piece> (" + where(piece) + ") " + attr + " '" + printable(s) + "' is not a count");
        return {};
    };
    std::uint64_t nPoints = 0, nCells = 0;
    if (Status s = count("NumberOfPoints", nPoints); !s) return s;
    if (Status s = count("NumberOfCells", nCells); !s) return s;
    // Every point and cell takes at least one byte of the file (compressed data: 1/1040 of
    // one): larger counts are corrupt, and must not size an allocation.
    const std::uint64_t bound = std::uint64_t(bytes_.size()) * kMaxZlibRatio + 1024;
    if (nPoints > bound || nCells > bound || points_.size() + nPoints > std::numeric_limits<std::uint32_t>::max())
        return fail("<Piece> (" + where(piece) + ") declares " + std::to_string(nPoints) + " points and " +
                    std::to_string(nCells) + " cells, more than a file of " + std::to_string(bytes_.size()) +
                    " bytes can hold");

    const std::size_t base = points_.size();
    // Points.
    if (nPoints > 0) {
        pugi::xml_node pa = piece.child("Points").child("DataArray");
        if (!pa)
            return fail("<Piece> (" + where(piece) + ") has " + std::to_string(nPoints) +
                        " points but no <Points><DataArray>");
        auto decl = declare(pa, "Points");
        if (!decl) return decl.error();
        if (decl->components != 3)
            return failArray(*decl, "points need 3 components, not " + std::to_string(decl->components));
        std::vector<double> xyz;
        if (Status s = read(*decl, nPoints * 3, xyz); !s) return s;
        for (std::size_t i = 0; i < xyz.size(); i += 3) {
            const glm::dvec3 p(xyz[i], xyz[i + 1], xyz[i + 2]);
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                return failArray(*decl, "point " + std::to_string(i / 3) + " is not finite");
            points_.push_back(p);
        }
    }
    // Cells.
    if (nCells > 0) {
        pugi::xml_node cells = piece.child("Cells");
        ArrayDecl conn, offs, types;
        bool haveConn = false, haveOffs = false, haveTypes = false;
        for (pugi::xml_node da = cells.child("DataArray"); da; da = da.next_sibling("DataArray")) {
            const std::string_view name = da.attribute("Name").value();
            auto decl = declare(da, name);
            if (!decl) return decl.error();
            if (name == "connectivity")
                conn = *decl, haveConn = true;
            else if (name == "offsets")
                offs = *decl, haveOffs = true;
            else if (name == "types")
                types = *decl, haveTypes = true;
        }
        if (!haveConn || !haveOffs || !haveTypes)
            return fail("<Piece> (" + where(piece) + ") has " + std::to_string(nCells) +
                        " cells but lacks the Cells arrays connectivity, offsets and types");
        std::vector<std::int64_t> o, t, c;
        if (Status s = read(offs, nCells, o); !s) return s;
        if (Status s = read(types, nCells, t); !s) return s;
        std::int64_t prev = 0;
        for (std::size_t i = 0; i < o.size(); ++i) {
            if (o[i] < prev)
                return failArray(offs, "offset " + std::to_string(i) + " (" + std::to_string(o[i]) +
                                           ") is smaller than the one before (" + std::to_string(prev) + ")");
            prev = o[i];
        }
        // Connectivity values take >= 1 byte each in any encoding (1/1040 compressed).
        if (std::uint64_t(prev) > bound)
            return failArray(offs, "last offset " + std::to_string(prev) + " is larger than the file can hold");
        if (Status s = read(conn, std::uint64_t(prev), c); !s) return s;
        const std::int64_t connBase = static_cast<std::int64_t>(connectivity_.size());
        for (std::size_t i = 0; i < t.size(); ++i) {
            if (t[i] < 0 || t[i] > 255)
                return failArray(
                    types, "cell " + std::to_string(i) + " has type " + std::to_string(t[i]) + ", not a VTK cell type");
            types_.push_back(static_cast<std::uint8_t>(t[i]));
            offsets_.push_back(connBase + o[i]);
        }
        for (std::size_t i = 0; i < c.size(); ++i) {
            if (c[i] < 0 || std::uint64_t(c[i]) >= nPoints)
                return failArray(conn, "value " + std::to_string(i) + " (" + std::to_string(c[i]) +
                                           ") is not a point index of this piece (it has " + std::to_string(nPoints) +
                                           " points)");
            connectivity_.push_back(c[i] + static_cast<std::int64_t>(base));
        }
    }
    // Point and cell data.
    auto readData = [&](const char* element, std::uint64_t n, std::vector<CellArray>& into) -> Status {
        std::size_t k = 0;
        for (pugi::xml_node da = piece.child(element).child("DataArray"); da; da = da.next_sibling("DataArray"), ++k) {
            auto decl = declare(da, std::string(element) + " array " + std::to_string(k));
            if (!decl) return decl.error();
            std::vector<double> v;
            auto total = mulChecked(n, decl->components);
            if (!total) return failArray(*decl, "declared size overflows");
            if (Status s = read(*decl, *total, v); !s) return s;
            if (pieces_ == 0) {
                into.push_back({decl->name, isIntegerScalar(decl->type), decl->components, std::move(v)});
                continue;
            }
            // Later pieces: append to the array of the same name (same components).
            auto it = std::find_if(into.begin(), into.end(), [&](const CellArray& c) { return c.name == decl->name; });
            if (it == into.end() || it->components != decl->components)
                return failArray(
                    *decl, "is not in the first piece with the same components; pieces must carry the same arrays");
            it->values.insert(it->values.end(), v.begin(), v.end());
        }
        return {};
    };
    if (Status s = readData("PointData", nPoints, pointArrays_); !s) return s;
    if (Status s = readData("CellData", nCells, cellArrays_); !s) return s;
    ++pieces_;
    return {};
}

// The .vtu's cells as a VolumeMesh (region indices filled by the caller).
struct CellCensus {
    std::size_t lowerDimensional = 0;  // types 1-9
    std::size_t quadratic = 0;         // types 24-27 taken as linear
};

Result<Model> VtuReader::run() {
    // Raw appended data is not XML: cut the file at <AppendedData ...> and parse the part before it.
    const std::size_t appendedTag = bytes_.find("<AppendedData");
    if (appendedTag != std::string_view::npos) {
        const std::size_t gt = bytes_.find('>', appendedTag);
        if (gt == std::string_view::npos)
            return fail("byte " + std::to_string(appendedTag) + ": <AppendedData> tag is not closed");
        std::size_t underscore = gt + 1;
        while (underscore < bytes_.size() && isSpace(bytes_[underscore])) ++underscore;
        if (underscore >= bytes_.size() || bytes_[underscore] != '_')
            return fail("byte " + std::to_string(gt + 1) + ": <AppendedData> does not start with the '_' marker");
        appended_ = bytes_.substr(underscore + 1);
        haveAppended_ = true;
        xmlText_.assign(bytes_.substr(0, gt + 1));
        xmlText_ += "</AppendedData></VTKFile>";
    } else {
        xmlText_.assign(bytes_);
    }
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_buffer(xmlText_.data(), xmlText_.size());
    if (!parsed)
        return fail("byte " + std::to_string(parsed.offset) + ": not well-formed XML: " + parsed.description());
    const pugi::xml_node root = doc.document_element();
    if (std::string_view(root.name()) != "VTKFile")
        return fail("root element is <" + printable(root.name()) + ">, not <VTKFile>");
    const std::string_view type = root.attribute("type").value();
    if (type != "UnstructuredGrid")
        return fail("VTKFile type '" + printable(type) + "' is not UnstructuredGrid (only .vtu volume grids are read)",
                    ErrorCode::Unsupported);
    const std::string_view byteOrder = root.attribute("byte_order").value();
    if (byteOrder == "BigEndian")
        bigEndian_ = true;
    else if (!byteOrder.empty() && byteOrder != "LittleEndian")
        return fail("byte_order '" + printable(byteOrder) + "' is not LittleEndian or BigEndian");
    const std::string_view header = root.attribute("header_type").value();
    if (header == "UInt64")
        header64_ = true;
    else if (!header.empty() && header != "UInt32")
        return fail("header_type '" + printable(header) + "' is not UInt32 or UInt64");
    const std::string_view compressor = root.attribute("compressor").value();
    if (compressor == "vtkZLibDataCompressor")
        zlib_ = true;
    else if (!compressor.empty())
        return fail(
            "compressor '" + printable(compressor) +
                "' is not supported (only vtkZLibDataCompressor; re-save the file with zlib or without compression)",
            ErrorCode::Unsupported);
    if (haveAppended_) {
        pugi::xml_node ad = root.child("AppendedData");
        const std::string_view enc = ad.attribute("encoding").value();
        if (enc == "base64")
            appendedBase64_ = true;
        else if (enc != "raw")
            return fail("<AppendedData> encoding '" + printable(enc) + "' is not raw or base64");
    }

    const pugi::xml_node grid = root.child("UnstructuredGrid");
    if (!grid) return fail("no <UnstructuredGrid> element under <VTKFile>");
    for (pugi::xml_node piece = grid.child("Piece"); piece; piece = piece.next_sibling("Piece"))
        if (Status s = readPiece(piece); !s) return s.error();
    if (pieces_ == 0) return fail("<UnstructuredGrid> has no <Piece>");

    // Cells -> VolumeMesh cells; which cells are kept.
    VolumeMesh vm;
    vm.positions = std::move(points_);
    CellCensus census;
    std::vector<std::uint32_t> keptCells;  // input cell index of each VolumeMesh cell
    vm.cellOffsets.push_back(0);
    std::int64_t begin = 0;
    for (std::size_t c = 0; c < types_.size(); ++c) {
        const std::int64_t end = offsets_[c];
        const std::size_t n = static_cast<std::size_t>(end - begin);
        const std::int64_t* v = connectivity_.data() + begin;
        const int t = types_[c];
        auto bad = [&](std::size_t need) {
            return fail("cell " + std::to_string(c) + " of type " + std::to_string(t) + " has " + std::to_string(n) +
                        " vertices, not " + std::to_string(need));
        };
        VolumeMesh::CellType ct{};
        std::size_t corners = 0;
        const std::int64_t* order = nullptr;
        static const std::int64_t kVoxelToHex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
        switch (t) {
            case 10:
                ct = VolumeMesh::CellType::Tetra, corners = 4;
                break;
            case 11:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8, order = kVoxelToHex;
                break;
            case 12:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8;
                break;
            case 13:
                ct = VolumeMesh::CellType::Wedge, corners = 6;
                break;
            case 14:
                ct = VolumeMesh::CellType::Pyramid, corners = 5;
                break;
            case 24:
                ct = VolumeMesh::CellType::Tetra, corners = 4;
                break;  // quadratic: 10 nodes
            case 25:
                ct = VolumeMesh::CellType::Hexahedron, corners = 8;
                break;  // 20
            case 26:
                ct = VolumeMesh::CellType::Wedge, corners = 6;
                break;  // 15
            case 27:
                ct = VolumeMesh::CellType::Pyramid, corners = 5;
                break;  // 13
            default:
                if (t >= 1 && t <= 9) {
                    ++census.lowerDimensional;
                    begin = end;
                    continue;
                }
                return fail("cell " + std::to_string(c) + " has VTK type " + std::to_string(t) +
                                (t == 42 ? " (polyhedron)" : "") +
                                ", which is not read (tetrahedra, hexahedra, voxels, wedges and pyramids are); "
                                "dropping it would change the volume",
                            ErrorCode::Unsupported);
        }
        static const std::size_t kQuadraticNodes[] = {10, 20, 15, 13};
        const std::size_t need = t >= 24 ? kQuadraticNodes[t - 24] : corners;
        if (n != need) return bad(need);
        if (t >= 24) ++census.quadratic;
        vm.cellTypes.push_back(ct);
        for (std::size_t k = 0; k < corners; ++k)
            vm.cellVertices.push_back(static_cast<std::uint32_t>(v[order ? order[k] : std::int64_t(k)]));
        if (vm.cellVertices.size() >= std::numeric_limits<std::uint32_t>::max())
            return fail("more cell vertices than 32-bit offsets can address");
        vm.cellOffsets.push_back(static_cast<std::uint32_t>(vm.cellVertices.size()));
        keptCells.push_back(static_cast<std::uint32_t>(c));
        begin = end;
    }
    if (begin != static_cast<std::int64_t>(connectivity_.size()))
        return fail("the cells' offsets end at " + std::to_string(begin) + " but connectivity has " +
                    std::to_string(connectivity_.size()) + " values");
    if (vm.cellTypes.empty())
        return fail("no volume cells (tetrahedra, hexahedra, wedges, pyramids) in " + std::to_string(types_.size()) +
                        " cells; a .vtu of surfaces or points is not a volume model",
                    ErrorCode::Unsupported);
    connectivity_ = {};
    offsets_ = {};

    // The formation array.
    const CellArray* region = nullptr;
    if (!options_.regionArray.empty()) {
        for (const auto& a : cellArrays_)
            if (a.name == options_.regionArray) region = &a;
        if (!region) {
            std::string names;
            for (const auto& a : cellArrays_)
                names += (names.empty() ? "" : ", ") + std::string("'") + printable(a.name) + "'";
            return fail("no cell-data array named '" + printable(options_.regionArray) + "' (the file has " +
                            (names.empty() ? std::string("none") : names) + ")",
                        ErrorCode::NotFound);
        }
        if (region->components != 1)
            return fail("cell-data array '" + printable(region->name) + "' has " + std::to_string(region->components) +
                            " components; a formation array has one",
                        ErrorCode::InvalidArgument);
    } else {
        for (const auto& a : cellArrays_)
            if (a.components == 1 && a.integerType) {
                region = &a;
                break;
            }
        if (!region)
            for (const auto& a : cellArrays_)
                if (a.components == 1 && std::all_of(a.values.begin(), a.values.end(), [](double x) {
                        return std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9e15;
                    })) {
                    region = &a;
                    break;
                }
    }
    // Formation value of each kept cell -> region index (sorted by value).
    std::vector<std::int64_t> values;
    vm.cellRegions.resize(keptCells.size(), 0);
    std::vector<std::int64_t> cellValue(keptCells.size(), 0);
    if (region) {
        for (std::size_t i = 0; i < keptCells.size(); ++i) {
            const double x = region->values[keptCells[i]];
            if (!std::isfinite(x) || x != std::floor(x) || std::abs(x) >= 9e15)
                return fail("cell-data array '" + printable(region->name) + "': cell " + std::to_string(keptCells[i]) +
                            " has value " + std::to_string(x) + ", not a whole number naming a formation");
            cellValue[i] = static_cast<std::int64_t>(x);
        }
        values = cellValue;
        std::sort(values.begin(), values.end());
        values.erase(std::unique(values.begin(), values.end()), values.end());
        for (std::size_t i = 0; i < keptCells.size(); ++i)
            vm.cellRegions[i] = static_cast<std::int32_t>(std::lower_bound(values.begin(), values.end(), cellValue[i]) -
                                                          values.begin());
    } else {
        values = {1};
    }
    if (values.size() > 1000000)
        return fail("cell-data array '" + printable(region->name) + "' has " + std::to_string(values.size()) +
                        " distinct values; a formation array has few (choose another with --region-array)",
                    ErrorCode::InvalidArgument);

    auto boundaries = regionBoundaries(vm, values.size());
    if (!boundaries) return fail(boundaries.error().message, boundaries.error().code);

    Model model;
    model.source = source_;
    const bool direct = region && values.front() >= 1 && values.back() <= kMaxDirectRecordId;
    const std::string arrayName = region ? region->name : std::string("formation");
    model.notes["vtu_region_array"] = region ? region->name : std::string("(none: one formation)");
    if (region && !direct)
        model.notes["vtu_record_ids"] = "formation values are not all in [1, " + std::to_string(kMaxDirectRecordId) +
                                        "]: record ids are their ranks 1.." + std::to_string(values.size());
    if (census.lowerDimensional)
        model.notes["vtu_skipped_cells"] =
            std::to_string(census.lowerDimensional) + " point, line and face cells skipped";
    if (census.quadratic)
        model.notes["vtu_quadratic_cells"] =
            std::to_string(census.quadratic) + " quadratic cells taken as linear (mid-edge nodes ignored)";

    // Position -> input point, for point data on boundary vertices (regionBoundaries
    // renumbers each region's vertices; equal positions carry the first point's values).
    std::unordered_map<std::string_view, std::uint32_t> pointOf;
    std::vector<const CellArray*> pointFields;
    for (const auto& a : pointArrays_)
        if (a.values.size() == a.components * vm.positions.size()) pointFields.push_back(&a);
    if (!pointFields.empty()) {
        pointOf.reserve(vm.positions.size());
        for (std::size_t i = 0; i < vm.positions.size(); ++i)
            pointOf.emplace(std::string_view(reinterpret_cast<const char*>(&vm.positions[i]), sizeof(glm::dvec3)),
                            static_cast<std::uint32_t>(i));
    }

    for (std::size_t r = 0; r < values.size(); ++r) {
        Mesh& mesh = boundaries.value()[r];
        if (mesh.indices.empty()) continue;
        Part part;
        part.name = region ? arrayName + " " + std::to_string(values[r]) : std::string("cells");
        part.kind = PartKind::Body;
        part.kindDeclared = true;  // cells are a volume: a shell that cannot be closed is an error
        AttributeRecord rec;
        rec.id = direct ? static_cast<RecordId>(values[r]) : static_cast<RecordId>(r + 1);
        rec.name = part.name;
        rec.kind = "formation";
        if (region) rec.extra[region->name] = values[r];
        part.record = rec.id;
        model.attributes.put(std::move(rec));
        if (!pointFields.empty()) {
            for (const CellArray* a : pointFields)
                for (std::size_t k = 0; k < a->components; ++k)
                    mesh.propertyNames.push_back(a->components == 1 ? a->name
                                                                    : a->name + "[" + std::to_string(k) + "]");
            mesh.propertyValues.reserve(mesh.positions.size() * mesh.propertyNames.size());
            for (const glm::dvec3& p : mesh.positions) {
                auto it = pointOf.find(std::string_view(reinterpret_cast<const char*>(&p), sizeof(glm::dvec3)));
                const std::uint32_t src = it == pointOf.end() ? 0 : it->second;
                for (const CellArray* a : pointFields)
                    for (std::size_t k = 0; k < a->components; ++k)
                        mesh.propertyValues.push_back(static_cast<float>(a->values[src * a->components + k]));
            }
        }
        part.mesh = std::move(mesh);
        model.bodies.push_back(std::move(part));
    }
    // Cell arrays constant over a formation -> that formation's record.
    for (const auto& a : cellArrays_) {
        if (&a == region || a.components != 1) continue;
        std::vector<double> first(values.size(), std::numeric_limits<double>::quiet_NaN());
        std::vector<char> constant(values.size(), 1);
        for (std::size_t i = 0; i < keptCells.size(); ++i) {
            const std::size_t r = static_cast<std::size_t>(vm.cellRegions[i]);
            const double x = a.values[keptCells[i]];
            if (std::isnan(first[r]))
                first[r] = x;
            else if (first[r] != x)
                constant[r] = 0;
        }
        for (auto& part : model.bodies) {
            const std::size_t r =
                direct ? static_cast<std::size_t>(
                             std::lower_bound(values.begin(), values.end(), std::int64_t(part.record)) - values.begin())
                       : static_cast<std::size_t>(part.record - 1);
            if (!constant[r] || !std::isfinite(first[r])) continue;
            if (AttributeRecord* rec = model.attributes.find(part.record)) rec->extra[a.name] = first[r];
        }
    }
    finishLoadedModel(model, /*classifyByClosure=*/false);
    return model;
}

}  // namespace

Result<Model> parseVtu(std::string_view bytes, const std::string& source, const VtuOptions& options) {
    return VtuReader(bytes, source, options).run();
}

}  // namespace geoslice
