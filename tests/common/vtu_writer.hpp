// A small VTK XML UnstructuredGrid (.vtu) writer for tests, benchmarks and fuzz seeds, in
// every encoding the loader reads: ascii, inline base64 binary, appended raw or base64
// data, optionally zlib-compressed in VTK's block format (compressed with zlib's own
// compress2), UInt32 or UInt64 headers, either byte order. Written from the format
// description (docs.vtk.org, "VTK File Formats"), independently of model/io/vtu/vtu_loader.cpp.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <zlib.h>
#include <glm/glm.hpp>

namespace geoslice::testing {

struct VtuGrid {
    struct Array {
        std::string name;
        std::string type = "Int32";  // VTK scalar type name
        int components = 1;
        std::vector<double> values;
    };
    std::vector<glm::dvec3> points;
    std::vector<std::uint8_t> types;    // VTK cell types
    std::vector<std::int64_t> offsets;  // end offset of each cell in connectivity
    std::vector<std::int64_t> connectivity;
    std::vector<Array> cellData, pointData;

    void addCell(std::uint8_t type, std::initializer_list<std::int64_t> vertices) {
        types.push_back(type);
        connectivity.insert(connectivity.end(), vertices.begin(), vertices.end());
        offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    }
};

struct VtuEncoding {
    enum class Format { Ascii, Binary, Appended };
    Format format = Format::Ascii;
    bool appendedBase64 = false;
    bool zlib = false;
    bool header64 = false;
    bool bigEndian = false;
    bool separateHeader = false;  // uncompressed binary: base64 the header on its own
    std::string pointType = "Float64";
    std::string indexType = "Int64";  // connectivity and offsets
    std::size_t blockSize = 32768;    // zlib: uncompressed bytes per block

    std::string label() const {
        std::string s = format == Format::Ascii    ? "ascii"
                        : format == Format::Binary ? "binary"
                        : appendedBase64           ? "appended-base64"
                                                   : "appended-raw";
        if (zlib) s += "-zlib";
        if (header64) s += "-h64";
        if (bigEndian) s += "-be";
        return s;
    }
};

namespace detail {

inline std::string base64(const std::vector<std::uint8_t>& in) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const std::uint32_t b0 = in[i], b1 = i + 1 < in.size() ? in[i + 1] : 0, b2 = i + 2 < in.size() ? in[i + 2] : 0;
        const std::uint32_t v = (b0 << 16) | (b1 << 8) | b2;
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < in.size() ? kAlphabet[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? kAlphabet[v & 63] : '=';
    }
    return out;
}

template <class T>
void putScalar(std::vector<std::uint8_t>& out, T v, bool bigEndian) {
    std::uint8_t b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (bigEndian) std::reverse(b, b + sizeof(T));
    out.insert(out.end(), b, b + sizeof(T));
}

inline void putTyped(std::vector<std::uint8_t>& out, const std::string& type, double v, bool be) {
    if (type == "Int8")
        putScalar(out, static_cast<std::int8_t>(v), be);
    else if (type == "UInt8")
        putScalar(out, static_cast<std::uint8_t>(v), be);
    else if (type == "Int16")
        putScalar(out, static_cast<std::int16_t>(v), be);
    else if (type == "UInt16")
        putScalar(out, static_cast<std::uint16_t>(v), be);
    else if (type == "Int32")
        putScalar(out, static_cast<std::int32_t>(v), be);
    else if (type == "UInt32")
        putScalar(out, static_cast<std::uint32_t>(v), be);
    else if (type == "Int64")
        putScalar(out, static_cast<std::int64_t>(v), be);
    else if (type == "UInt64")
        putScalar(out, static_cast<std::uint64_t>(v), be);
    else if (type == "Float32")
        putScalar(out, static_cast<float>(v), be);
    else
        putScalar(out, v, be);
}

inline void putHeader(std::vector<std::uint8_t>& out, std::uint64_t v, const VtuEncoding& e) {
    if (e.header64)
        putScalar(out, v, e.bigEndian);
    else
        putScalar(out, static_cast<std::uint32_t>(v), e.bigEndian);
}

// The encoded text of one binary array (inline or appended base64) or its raw bytes.
struct Encoded {
    std::vector<std::uint8_t> raw;  // header + data, for appended raw
    std::string text;               // base64, for inline binary and appended base64
};

inline Encoded encode(const std::vector<std::uint8_t>& data, const VtuEncoding& e) {
    Encoded out;
    std::vector<std::uint8_t> header, body;
    if (!e.zlib) {
        putHeader(header, data.size(), e);
        body = data;
    } else {
        const std::size_t blocks = data.empty() ? 0 : (data.size() + e.blockSize - 1) / e.blockSize;
        const std::size_t last = data.size() % e.blockSize;
        putHeader(header, blocks, e);
        putHeader(header, e.blockSize, e);
        putHeader(header, last, e);
        std::vector<std::uint8_t> compressed;
        for (std::size_t b = 0; b < blocks; ++b) {
            const std::size_t n = std::min(e.blockSize, data.size() - b * e.blockSize);
            uLongf size = compressBound(static_cast<uLong>(n));
            std::vector<std::uint8_t> c(size);
            compress2(c.data(), &size, data.data() + b * e.blockSize, static_cast<uLong>(n), 6);
            c.resize(size);
            putHeader(header, size, e);
            body.insert(body.end(), c.begin(), c.end());
        }
    }
    out.raw = header;
    out.raw.insert(out.raw.end(), body.begin(), body.end());
    if (e.zlib || e.separateHeader)
        out.text = base64(header) + base64(body);  // as VTK writes compressed data
    else
        out.text = base64(out.raw);
    return out;
}

inline std::string asciiValue(const std::string& type, double v) {
    char buf[40];
    if (type == "Float32" || type == "Float64")
        std::snprintf(buf, sizeof buf, "%.17g", v);
    else
        std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(v));
    return buf;
}

}  // namespace detail

