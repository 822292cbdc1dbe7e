// GOCAD reading: vertex lines (VRTX, PVRTX, constraint flags), property columns (PROPERTIES,
// ESIZES, NO_DATA_VALUES), vertex ids with ATOM aliases, and exact welding. Part of what the
// GOCAD readers share (model/io/gocad/gocad_reader.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

// Columns of PVRTX properties per vertex (sum of ESIZES). Real files have a few dozen at
// most; the cap bounds the NaN padding that plain VRTX lines in such an object cost.
constexpr std::size_t kMaxPropertyColumns = 256;

bool isConstraintFlag(std::string_view tok) {
    // GOCAD writes constraint flags after a vertex's coordinates: CNXYZ, CNXY, CNZ, CNX...
    if (tok.size() < 3 || tok.substr(0, 2) != "CN") return false;
    for (char c : tok.substr(2))
        if (c != 'X' && c != 'Y' && c != 'Z' && c != 'T') return false;
    return true;
}

}  // namespace

Status readVertexLine(Context& cx, Tokens& tokens, std::string_view keyword, VertexLine& out) {
    const std::string kw(keyword);
    std::string_view tok;
    if (!tokens.next(tok)) return cx.lines.fail(kw + " needs an id and x y z");
    switch (parseId(tok, out.id)) {
        case IdStatus::Ok:
            break;
        case IdStatus::NotInteger:
            return cx.lines.fail(kw + " id " + quoteToken(tok) + " is not a non-negative integer");
        case IdStatus::TooLarge:
            return cx.lines.fail(kw + " id " + quoteToken(tok) + " is out of range");
    }
    for (int a = 0; a < 3; ++a) {
        if (!tokens.next(tok))
            return cx.lines.fail(kw + " " + std::to_string(out.id) + " needs x y z, found " + std::to_string(a) +
                                 " coordinate" + (a == 1 ? "" : "s"));
        std::optional<double> v = parseDouble(tok);
        if (!v)
            return cx.lines.fail(kw + " " + std::to_string(out.id) + ": coordinate " + quoteToken(tok) +
                                 " is not a number");
        if (!std::isfinite(*v))
            return cx.lines.fail(kw + " " + std::to_string(out.id) + ": coordinate " + quoteToken(tok) +
                                 " is not a finite number");
        out.p[a] = *v;
    }
    Tokens peek = tokens;
    if (peek.next(tok) && isConstraintFlag(tok)) {
        tokens = peek;
        cx.warn(cx.lines.lineNo(),
                kw + " with GOCAD's constraint flag " + quoteToken(tok) + ": accepted, the flag is ignored", "cnxyz");
    }
    return {};
}

Status PropertySchema::readKeyword(const Lines& lines, std::string_view keyword, Tokens& tokens, bool& handled) {
    handled = true;
    if (keyword == "PROPERTIES" || keyword == "PROPERTY_CLASSES") {
        // PROPERTIES names the columns; PROPERTY_CLASSES only when PROPERTIES is absent.
        if (fixed) return lines.fail(std::string(keyword) + " must come before the first vertex");
        if (keyword == "PROPERTY_CLASSES" && propertiesLine != 0 && !names.empty()) return {};
        propertiesLine = lines.lineNo();
        names.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            if (names.size() == kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " properties");
            names.push_back(toUtf8(unquote(tok)));
        }
        return {};
    }
    if (keyword == "ESIZES") {
        if (fixed) return lines.fail("ESIZES must come before the first vertex");
        esizesLine = lines.lineNo();
        esizes.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::uint64_t n = 0;
            if (parseId(tok, n) != IdStatus::Ok || n == 0 || n > kMaxPropertyColumns)
                return lines.fail("ESIZES entry " + quoteToken(tok) + " is not an integer from 1 to " +
                                  std::to_string(kMaxPropertyColumns));
            esizes.push_back(static_cast<std::size_t>(n));
            if (esizes.size() > kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " ESIZES entries");
        }
        return {};
    }
    if (keyword == "NO_DATA_VALUES") {
        if (fixed) return lines.fail("NO_DATA_VALUES must come before the first vertex");
        noDataLine = lines.lineNo();
        noData.clear();
        std::string_view tok;
        while (tokens.next(tok)) {
            std::optional<double> v = parseDouble(tok);
            if (!v) return lines.fail("NO_DATA_VALUES entry " + quoteToken(tok) + " is not a number");
            noData.push_back(*v);
            if (noData.size() > kMaxPropertyColumns)
                return lines.fail("more than " + std::to_string(kMaxPropertyColumns) + " NO_DATA_VALUES entries");
        }
        return {};
    }
    handled = false;
    return {};
}

