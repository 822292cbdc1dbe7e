// Internal to model/: what the GOCAD ASCII readers share (GOCAD "ASCII File Formats":
// TSurf, Model3d, TSolid, Voxet, SGrid, PLine, groups). One reader per object type, each
// in its own gocad_<type>.cpp; parseGocad() (gocad_file.cpp) dispatches on the
// `GOCAD <Type>` line of every object and merges them into one Model.
//
// Frames: readers keep coordinates as written (file units, z sign as written) and apply
// the object's CoordinateSystem (toWorld) when the object ends: world is x east, y north,
// z up, metres.
//
// Robustness: every line must be text; counts read from a file are checked against the
// bytes present before anything is sized from them; errors name the file and the line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "model/model.hpp"
#include "model/result.hpp"
#include "model/text_scan.hpp"

namespace geoslice::gocad {

// The lines of one input, numbered from 1, with CR stripped.
class Lines {
public:
    Lines(std::string_view text, const std::string& source);
    bool next(std::string_view& line);
    std::size_t lineNo() const { return lineNo_; }
    std::size_t lastLine() const { return lastLine_; }
    bool atEnd() const { return pos_ >= text_.size(); }
    std::size_t size() const { return text_.size(); }
    const std::string& source() const { return source_; }
    std::string_view text() const { return text_; }
    // A position to come back to (to look at the next object's first line).
    struct Mark {
        std::size_t pos = 0, lineNo = 0;
    };
    Mark mark() const { return {pos_, lineNo_}; }
    void reset(Mark m) {
        pos_ = m.pos;
        lineNo_ = m.lineNo;
    }

    Error failAt(std::size_t line, const std::string& what, ErrorCode code = ErrorCode::ParseError) const;
    Error fail(const std::string& what) const { return failAt(lineNo_, what); }
    // An error when `line` holds control bytes (or, with `utf8`, bytes that are not UTF-8).
    Status checkText(std::string_view line, bool utf8) const;
    // "(truncated file?)" when the input ends without a newline or in this line.
    std::string truncationHint() const;

    // One line with content: the line, its trimmed text, its first word and the words after it.
    struct Statement {
        std::string_view line, text, keyword;
        text::Tokens tokens{std::string_view()};
    };
    // Advances to the next line that is neither blank nor a '#' comment. False at the end of
    // the input, or at a line with control bytes, whose error is then left in `bad`.
    bool nextStatement(Statement& out, Status& bad);

private:
    std::string_view text_;
    const std::string& source_;
    std::size_t pos_ = 0;
    std::size_t lineNo_ = 0;
    std::size_t lastLine_ = 0;
    bool endsWithNewline_ = true;
};

// A reader of some of an object's keywords (readObjectBody): it reads one statement;
// `handled` is true on entry, and it sets it to false for a keyword that is not one of its own.
using KeywordReader = std::function<Status(Lines::Statement& st, bool& handled)>;

// GOCAD ids are unsigned decimal integers: text::parseUnsigned.
using IdStatus = text::IntStatus;
inline IdStatus parseId(std::string_view tok, std::uint64_t& out) { return text::parseUnsigned(tok, out); }
// Reads a non-negative integer token into `out`, or returns an error naming `what`.
Status readId(const Lines& lines, text::Tokens& tokens, const std::string& what, std::uint64_t& out);
std::string_view unquote(std::string_view s);

// Metres per unit of an AXIS_UNIT entry (m, km, ft, feet, US survey feet), or nullopt.
std::optional<double> metresPerUnit(std::string_view unit);

// GOCAD_ORIGINAL_COORDINATE_SYSTEM of one object.
struct CoordinateSystem {
    glm::dvec3 metresPerUnit{1.0};  // per axis
    bool depthPositive = false;     // ZPOSITIVE Depth: z grows downwards
    std::string name;               // NAME, unquoted; "Default" means no georeference
    std::string text;               // the block's lines, as provenance
    std::optional<int> epsg;        // an "EPSG:nnnn" found in NAME or PROJECTION
    bool declared = false;          // the object had its own block

    glm::dvec3 scale() const { return metresPerUnit * glm::dvec3(1.0, 1.0, depthPositive ? -1.0 : 1.0); }
    // As written -> world; + 0.0 so that a depth of 0 gives +0, not -0.
    glm::dvec3 toWorld(const glm::dvec3& p) const { return p * scale() + glm::dvec3(0.0); }
    // A direction or offset (no + 0.0 needed, same scale).
    glm::dvec3 vectorToWorld(const glm::dvec3& v) const { return v * scale(); }
    bool hasUnitConversion() const { return metresPerUnit != glm::dvec3(1.0); }
};

// State shared by the readers of one input (and of the members of a group).
struct Context {
    Lines& lines;
    std::string baseDir;  // folder of the input, for Voxet/SGrid data files; empty: none
    Model& model;
    CoordinateSystem fileCrs;  // last block seen: objects without one inherit it
    std::vector<std::string> warnings;
    std::set<std::string> warned;         // warning keys already given once
    std::set<std::string> crsNames;       // NAMEs other than Default declared by the objects
    std::size_t propertyValueBudget = 0;  // floats left for per-vertex properties
    bool declaredVolumes = false;         // a Model3d or TSolid added bodies (no closure reclassification)
    // TSurf parts whose name is empty: named after the model when the input ends.
    std::vector<std::size_t> unnamedSurfaces;

