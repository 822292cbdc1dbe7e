// A GOCAD ASCII input: a sequence of objects (`GOCAD <Type> <version>` ... `END`), each
// read by the reader of its type, and group objects (HomogeneousGroup,
// HeterogeneousGroup) whose members (BEGIN_MEMBERS ... END_MEMBERS) are objects again, all
// merged into one Model.
//
// CRS: each object's GOCAD_ORIGINAL_COORDINATE_SYSTEM names one (an EPSG code in NAME or
// PROJECTION, else NAME; "Default" means none). When the objects name exactly one, it is
// parsed by Crs::parse; a name geoslice cannot use, or objects that disagree, leave the
// model local, with a warning. Each record keeps its block's text as provenance.
//
// Warnings (leniencies, unread parts, CRS) go into the validation report (severity
// warning) and into model.notes["loader_warnings"].
#include <filesystem>

#include "model/io/gocad/gocad_reader.hpp"
#include "model/io/loaders.hpp"

namespace geoslice {
namespace gocad {

using namespace geoslice::text;

Error missingEnd(const Lines& lines, std::string_view object, std::size_t startLine) {
    return lines.failAt(lines.lastLine(), "missing END of the " + std::string(object) + " that starts on line " +
                                              std::to_string(startLine) + " (truncated file?)");
}

Status readObjectBody(Context& cx, ObjectInfo& info, std::string_view object, std::size_t startLine,
                      const KeywordReader& own, const KeywordReader& shared, bool* ended) {
    Lines& lines = cx.lines;
    Lines::Statement st;
    Status bad;
    while (lines.nextStatement(st, bad)) {
        const std::string_view line = st.line, keyword = st.keyword;
        bool handled = true;
        if (Status s = own(st, handled); !s) return s;
        if (handled) continue;
        if (keyword == "END") {
            if (ended) *ended = true;
            return {};
        }
        if (keyword == "GOCAD")
            return lines.fail("a new GOCAD object starts before END of the " + std::string(object) +
                              " that starts on line " + std::to_string(startLine));
        if (Status s = info.readCommon(cx, keyword, st.tokens, line, handled); !s) return s;
        if (handled) continue;
        if (shared) {
            handled = true;
            if (Status s = shared(st, handled); !s) return s;
            if (handled) continue;
        }
        if (Status s = skipUnknown(lines, keyword, line); !s) return s;
    }
    if (!bad) return bad;
    if (!ended) return missingEnd(lines, object, startLine);
    *ended = false;
    return {};
}

namespace {

constexpr int kMaxGroupDepth = 16;

Status readGroup(Context& cx, std::size_t startLine, int depth);

// Reads one object whose `GOCAD Type` line was just read.
Status readObject(Context& cx, std::string_view type, std::size_t line, int depth) {
    const std::string t = lower(type);
    if (t == "tsurf") return readTsurf(cx, line);
    if (t == "model3d") return readModel3d(cx, line);
    if (t == "tsolid" || t == "lighttsolid") return readTsolid(cx, line);
    if (t == "voxet" || t == "gsurf_voxet") return readVoxet(cx, line);
    if (t == "sgrid") return readSgrid(cx, line);
    if (t == "pline") return readPline(cx, line);
    if (t == "homogeneousgroup" || t == "heterogeneousgroup") return readGroup(cx, line, depth + 1);
    cx.warn(line, "GOCAD " + quoteToken(type) + " objects are not read (skipped to their END)",
            "skip " + std::string(type));
    return skipObject(cx.lines, line);
}

// Reads objects up to the end of the input, or up to `terminator` (END_MEMBERS).
Status readObjects(Context& cx, int depth, std::string_view terminator, std::size_t& objects) {
    Lines& lines = cx.lines;
    Lines::Statement st;
    Status bad;
    while (lines.nextStatement(st, bad)) {
        const std::string_view t = st.text, keyword = st.keyword;
        Tokens& tokens = st.tokens;
        std::string_view type;
        if (!terminator.empty() && keyword == terminator) return {};
        if (keyword != "GOCAD") {
            if (objects == 0 && depth == 0)
                return lines.fail("not a GOCAD file: expected 'GOCAD <type> 1', found " + quoteToken(t));
            return lines.fail("expected 'GOCAD' to start the next object" +
                              (terminator.empty() ? std::string() : " or " + std::string(terminator)) + ", found " +
                              quoteToken(t));
        }
        if (!tokens.next(type)) return lines.fail("'GOCAD' needs an object type (TSurf, Model3d, TSolid, ...)");
        ++objects;
        if (Status s = readObject(cx, type, lines.lineNo(), depth); !s) return s;
    }
    if (!bad) return bad;
    if (!terminator.empty())
        return lines.failAt(lines.lastLine(), "missing " + std::string(terminator) + " (truncated file?)");
    return {};
}

Status readGroup(Context& cx, std::size_t startLine, int depth) {
    Lines& lines = cx.lines;
    if (depth > kMaxGroupDepth)
        return lines.fail("groups nested more than " + std::to_string(kMaxGroupDepth) + " deep");
    ObjectInfo info;
    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        if (st.keyword == "BEGIN_MEMBERS") {
            std::size_t members = 0;
            return readObjects(cx, depth, "END_MEMBERS", members);
        }
        if (st.keyword == "GOCAD")
            return lines.fail("a GOCAD object outside BEGIN_MEMBERS ... END_MEMBERS of the group that starts on line " +
                              std::to_string(startLine));
        handled = false;
        return {};
    };
    return readObjectBody(cx, info, "group", startLine, own);
}

Result<Model> parse(std::string_view text, const std::string& source, const std::string& baseDir, bool tsurfOnly) {
    Lines lines(text, source);
    Model model;
    model.source = source;
    model.name = std::filesystem::path(source).stem().string();
    Context cx{lines, baseDir, model, {}, {}, {}, {}, 0, false, {}};
    cx.propertyValueBudget = text.size() + (std::size_t(1) << 20);

    if (tsurfOnly) {
        // The first object must be a TSurf (the contract of parseTsurf).
        Lines::Mark m = lines.mark();
        std::string_view line;
        bool any = false;
        while (lines.next(line)) {
            if (Status s = lines.checkText(line, false); !s) return s.error();
            std::string_view t = trim(line);
            if (t.empty() || t.front() == '#') continue;
            any = true;
            Tokens tokens(t);
            std::string_view keyword, type;
            tokens.next(keyword);
            if (keyword != "GOCAD")
                return lines.fail("not a GOCAD TSurf file: expected 'GOCAD TSurf 1', found " + quoteToken(t));
            tokens.next(type);
            if (lower(type) != "tsurf")
                return lines.fail("not a GOCAD TSurf file: the object type is " + quoteToken(type) +
                                  ", this loader reads 'GOCAD TSurf'");
            break;
        }
        if (!any) {
            if (lines.size() == 0)
                return makeError(ErrorCode::ParseError, source + ": empty input (expected 'GOCAD TSurf 1')");
            return lines.fail("empty input: only blank lines and comments, expected 'GOCAD TSurf 1'");
        }
        lines.reset(m);
    }
    std::size_t objects = 0;
    if (Status s = readObjects(cx, 0, "", objects); !s) return s.error();
    if (objects == 0) {
        if (lines.size() == 0)
            return makeError(ErrorCode::ParseError, source + ": empty input (expected 'GOCAD <type> 1')");
        return lines.fail("empty input: only blank lines and comments, expected 'GOCAD <type> 1'");
    }
    if (model.bodies.empty() && model.surfaces.empty() && model.grids.empty() && model.lines.empty())
        return makeError(ErrorCode::ParseError,
                         source + ": no geometry: no triangles (TRGL), tetrahedra, grids or lines in any object");

    for (std::size_t i : cx.unnamedSurfaces) {
        Part& p = model.surfaces[i];
        p.name = model.surfaces.size() == 1 ? model.name : model.name + "#" + std::to_string(i + 1);
        if (AttributeRecord* r = model.attributes.find(p.record)) r->name = p.name;
    }
    if (cx.crsNames.size() == 1) {
        const std::string& name = *cx.crsNames.begin();
        auto crs = Crs::parse(name);
        if (crs)
            model.crs = crs.value();
        else
            cx.warn(1, "coordinate system " + quoteToken(name) + " is not one geoslice knows (" + crs.error().message +
                           "): the model stays in local coordinates");
    } else if (cx.crsNames.size() > 1) {
        std::string all;
        for (const auto& n : cx.crsNames) all += (all.empty() ? "" : ", ") + quoteToken(n);
        cx.warn(1,
                "the objects declare different coordinate systems (" + all + "): the model stays in local coordinates");
    }

    finishLoadedModel(model, /*classifyByClosure=*/!cx.declaredVolumes);
    // Records without a GEOLOGICAL_TYPE take the kind their part was classified as.
    for (auto* list : {&model.bodies, &model.surfaces}) {
        for (Part& p : *list) {
            AttributeRecord* r = model.attributes.find(p.record);
            if (r && r->kind.empty()) r->kind = p.kind == PartKind::Body ? "body" : "surface";
        }
    }
    if (!cx.warnings.empty()) {
        std::string joined;
        for (const auto& w : cx.warnings) {
            model.validation.issues.push_back({ValidationIssue::Severity::Warning, "", w});
            joined += (joined.empty() ? "" : "\n") + w;
        }
        model.notes["loader_warnings"] = joined;
    }
    return model;
}

}  // namespace
}  // namespace gocad

Result<Model> parseGocad(std::string_view text, const std::string& source, const std::string& baseDir) {
    return gocad::parse(text, source, baseDir, /*tsurfOnly=*/false);
}

Result<Model> parseTsurf(std::string_view text, const std::string& source) {
    return gocad::parse(text, source, "", /*tsurfOnly=*/true);
}

}  // namespace geoslice
