// VTK XML UnstructuredGrid (.vtu) loader: volume cells with a formation per cell -> one
// closed body per formation (regionBoundaries in model/mesh/volume_mesh.hpp).
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
// the boundary meshes (float32). String arrays (<Array type="String">, VTK's vtkStringArray)
// in CellData or FieldData name the formations (model/io/vtu/vtu_cells.cpp).
//
// Robustness: every count, size and offset read from the file is checked against the
// bytes present before anything is allocated or read; zlib data is checked block by block
// against the sizes its header declares. Errors name the file, the array and the problem.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "model/io/vtu/vtu_reader.hpp"

namespace geoslice {
namespace vtu {

std::string VtuReader::where(pugi::xml_node n) const {
    const std::ptrdiff_t off = n.offset_debug();
    return off >= 0 ? "byte " + std::to_string(static_cast<std::size_t>(off) + xmlDocOffset_) : std::string("?");
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
    // String arrays (<Array type="String">): per cell in CellData, free lists in FieldData.
    std::size_t k = 0;
    for (pugi::xml_node sa = piece.child("CellData").child("Array"); sa; sa = sa.next_sibling("Array"), ++k) {
        if (std::string_view(sa.attribute("type").value()) != "String") continue;
        auto strings = readStrings(sa, nCells, "CellData string array " + std::to_string(k));
        if (!strings) return strings.error();
        auto it = std::find_if(cellStrings_.begin(), cellStrings_.end(),
                               [&](const StringArray& s) { return s.name == strings->name; });
        if (pieces_ == 0)
            cellStrings_.push_back(std::move(strings.value()));
        else if (it == cellStrings_.end())
            return fail("CellData string array '" + printable(strings->name) +
                        "' is not in the first piece; pieces must carry the same arrays");
        else
            it->values.insert(it->values.end(), strings->values.begin(), strings->values.end());
    }
    if (Status s = readFieldStrings(piece); !s) return s;
    ++pieces_;
    return {};
}

Status VtuReader::readFieldStrings(pugi::xml_node owner) {
    std::size_t k = 0;
    for (pugi::xml_node sa = owner.child("FieldData").child("Array"); sa; sa = sa.next_sibling("Array"), ++k) {
        if (std::string_view(sa.attribute("type").value()) != "String") continue;
        std::uint64_t n = 0;
        if (pugi::xml_attribute t = sa.attribute("NumberOfTuples");
            t && (text::parseUnsigned(trimSpace(t.value()), n) != text::IntStatus::Ok || n > (1u << 24)))
            return fail("FieldData string array '" + printable(sa.attribute("Name").value()) + "': NumberOfTuples '" +
                        printable(t.value()) + "' is not a count up to 16777216");
        auto strings = readStrings(sa, n, "FieldData string array " + std::to_string(k));
        if (!strings) return strings.error();
        fieldStrings_.push_back(std::move(strings.value()));
    }
    return {};
}

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
    if (Status s = readFieldStrings(grid); !s) return s.error();
    for (pugi::xml_node piece = grid.child("Piece"); piece; piece = piece.next_sibling("Piece"))
        if (Status s = readPiece(piece); !s) return s.error();
    if (pieces_ == 0) return fail("<UnstructuredGrid> has no <Piece>");
    return buildModel();
}

}  // namespace vtu

Result<Model> parseVtu(std::string_view bytes, const std::string& source, const VtuOptions& options) {
    return vtu::VtuReader(bytes, source, options).run();
}

}  // namespace geoslice
