// VTK XML UnstructuredGrid (.vtu) reading, internal: the reader that model/io/vtu/vtu_loader.cpp
// (the document, its header and pieces), model/io/vtu/vtu_arrays.cpp (DataArray decoding: ascii,
// base64, appended, zlib, byte order) and model/io/vtu/vtu_cells.cpp (cells -> formations ->
// bodies and records) implement together. What is read: see model/io/vtu/vtu_loader.cpp. Not a
// public header; parseVtu is declared in model/io/loaders.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "model/io/loaders.hpp"
#include "model/text_scan.hpp"

namespace geoslice::vtu {

// zlib's deflate never compresses better than about 1032:1; a header that claims more is
// corrupt (and would make us allocate for data that is not there).
constexpr std::uint64_t kMaxZlibRatio = 1040;

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32, Float64 };

inline bool isIntegerScalar(Scalar t) { return t != Scalar::Float32 && t != Scalar::Float64; }

using text::isSpace;
using text::printable;
using text::trimSpace;

// Checked a * b for sizes.
inline std::optional<std::uint64_t> mulChecked(std::uint64_t a, std::uint64_t b) {
    if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a) return std::nullopt;
    return a * b;
}

// One DataArray element, as declared.
struct ArrayDecl {
    pugi::xml_node node;
    std::string name;  // Name attribute, or the role ("Points") when it has none
    Scalar type = Scalar::Float64;
    std::size_t components = 1;
    enum class Format { Ascii, Binary, Appended } format = Format::Ascii;
    std::uint64_t offset = 0;  // appended only
};

// A decoded String array (<Array type="String">: NUL-terminated strings, one per tuple).
struct StringArray {
    std::string name;
    std::vector<std::string> values;
};

// payload()'s byte count when the array's own header gives it (String arrays).
constexpr std::uint64_t kLengthFromHeader = std::numeric_limits<std::uint64_t>::max();

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

    // strings: a String array (<Array type="String">) is accepted, its bytes as UInt8.
    Result<ArrayDecl> declare(pugi::xml_node node, std::string_view role, bool strings = false) const;
    // Decodes `count` values of the array (components included) as T (double or int64).
    template <class T>
    Status read(const ArrayDecl& a, std::uint64_t count, std::vector<T>& out) const;
    // The array's payload bytes (binary / appended), exactly `bytes` long after any
    // decompression, in file byte order.
    // bytes == kLengthFromHeader: as many as the header says (at most what is present).
    Status payload(const ArrayDecl& a, std::uint64_t bytes, std::vector<std::uint8_t>& out) const;
    // An <Array type="String"> of `count` strings (count 0: as many as it holds), UTF-8
    // checked (invalid sequences become U+FFFD).
    Result<StringArray> readStrings(pugi::xml_node node, std::uint64_t count, std::string_view role) const;
    Status readPiece(pugi::xml_node piece);
    // FieldData String arrays of the grid or a piece into fieldStrings_.
    Status readFieldStrings(pugi::xml_node owner);
    // The cells read by run() -> one closed body per formation (model/io/vtu/vtu_cells.cpp).
    Result<Model> buildModel();

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
    std::vector<StringArray> cellStrings_;   // CellData String arrays (one string per cell)
    std::vector<StringArray> fieldStrings_;  // FieldData String arrays (the grid's and pieces')
    std::size_t pieces_ = 0;
};

}  // namespace geoslice::vtu
