// Model loaders. Each names the file and the line (text formats) or byte offset (binary)
// in its errors, and never crashes or hangs on any input: sizes and counts read from a
// file are checked against the bytes actually present before anything is allocated.
//
// Loaders return world coordinates (x east, y north, z up, metres; depth-positive inputs
// are converted) and call finishLoadedModel(): parts classified as bodies or surfaces,
// records created for parts that name none, origin set, validation run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

// Options of the .vtu reader (model/io/vtu/vtu_loader.cpp).
struct VtuOptions {
    // The cell-data array naming each cell's formation; empty: the first integer-typed
    // one-component cell array (else the first whose values are whole numbers).
    std::string regionArray;
};

// Options that reach the format readers (CLI flags such as --region-array).
struct LoadOptions {
    VtuOptions vtu;
    // The model's CRS given explicitly (--crs): overrides the file's (model/crs/model_crs.hpp).
    std::string crs;
    // The block model (--blocks, --blocks-clip; model/blocks/block_model.hpp attachBlockModel):
    // empty source = the <stem>.blocks.json / .blocks.csv sidecar when there is one.
    BlockOptions blocks;
};

// Dispatches on extension (.glb .gltf .obj .xml .geo3dml .vtu .stl .ply .dxf; GOCAD .ts .tsurf
// .ml .so .vo .sg .pl .gp; Surpac .str .dtm) and, for unknown extensions, on content. A .dtm
// is read with its string file: the one its header names, else <stem>.str, in its folder. A sidecar
// "<stem>.attributes.json" or ".csv" next to the file is merged into the attribute table when present. The CRS comes
// from the file, the JSON sidecar's "crs", a "<stem>.crs" file and options.crs (`--crs`), in the order and with the
// rules of model/crs/model_crs.hpp; a CRS a model cannot use (feet) is an error. A block model (options.blocks or a
// <stem>.blocks.json|csv sidecar) is attached last.
Result<Model> loadModel(const std::string& path, const LoadOptions& options = {});

// From bytes in memory; `source` names the input in error messages (fuzzers use these).
Result<Model> parseGltf(const std::uint8_t* data, std::size_t size, const std::string& source,
                        const std::string& baseDir = "");
// baseDir: the folder of the OBJ, where its mtllib files are read ("": materials not read).
Result<Model> parseObj(std::string_view text, const std::string& source, const std::string& baseDir = "");
// GOCAD TSurf: the first object must be a TSurf (later objects of any type are read too).
Result<Model> parseTsurf(std::string_view text, const std::string& source);
// Any GOCAD ASCII input: TSurf, Model3d, TSolid, LightTSolid, Voxet, SGrid, PLine and
// groups of them (model/io/gocad/gocad_reader.hpp). Voxet/SGrid data files are read from `baseDir`;
// with an empty baseDir (bytes from memory) they cannot be read and are an error.
Result<Model> parseGocad(std::string_view text, const std::string& source, const std::string& baseDir = "");
// baseDir: the file's folder, against which a Geo3DProject's xi:include hrefs are resolved
// (only files inside it are read); empty: includes are listed in warnings, not followed.
Result<Model> parseGeo3dml(std::string_view text, const std::string& source, const std::string& baseDir = "");
// VTK XML UnstructuredGrid: one closed body per formation (see model/io/vtu/vtu_loader.cpp).
Result<Model> parseVtu(std::string_view bytes, const std::string& source, const VtuOptions& options = {});

// STL, ASCII or binary (told apart by the binary size rule 84 + 50 n; model/io/stl/stl_loader.cpp):
// ASCII solids are parts named after the solid, a binary file one part named after the stem.
Result<Model> parseStl(std::string_view bytes, const std::string& source);
// Whether `bytes` has the exact size of a binary STL with the triangle count at offset 80.
bool isBinaryStl(std::string_view bytes);
// PLY, ASCII or binary (model/io/ply/ply_loader.cpp): a face property such as `region` splits parts.
Result<Model> parsePly(std::string_view bytes, const std::string& source);
// ASCII DXF (model/io/dxf/dxf_loader.cpp): 3DFACE, polyface/polygon-mesh POLYLINE and MESH
// faces as one part per layer; LINE, LWPOLYLINE and other POLYLINEs as lines.
Result<Model> parseDxf(std::string_view text, const std::string& source);
// Surpac string file (model/io/surpac/surpac_loader.cpp): its strings as lines.
Result<Model> parseSurpacString(std::string_view text, const std::string& source);
// Surpac DTM with the string file whose points its triangles number: one part per trisolation.
Result<Model> parseSurpacDtm(std::string_view dtm, const std::string& dtmSource, std::string_view str,
                             const std::string& strSource);

// Reads a whole regular file; refuses files over maxBytes with an OutOfRange error. Opened
// without blocking and checked with fstat first: a FIFO, socket or device is an error naming
// it (a FIFO opened for reading would wait for a writer forever), never read.
Result<std::string> readFile(const std::string& path, std::size_t maxBytes = std::size_t(4) << 30);

// "a FIFO (named pipe)", "a directory", ... for a stat st_mode (error messages).
std::string fileKindName(unsigned mode);

// The largest model file a server reads by default (server setting maxModelMiB): 1 GiB.
// A model file is read whole into memory and parsed (an OBJ of about 20 million triangles
// is 1 GiB); a larger one is refused from its size before any of it is read.
constexpr std::uint64_t kDefaultMaxModelBytes = std::uint64_t(1) << 30;
// How much of a model file probeModelFile reads.
constexpr std::size_t kModelProbeBytes = 4096;

// Checks a model file before it is read, cheaply (one open, one fstat, one read of at most
// kModelProbeBytes): a readable regular file (opened without blocking: a FIFO is never read),
// not empty, at most maxBytes, and its first bytes plausible for its extension: not all zero
// (a sparse or preallocated file), GLB magic or a JSON object for .glb/.gltf, no NUL byte in
// a text format (.obj, .dxf, GOCAD), 'ply' first for .ply, no binary DXF or binary Surpac
// .str/.dtm (refused as Unsupported). Errors name the file and the reason.
Status probeModelFile(const std::string& path, std::uint64_t maxBytes = kDefaultMaxModelBytes);

// Shared by all loaders, after parsing:
//  - parts with record == 0 get a record named after the part (kind from the part kind);
//  - when `classifyByClosure`, parts whose kind is not declared (Part::kindDeclared) become
//    bodies when closed (after splitting pinch-outs, see analyseMesh) and surfaces when open;
//    declared parts keep their kind, so a declared body that is not closed is an error;
//  - origin = rounded bounds centre; validate(model) runs (see model/mesh/validate.hpp) unless
//    `validateModel` is false (a baked package's mesh, validated when it was baked:
//    bake/package.hpp packageModel()).
void finishLoadedModel(Model& model, bool classifyByClosure, bool validateModel = true);

}  // namespace geoslice