    // Records a warning naming the line; `key` (when given) makes it once per input.
    void warn(std::size_t line, const std::string& what, const std::string& key = "");
};

// Keyword handlers shared by every object type. Each returns true when it consumed the line.
// HEADER { key:value ... } (one line or several); keys are lower-cased.
Status readHeader(Lines& lines, std::string_view afterKeyword, std::map<std::string, std::string>& out);
// A GOCAD_ORIGINAL_COORDINATE_SYSTEM block, the keyword line just read.
Status readCoordinateSystem(Context& cx, CoordinateSystem& out);
// Skips a `KEYWORD ... {` block up to the line holding its '}'.
Status skipBlock(Lines& lines, std::size_t startLine, std::string_view what);
// Skips an object up to its END (nested objects of a group are not expected here).
Status skipObject(Lines& lines, std::size_t startLine);
// For a keyword a reader does not know: checks the line is UTF-8 text and skips its
// { } block if it opens one.
Status skipUnknown(Lines& lines, std::string_view keyword, std::string_view line);
// The record every GOCAD object gets: name, colour, GEOLOGICAL_TYPE -> kind, provenance.
struct ObjectInfo {
    std::string name;
    std::map<std::string, Rgba8> colours;  // header key (*solid*color, color...) -> colour
    std::string rawColour;
    std::string geologicalType, geologicalFeature, stratigraphicPosition;
    CoordinateSystem crs;
    void headerEntries(const std::map<std::string, std::string>& header);
    // Handles HEADER, GOCAD_ORIGINAL_COORDINATE_SYSTEM, GEOLOGICAL_TYPE/FEATURE,
    // STRATIGRAPHIC_POSITION. `handled` says whether the keyword was one of them.
    Status readCommon(Context& cx, std::string_view keyword, text::Tokens& tokens, std::string_view line,
                      bool& handled);
    AttributeRecord record() const;
};

// A GOCAD vertex line after its keyword: `id x y z [flag] [property values]`. GOCAD's
// constraint flags (CNXYZ, CNXY, CNZ, ...) after the coordinates are skipped with a warning.
struct VertexLine {
    std::uint64_t id = 0;
    glm::dvec3 p{0.0};
};
Status readVertexLine(Context& cx, text::Tokens& tokens, std::string_view keyword, VertexLine& out);

// Per-vertex property schema (PROPERTIES, ESIZES, NO_DATA_VALUES), fixed at the first vertex.
struct PropertySchema {
    std::vector<std::string> names;
    std::vector<std::size_t> esizes;
    std::vector<double> noData;
    std::size_t propertiesLine = 0, esizesLine = 0, noDataLine = 0;
    bool fixed = false;
    std::vector<std::string> columnNames;
    std::vector<double> columnNoData;  // NaN: none for that column
    std::vector<float> values;         // columnNames.size() per vertex

    // PROPERTIES / PROPERTY_CLASSES / ESIZES / NO_DATA_VALUES; `handled` as above.
    Status readKeyword(const Lines& lines, std::string_view keyword, text::Tokens& tokens, bool& handled);
    // Appends one vertex's values: the rest of a PVRTX line, or NaN padding for VRTX.
    Status appendVertex(Context& cx, text::Tokens& tokens, bool withProperties, std::uint64_t id);

private:
    Status fix(const Lines& lines);
};

// Sorted (id -> index) lookup of one object's vertices, with ATOM aliases. O(n log n)
// whatever ids an input picks (a hash map could be driven quadratic).
struct VertexIds {
    struct Key {
        std::uint64_t id = 0;
        std::uint32_t index = 0;  // vertex; for an ATOM, resolved in resolve()
        std::size_t line = 0;
        bool atom = false;
    };
    struct Atom {
        std::uint64_t id = 0, ref = 0;
        std::size_t line = 0;
    };
    std::vector<Key> keys;
    std::vector<Atom> atoms;
    bool contiguous = false;

