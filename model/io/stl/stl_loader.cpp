// STL reader, ASCII and binary.
//
// Frame: STL has no units and no axis convention; mining wireframers (Surpac, Datamine,
// Micromine, 3DMine, DIMINE) write world coordinates, z up, metres, so STL is read as
// world coordinates without an axis swap (the same rule as OBJ).
//
// ASCII or binary: a binary file is 80 header bytes, a little-endian uint32 triangle count
// n and n records of 50 bytes, so its size is exactly 84 + 50 n. That rule decides first:
// a binary header may well begin with "solid" (many exporters write "solid name" there),
// while an ASCII file's bytes 80..83 are text, which as a count would need gigabytes.
// A file that fails the rule and begins with "solid" is ASCII; any other file of at least
// 84 bytes is a binary file whose count disagrees with its size, which is an error naming
// both (a truncated or padded file), checked before anything is allocated.
//
// Parts: each ASCII `solid NAME ... endsolid` is a part named NAME (the file stem when
// NAME is empty; a name seen again appends to its part). A binary file is one part named
// after the file stem: the 80-byte header is free text that exporters fill with anything
// ("solid x", "VTK generated", "COLOR=..."), so it is kept as the model note "stl_header"
// when printable, never used as a name. Facet normals and the binary attribute word are
// not used: orientation comes from the winding, and validation orients closed bodies.
// Vertices are welded exactly (model/io/weld.hpp): a closed shell written facet by facet
// is a closed body again, an open one a surface.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "model/io/loaders.hpp"
#include "model/io/weld.hpp"
#include "model/text_scan.hpp"

namespace geoslice {
namespace {

using namespace geoslice::text;

constexpr std::size_t kHeaderBytes = 80;
constexpr std::size_t kRecordBytes = 50;
// Welded indices are uint32; one part holds at most this many triangles.
constexpr std::uint64_t kMaxTriangles = (std::uint64_t(1) << 32) / 3 - 1;

std::string stemOf(const std::string& source) {
    std::string stem = std::filesystem::path(source).stem().string();
    return stem.empty() ? "stl" : stem;
}

std::uint32_t readLe32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

float readLeFloat(const unsigned char* p) {
    const std::uint32_t u = readLe32(p);
    float f = 0.0f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

Result<Model> finish(std::vector<WeldedPart>& parts, const std::string& source) {
    Model model;
    model.source = source;
    model.name = stemOf(source);
    addWeldedParts(model, parts);
    finishLoadedModel(model, /*classifyByClosure=*/true);
    setRecordKinds(model);
    return model;
}

Result<Model> parseBinary(std::string_view bytes, const std::string& source) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::uint64_t count = readLe32(data + kHeaderBytes);
    const std::uint64_t needed = kHeaderBytes + 4 + kRecordBytes * count;
    if (needed != bytes.size())
        return makeError(ErrorCode::ParseError, source + ": binary STL: the triangle count at offset 80 is " +
                                                    std::to_string(count) + ", which needs " + std::to_string(needed) +
                                                    " bytes, but the file has " + std::to_string(bytes.size()) +
                                                    (needed > bytes.size() ? " (truncated?)" : " (trailing bytes?)"));
    if (count == 0) return makeError(ErrorCode::ParseError, source + ": binary STL with no triangles: nothing to load");
    if (count > kMaxTriangles)
        return makeError(ErrorCode::OutOfRange, source + ": binary STL: " + std::to_string(count) +
                                                    " triangles is over the limit of " + std::to_string(kMaxTriangles));
    std::vector<WeldedPart> parts(1);
    parts[0].name = stemOf(source);
    parts[0].indices.reserve(static_cast<std::size_t>(count) * 3);
    for (std::uint64_t t = 0; t < count; ++t) {
        const std::size_t offset = kHeaderBytes + 4 + static_cast<std::size_t>(t) * kRecordBytes;
        const unsigned char* rec = data + offset + 12;  // past the normal
        glm::dvec3 v[3];
        for (int k = 0; k < 3; ++k) {
            for (int a = 0; a < 3; ++a) {
                const float f = readLeFloat(rec + 12 * k + 4 * a);
                if (!std::isfinite(f))
                    return makeError(ErrorCode::ParseError, source + ": binary STL: triangle " + std::to_string(t) +
                                                                " at offset " + std::to_string(offset) + ": vertex " +
                                                                std::to_string(k + 1) +
                                                                " has a non-finite coordinate (byte offset " +
                                                                std::to_string(offset + 12 + 12 * k + 4 * a) + ")");
                v[k][a] = static_cast<double>(f);
            }
        }
        parts[0].addTriangle(v[0], v[1], v[2]);
    }
    auto model = finish(parts, source);
    if (model) {
        std::string_view header(bytes.data(), kHeaderBytes);
        header = trim(header.substr(0, header.find('\0')));
        if (!header.empty() && findNonText(header, false) == std::string_view::npos)
            model->notes["stl_header"] = std::string(header);
    }
    return model;
}

class AsciiStl {
public:
    AsciiStl(std::string_view text, const std::string& source) : text_(text), source_(source) {}
    Result<Model> run();

private:
    Error fail(const std::string& what) const {
        return makeError(ErrorCode::ParseError, source_ + ": line " + std::to_string(lineNo_) + ": " + what);
    }
    // The next non-blank line's tokens; false at the end of the input.
    bool next(Tokens& tokens, std::string_view& keyword);
    Status expect(std::string_view want, Tokens& tokens);
    Status readFacet(Tokens& tokens, WeldedPart& part);