Status PropertySchema::fix(const Lines& lines) {
    fixed = true;
    const std::size_t n = names.size();
    if (n == 0) return {};
    std::vector<std::size_t> sizes = esizes;
    if (sizes.empty()) sizes.assign(n, 1);
    if (sizes.size() != n)
        return lines.failAt(esizesLine, "ESIZES has " + std::to_string(sizes.size()) + " entries for " +
                                            std::to_string(n) + " PROPERTIES");
    if (!noData.empty() && noData.size() != n)
        return lines.failAt(noDataLine, "NO_DATA_VALUES has " + std::to_string(noData.size()) + " entries for " +
                                            std::to_string(n) + " PROPERTIES");
    std::size_t total = 0;
    for (std::size_t s : sizes) total += s;  // each <= kMaxPropertyColumns, count <= kMaxPropertyColumns
    if (total > kMaxPropertyColumns)
        return lines.failAt(esizesLine, "the properties have " + std::to_string(total) +
                                            " values per vertex, over the limit of " +
                                            std::to_string(kMaxPropertyColumns));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 0; k < n; ++k) {
        for (std::size_t e = 0; e < sizes[k]; ++e) {
            columnNames.push_back(sizes[k] == 1 ? names[k] : names[k] + "[" + std::to_string(e) + "]");
            columnNoData.push_back(noData.empty() ? nan : noData[k]);
        }
    }
    return {};
}

Status PropertySchema::appendVertex(Context& cx, Tokens& tokens, bool withProperties, std::uint64_t id) {
    const Lines& lines = cx.lines;
    if (!fixed) {
        if (Status s = fix(lines); !s) return s;
        // Without a PROPERTIES line, the first PVRTX names its columns.
        if (withProperties && columnNames.empty()) {
            Tokens peek = tokens;
            std::string_view t;
            while (peek.next(t) && columnNames.size() < kMaxPropertyColumns) {
                columnNames.push_back("property_" + std::to_string(columnNames.size() + 1));
                columnNoData.push_back(std::numeric_limits<double>::quiet_NaN());
            }
        }
    }
    const std::size_t columns = columnNames.size();
    if (columns == 0) return {};
    // Honest PVRTX values cost at least two bytes of text each; only VRTX lines in an
    // object with properties add NaN padding, which this budget bounds.
    if (cx.propertyValueBudget < columns)
        return lines.fail("too many property values for the size of the input (VRTX lines in an object with " +
                          std::to_string(columns) + " property columns)");
    cx.propertyValueBudget -= columns;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (!withProperties) {
        values.insert(values.end(), columns, std::numeric_limits<float>::quiet_NaN());
        return {};
    }
    std::size_t found = 0;
    std::string_view tok;
    while (tokens.next(tok)) {
        if (found >= columns) {  // too many: count them for the message
            ++found;
            continue;
        }
        std::optional<double> v = parseDouble(tok);
        if (!v)
            return lines.fail("PVRTX " + std::to_string(id) + ": property value " + quoteToken(tok) +
                              " is not a number");
        double d = *v;
        if (d == columnNoData[found]) d = nan;
        if (std::isinf(d) || (std::isfinite(d) && std::fabs(d) > std::numeric_limits<float>::max()))
            return lines.fail("PVRTX " + std::to_string(id) + ": property value " + quoteToken(tok) +
                              " is outside the float range");
        values.push_back(static_cast<float>(d));
        ++found;
    }
    if (found != columns) {
        values.resize(values.size() - std::min(values.size(), found));
        return lines.fail("PVRTX " + std::to_string(id) + " has " + std::to_string(found) +
                          " property values, expected " + std::to_string(columns));
    }
    return {};
}

namespace {

// One VRTX / PVRTX line (`object` names the object in errors).
Status readVertex(Context& cx, const Lines& lines, Tokens& tokens, std::string_view keyword, std::string_view object,
                  PropertySchema& schema, VertexIds& ids, std::vector<glm::dvec3>& positions) {
    VertexLine v;
    if (Status s = readVertexLine(cx, tokens, keyword, v); !s) return s;
    if (positions.size() >= std::numeric_limits<std::uint32_t>::max() - 1)
        return lines.fail("too many vertices in one " + std::string(object) + " object");
    if (Status s = schema.appendVertex(cx, tokens, keyword == "PVRTX", v.id); !s) return s;
    ids.addVertex(v.id, static_cast<std::uint32_t>(positions.size()), lines.lineNo());
    positions.push_back(v.p);
    return {};
}

}  // namespace