    void addVertex(std::uint64_t id, std::uint32_t index, std::size_t line) {
        keys.push_back({id, index, line, false});
    }
    Status addAtom(const Lines& lines, text::Tokens& tokens, std::string_view keyword);
    // Sorts, rejects duplicates, resolves atoms (each must follow what it references).
    Status resolve(const Lines& lines);
    const Key* find(std::uint64_t id) const;
};

// The vertex keywords of a TSurf, TSolid or PLine (`object` names it in errors), as a
// KeywordReader: each VRTX / PVRTX line's position goes to `positions`, its id to `ids`, its
// property values (or NaN padding) to `schema`; ATOM / PATOM go to `ids`; PROPERTIES,
// PROPERTY_CLASSES, ESIZES, NO_DATA_VALUES to `schema`.
KeywordReader vertexKeywords(Context& cx, std::string_view object, PropertySchema& schema, VertexIds& ids,
                             std::vector<glm::dvec3>& positions);

// Binary sample files of Voxet and SGrid: `count` values of `esize` bytes (IEEE float 4
// or 8, or signed/unsigned integers of 1, 2 or 4 bytes), big-endian unless `littleEndian`,
// from byte `offset` of `path`. The file size is checked before anything is allocated.
struct SampleFormat {
    std::size_t esize = 4;
    std::string etype = "IEEE";  // IEEE, SIGNED_INT, UNSIGNED_INT
    bool littleEndian = false;
    std::uint64_t offset = 0;
};
Result<std::vector<float>> readSampleFile(const std::string& path, const SampleFormat& format, std::size_t count,
                                          std::optional<double> noData, const std::string& what);
// Resolves a data file named in a header (quotes removed) against the input's folder.
Result<std::string> dataFilePath(const Context& cx, std::string_view name, std::size_t line);

// The property table and dimensions shared by Voxet and SGrid headers: AXIS_N, PROPERTY n
// name, PROP_FILE n file, PROP_ESIZE n bytes, PROP_ETYPE n type, PROP_FORMAT n RAW,
// PROP_OFFSET n bytes, PROP_NO_DATA_VALUE n value, PROP_UNIT n unit.
struct GridHeader {
    struct Prop {
        std::string name, file, unit;
        SampleFormat format;
        std::string formatName = "RAW";
        std::optional<double> noData;
        std::size_t line = 0, fileLine = 0;
    };
    std::map<std::uint64_t, Prop> props;  // by property number
    std::size_t dims[3] = {0, 0, 0};
    std::size_t dimsLine = 0;
    bool cellCentred = false;       // PROP_ALIGNMENT CELLS (SGrid)
    std::size_t alignmentLine = 0;  // line of the last PROP_ALIGNMENT, 0: none

    Status readKeyword(Context& cx, std::string_view keyword, text::Tokens& tokens, bool& handled);
    // readKeyword as a KeywordReader.
    KeywordReader keywords(Context& cx) {
        return [this, &cx](Lines::Statement& st, bool& handled) {
            return readKeyword(cx, st.keyword, st.tokens, handled);
        };
    }
    // A grid of `type` ("Voxet", "SGrid") with the header's dims and alignment, named after
    // the object (else the model); an error when the object had no AXIS_N.
    Status startGrid(const Context& cx, std::string_view type, std::size_t startLine, const ObjectInfo& info,
                     Grid& grid) const;
    // Reads every property's sample file into grid.properties (grid.dims set before).
    Status readProperties(Context& cx, std::size_t startLine, Grid& grid) const;
};

// Reads the statements of one object after its `GOCAD <Type>` line (number `startLine`)
// through its END. Each statement goes to `own` (the type's keywords) first; then END ends
// the object, GOCAD is an error (a new object before END), and any other keyword goes to
// info.readCommon, then to `shared` when set (PropertySchema or GridHeader keywords), else to
// skipUnknown. `object` names it in errors ("TSurf object", "Model3d header"). At the end of
// the input without END: missingEnd, or, when `ended` is given, *ended = false and the caller
// decides.
Status readObjectBody(Context& cx, ObjectInfo& info, std::string_view object, std::size_t startLine,
                      const KeywordReader& own, const KeywordReader& shared = {}, bool* ended = nullptr);
// "missing END of the <object> that starts on line N (truncated file?)", at the input's last line.
Error missingEnd(const Lines& lines, std::string_view object, std::size_t startLine);

// Readers: called after the `GOCAD <Type>` line (number `startLine`), they read through the
// object's END and add to cx.model.
Status readTsurf(Context& cx, std::size_t startLine);
Status readModel3d(Context& cx, std::size_t startLine);
Status readTsolid(Context& cx, std::size_t startLine);
Status readVoxet(Context& cx, std::size_t startLine);
Status readSgrid(Context& cx, std::size_t startLine);
Status readPline(Context& cx, std::size_t startLine);

// The TSurf reader's result for one object, also used by Model3d for its embedded surfaces.
struct TsurfData {
    ObjectInfo info;
    std::size_t startLine = 0;
    Mesh mesh;                            // world; unused vertices dropped
    std::vector<std::size_t> tfaceStart;  // first triangle of each TFACE, in file order
};
// Reads one TSurf object (after its GOCAD line) through END into `out`.
Status readTsurfData(Context& cx, std::size_t startLine, TsurfData& out);
// Adds a TSurf as a surface part of cx.model (with its record).
void addTsurfPart(Context& cx, TsurfData&& data);

// Sort-based exact weld of positions: returns, for each input position, the index of its
// first equal position in `unique` (world positions compared bit for bit after +0.0).
std::vector<std::uint32_t> weldExact(const std::vector<glm::dvec3>& positions, std::vector<glm::dvec3>& unique);

}  // namespace geoslice::gocad