    std::string_view text_;
    const std::string& source_;
    std::size_t pos_ = 0, lineNo_ = 0;
    std::vector<glm::dvec3> loop_;
};

bool AsciiStl::next(Tokens& tokens, std::string_view& keyword) {
    std::string_view line;
    while (text::nextLine(text_, pos_, line)) {
        ++lineNo_;
        std::string_view t = trim(line);
        if (t.empty()) continue;
        tokens = Tokens(t);
        tokens.next(keyword);
        return true;
    }
    return false;
}

Status AsciiStl::expect(std::string_view want, Tokens& tokens) {
    std::string_view keyword;
    if (!next(tokens, keyword)) return fail("the file ends where '" + std::string(want) + "' was expected");
    if (!equalsNoCase(keyword, want)) return fail("expected '" + std::string(want) + "', found " + quoteToken(keyword));
    return {};
}

Status AsciiStl::readFacet(Tokens& tokens, WeldedPart& part) {
    // "facet normal nx ny nz": the normal is checked for form, not used.
    std::string_view tok;
    if (tokens.next(tok)) {
        if (!equalsNoCase(tok, "normal")) return fail("expected 'normal' after 'facet', found " + quoteToken(tok));
        for (int a = 0; a < 3; ++a)
            if (!tokens.next(tok) || !parseDouble(tok)) return fail("'facet normal' needs three numbers");
    }
    if (Status s = expect("outer", tokens); !s) return s;
    if (!tokens.next(tok) || !equalsNoCase(tok, "loop")) return fail("expected 'outer loop'");
    loop_.clear();
    std::string_view keyword;
    for (;;) {
        if (!next(tokens, keyword)) return fail("the file ends inside a facet (no 'endloop')");
        if (equalsNoCase(keyword, "endloop")) break;
        if (!equalsNoCase(keyword, "vertex"))
            return fail("expected 'vertex' or 'endloop', found " + quoteToken(keyword));
        glm::dvec3 p(0.0);
        for (int a = 0; a < 3; ++a) {
            if (!tokens.next(tok)) return fail("'vertex' needs x y z");
            auto v = parseDouble(tok);
            if (!v) return fail("vertex coordinate " + quoteToken(tok) + " is not a number");
            if (!std::isfinite(*v)) return fail("vertex coordinate " + quoteToken(tok) + " is not a finite number");
            p[a] = *v;
        }
        if (tokens.next(tok)) return fail("'vertex' has more than three coordinates: " + quoteToken(tok));
        loop_.push_back(p);
    }
    if (loop_.size() < 3) return fail("a facet needs 3 vertices, found " + std::to_string(loop_.size()));
    // STL facets are triangles; a few writers put polygons in one loop: fanned.
    for (std::size_t i = 1; i + 1 < loop_.size(); ++i) part.addTriangle(loop_[0], loop_[i], loop_[i + 1]);
    if (part.indices.size() / 3 > kMaxTriangles) return fail("too many triangles in one solid");
    return expect("endfacet", tokens);
}

Result<Model> AsciiStl::run() {
    std::vector<WeldedPart> parts;
    std::map<std::string, std::size_t> byName;
    Tokens tokens("");
    std::string_view keyword;
    std::size_t solids = 0;
    while (next(tokens, keyword)) {
        if (std::size_t bad = findNonText(tokens.rest(), true); bad != std::string_view::npos)
            return fail(nonTextMessage(tokens.rest(), bad, true));
        if (!equalsNoCase(keyword, "solid")) return fail("expected 'solid', found " + quoteToken(keyword));
        ++solids;
        std::string name = toUtf8(tokens.rest());
        if (name.empty()) name = stemOf(source_);
        auto [it, inserted] = byName.try_emplace(name, parts.size());
        if (inserted) {
            parts.emplace_back();
            parts.back().name = name;
        }
        const std::size_t solidLine = lineNo_;
        for (;;) {
            if (!next(tokens, keyword))
                return fail("the file ends inside 'solid " + name + "' of line " + std::to_string(solidLine) +
                            " (no 'endsolid')");
            if (equalsNoCase(keyword, "endsolid")) break;
            if (!equalsNoCase(keyword, "facet"))
                return fail("expected 'facet' or 'endsolid', found " + quoteToken(keyword));
            if (Status s = readFacet(tokens, parts[it->second]); !s) return s.error();
        }
    }
    if (solids == 0) return makeError(ErrorCode::ParseError, source_ + ": ASCII STL with no 'solid': nothing to load");
    bool any = false;
    for (const auto& p : parts) any = any || !p.indices.empty();
    if (!any) return makeError(ErrorCode::ParseError, source_ + ": ASCII STL with no facets: nothing to load");
    return finish(parts, source_);
}

bool startsWithSolid(std::string_view bytes) {
    std::size_t i = 0;
    while (i < bytes.size() && isSpace(bytes[i])) ++i;
    return startsWithNoCase(bytes.substr(i), "solid") && (bytes.size() == i + 5 || isSpace(bytes[i + 5]));
}

}  // namespace

bool isBinaryStl(std::string_view bytes) {
    if (bytes.size() < kHeaderBytes + 4) return false;
    const std::uint64_t count = readLe32(reinterpret_cast<const unsigned char*>(bytes.data()) + kHeaderBytes);
    return kHeaderBytes + 4 + kRecordBytes * count == bytes.size();
}

Result<Model> parseStl(std::string_view bytes, const std::string& source) {
    if (isBinaryStl(bytes)) return parseBinary(bytes, source);
    if (startsWithSolid(bytes)) return AsciiStl(bytes, source).run();
    if (bytes.size() >= kHeaderBytes + 4) return parseBinary(bytes, source);  // reports the size mismatch
    return makeError(ErrorCode::ParseError, source + ": not STL: " + std::to_string(bytes.size()) +
                                                " bytes, too short for a binary STL (84 bytes at least) and "
                                                "not beginning with 'solid'");
}

}  // namespace geoslice