inline std::string writeVtu(const VtuGrid& g, const VtuEncoding& e) {
    std::string xml, appendedText;
    std::vector<std::uint8_t> appendedRaw;
    auto array = [&](const std::string& name, const std::string& type, int components, auto&& valueAt, std::size_t n) {
        xml += "        <DataArray type=\"" + type + "\"";
        if (!name.empty()) xml += " Name=\"" + name + "\"";
        xml += " NumberOfComponents=\"" + std::to_string(components) + "\"";
        if (e.format == VtuEncoding::Format::Ascii) {
            xml += " format=\"ascii\">\n";
            std::string line;
            for (std::size_t i = 0; i < n; ++i) {
                line += detail::asciiValue(type, valueAt(i));
                line += (i % 12 == 11) ? '\n' : ' ';
                if (line.size() > 4096) xml += line, line.clear();
            }
            xml += line + "\n        </DataArray>\n";
            return;
        }
        std::vector<std::uint8_t> data;
        data.reserve(n * 8);
        for (std::size_t i = 0; i < n; ++i) detail::putTyped(data, type, valueAt(i), e.bigEndian);
        detail::Encoded enc = detail::encode(data, e);
        if (e.format == VtuEncoding::Format::Binary) {
            xml += " format=\"binary\">\n" + enc.text + "\n        </DataArray>\n";
        } else if (e.appendedBase64) {
            xml += " format=\"appended\" offset=\"" + std::to_string(appendedText.size()) + "\"/>\n";
            appendedText += enc.text;
        } else {
            xml += " format=\"appended\" offset=\"" + std::to_string(appendedRaw.size()) + "\"/>\n";
            appendedRaw.insert(appendedRaw.end(), enc.raw.begin(), enc.raw.end());
        }
    };
    xml += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
    xml += e.bigEndian ? "BigEndian" : "LittleEndian";
    xml += "\" header_type=\"";
    xml += e.header64 ? "UInt64" : "UInt32";
    xml += "\"";
    if (e.zlib) xml += " compressor=\"vtkZLibDataCompressor\"";
    xml += ">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" + std::to_string(g.points.size()) +
           "\" NumberOfCells=\"" + std::to_string(g.types.size()) + "\">\n";
    auto dataBlock = [&](const char* tag, const std::vector<VtuGrid::Array>& arrays) {
        xml += std::string("      <") + tag + ">\n";
        for (const auto& a : arrays)
            array(
                a.name, a.type, a.components, [&](std::size_t i) { return a.values[i]; }, a.values.size());
        xml += std::string("      </") + tag + ">\n";
    };
    dataBlock("PointData", g.pointData);
    dataBlock("CellData", g.cellData);
    xml += "      <Points>\n";
    array(
        "Points", e.pointType, 3, [&](std::size_t i) { return g.points[i / 3][int(i % 3)]; }, g.points.size() * 3);
    xml += "      </Points>\n      <Cells>\n";
    array(
        "connectivity", e.indexType, 1, [&](std::size_t i) { return double(g.connectivity[i]); },
        g.connectivity.size());
    array(
        "offsets", e.indexType, 1, [&](std::size_t i) { return double(g.offsets[i]); }, g.offsets.size());
    array(
        "types", "UInt8", 1, [&](std::size_t i) { return double(g.types[i]); }, g.types.size());
    xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
    if (e.format == VtuEncoding::Format::Appended) {
        xml += "  <AppendedData encoding=\"";
        xml += e.appendedBase64 ? "base64" : "raw";
        xml += "\">\n   _";
        if (e.appendedBase64)
            xml += appendedText;
        else
            xml.append(reinterpret_cast<const char*>(appendedRaw.data()), appendedRaw.size());
        xml += "\n  </AppendedData>\n";
    }
    xml += "</VTKFile>\n";
    return xml;
}

// All the encodings the loader reads, for tests that must hold in each.
inline std::vector<VtuEncoding> allVtuEncodings() {
    using F = VtuEncoding::Format;
    std::vector<VtuEncoding> out;
    auto add = [&](F f, bool b64, bool z, bool h64, bool be, std::string pt, std::string it, bool sep = false) {
        VtuEncoding e;
        e.format = f;
        e.appendedBase64 = b64;
        e.zlib = z;
        e.header64 = h64;
        e.bigEndian = be;
        e.pointType = std::move(pt);
        e.indexType = std::move(it);
        e.separateHeader = sep;
        e.blockSize = 4096;  // several blocks even for small grids
        out.push_back(e);
    };
    add(F::Ascii, false, false, false, false, "Float64", "Int64");
    add(F::Binary, false, false, false, false, "Float64", "Int32");
    add(F::Binary, false, false, true, false, "Float64", "Int64", true);
    add(F::Binary, false, true, true, false, "Float64", "Int64");
    add(F::Binary, false, true, false, true, "Float64", "Int32");
    add(F::Appended, false, false, true, false, "Float64", "Int64");
    add(F::Appended, false, true, true, false, "Float64", "Int64");
    add(F::Appended, false, true, false, true, "Float64", "Int64");
    add(F::Appended, true, false, false, false, "Float64", "Int32");
    add(F::Appended, true, true, true, true, "Float64", "Int64");
    return out;
}

}  // namespace geoslice::testing