KeywordReader vertexKeywords(Context& cx, std::string_view object, PropertySchema& schema, VertexIds& ids,
                             std::vector<glm::dvec3>& positions) {
    return [&cx, object, &schema, &ids, &positions](Lines::Statement& st, bool& handled) -> Status {
        const Lines& lines = cx.lines;
        if (st.keyword == "VRTX" || st.keyword == "PVRTX")
            return readVertex(cx, lines, st.tokens, st.keyword, object, schema, ids, positions);
        // SHAREDVRTX / SHAREDPVRTX (LightTSolid, OpenGeode and SKUA exports): a vertex of
        // another region at the position of an earlier VRTX; read as an ATOM of it.
        if (st.keyword == "ATOM" || st.keyword == "PATOM" || st.keyword == "SHAREDVRTX" || st.keyword == "SHAREDPVRTX")
            return ids.addAtom(lines, st.tokens, st.keyword);
        return schema.readKeyword(lines, st.keyword, st.tokens, handled);
    };
}

Status VertexIds::addAtom(const Lines& lines, Tokens& tokens, std::string_view keyword) {
    const std::string kw(keyword);
    Atom a;
    if (Status s = readId(lines, tokens, kw + " id", a.id); !s) return s;
    if (Status s = readId(lines, tokens, kw + " " + std::to_string(a.id) + ": the id of the vertex it reuses", a.ref);
        !s)
        return s;
    a.line = lines.lineNo();
    atoms.push_back(a);
    keys.push_back(Key{a.id, 0, a.line, true});
    return {};
}

Status VertexIds::resolve(const Lines& lines) {
    // Keys were appended in line order; a stable sort keeps that order among equal ids.
    auto byId = [](const Key& a, const Key& b) { return a.id < b.id; };
    if (!std::is_sorted(keys.begin(), keys.end(), byId)) std::stable_sort(keys.begin(), keys.end(), byId);
    const Key* dup = nullptr;  // the duplicate with the smallest line, for a stable message
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].id == keys[i - 1].id && (!dup || keys[i].line < dup->line)) dup = &keys[i];
    if (dup) {
        auto first = std::lower_bound(keys.begin(), keys.end(), dup->id,
                                      [](const Key& k, std::uint64_t id) { return k.id < id; });
        return lines.failAt(dup->line, "duplicate vertex id " + std::to_string(dup->id) + " (already defined on line " +
                                           std::to_string(first->line) + ")");
    }
    // Ids are usually 1..n without gaps: then an id is its own offset (no search).
    contiguous = !keys.empty() && keys.back().id - keys.front().id == keys.size() - 1;
    // Atoms in file order: each reuses a vertex (or an atom) defined before it.
    for (const Atom& a : atoms) {
        const Key* ref = find(a.ref);
        if (!ref || ref->line >= a.line)
            return lines.failAt(a.line, "ATOM/SHAREDVRTX " + std::to_string(a.id) + " refers to vertex id " +
                                            std::to_string(a.ref) + ", which is not defined before it");
        Key* self = const_cast<Key*>(find(a.id));
        GS_ASSERT(self != nullptr, "every ATOM has its own key");
        self->index = ref->index;
    }
    return {};
}

const VertexIds::Key* VertexIds::find(std::uint64_t id) const {
    if (contiguous) {
        const std::uint64_t offset = id - keys.front().id;  // wraps to huge when id < first
        return offset < keys.size() ? &keys[static_cast<std::size_t>(offset)] : nullptr;
    }
    auto it = std::lower_bound(keys.begin(), keys.end(), id, [](const Key& k, std::uint64_t v) { return k.id < v; });
    return it != keys.end() && it->id == id ? &*it : nullptr;
}

std::vector<std::uint32_t> weldExact(const std::vector<glm::dvec3>& positions, std::vector<glm::dvec3>& unique) {
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const glm::dvec3 &p = positions[a], &q = positions[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<std::uint32_t> first(positions.size());  // each position -> its group's smallest index
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        while (j < order.size() && positions[order[j]] == positions[order[i]]) first[order[j++]] = order[i];
        i = j;
    }
    std::vector<std::uint32_t> remap(positions.size(), std::numeric_limits<std::uint32_t>::max());
    unique.clear();
    for (std::size_t v = 0; v < positions.size(); ++v) {
        std::uint32_t f = first[v];
        if (remap[f] == std::numeric_limits<std::uint32_t>::max()) {
            remap[f] = static_cast<std::uint32_t>(unique.size());
            unique.push_back(positions[f]);
        }
        remap[v] = remap[f];
    }
    return remap;
}

}  // namespace geoslice::gocad
