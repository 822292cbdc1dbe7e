// GOCAD Model3d (.ml): a boundary representation. The header lists the surfaces (TSURF),
// their patches (TFACE id type surface + a key triangle of three points), the regions
// (REGION id name, then signed TFACE ids ended by 0) and layers (LAYER name, then region
// ids ended by 0); after its END, one `GOCAD TSurf` object per TSURF holds the triangles,
// its TFACEs in the order the header numbers them.
//
// Side convention (checked on RINGMesh's geomodel3d.ml, whose box sides make it plain, and
// as RINGMesh's GOCAD reader reads it): `+id` puts the region on the side the key
// triangle's normal (p1-p0)x(p2-p0) points to, `-id` on the other side; a patch whose
// triangles turn the other way from its key triangle has its sides swapped. The Universe
// region (everything outside the model) lists the box sides with the signs of the inside,
// and is not a body.
//
// What it becomes: one closed body per region (Universe excluded), its shell made of its
// patches oriented outward and welded by exact position across surfaces; every TSurf also
// stays a surface (faults, horizons, box sides) for section traces. Region names become
// records, with their layer in extra["layer"].
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "model/io/gocad/gocad_reader.hpp"

namespace geoslice::gocad {

using namespace geoslice::text;

namespace {

struct Tface {
    std::uint64_t id = 0;
    std::string type, surface;
    glm::dvec3 key[3];
    std::size_t line = 0;
    // Filled when the surfaces are read:
    int surfaceIndex = -1;
    std::size_t firstTriangle = 0, triangleCount = 0;  // in that surface's mesh
    bool reversed = false;                             // the triangles turn the other way from the key triangle
    int regions = 0;                                   // regions it bounds (Universe excluded): at most two
};

struct Region {
    std::uint64_t id = 0;
    std::string name;
    std::vector<std::int64_t> faces;  // signed TFACE ids
    std::size_t line = 0;
    std::string layer;
};

// Reads integers over as many lines as it takes, up to a 0.
Status readZeroEndedList(Lines& lines, Tokens tokens, const std::string& what, std::vector<std::int64_t>& out) {
    const std::size_t start = lines.lineNo();
    std::string_view line;
    for (;;) {
        std::string_view tok;
        while (tokens.next(tok)) {
            std::int64_t v = 0;
            std::string_view digits = tok;
            bool negative = false;
            if (!digits.empty() && (digits.front() == '+' || digits.front() == '-')) {
                negative = digits.front() == '-';
                digits.remove_prefix(1);
            }
            std::uint64_t u = 0;
            if (parseId(digits, u) != IdStatus::Ok || u > (std::uint64_t(1) << 40))
                return lines.fail(what + ": " + quoteToken(tok) + " is not a signed integer id");
            v = negative ? -static_cast<std::int64_t>(u) : static_cast<std::int64_t>(u);
            if (v == 0) return {};
            out.push_back(v);
        }
        if (!lines.next(line))
            return lines.failAt(lines.lastLine(), what + " that starts on line " + std::to_string(start) +
                                                      " does not end with 0 (truncated file?)");
        if (Status s = lines.checkText(line, false); !s) return s;
        tokens = Tokens(trim(line));
    }
}

// Index (in `mesh`) of the triangle with the key points, and whether it turns the same way.
std::optional<bool> keyOrientation(const Mesh& mesh, std::size_t first, std::size_t count, const glm::dvec3 key[3]) {
    for (std::size_t t = first; t < first + count; ++t) {
        const glm::dvec3 p[3] = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                                 mesh.positions[mesh.indices[3 * t + 2]]};
        for (int r = 0; r < 3; ++r) {
            if (p[r] != key[0]) continue;
            if (p[(r + 1) % 3] == key[1] && p[(r + 2) % 3] == key[2]) return true;
            if (p[(r + 2) % 3] == key[1] && p[(r + 1) % 3] == key[2]) return false;
        }
    }
    return std::nullopt;
}

}  // namespace

Status readModel3d(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    std::vector<std::string> tsurfNames;
    std::vector<Tface> tfaces;
    std::vector<Region> regions;
    std::vector<std::pair<std::string, std::vector<std::int64_t>>> layers;

    auto own = [&](Lines::Statement& st, bool& handled) -> Status {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "TSURF") {
            tsurfNames.push_back(toUtf8(unquote(tokens.rest())));
        } else if (keyword == "TFACE") {
            Tface f;
            f.line = lines.lineNo();
            if (Status s = readId(lines, tokens, "TFACE id", f.id); !s) return s;
            std::string_view tok;
            if (tokens.next(tok)) f.type = toUtf8(tok);
            f.surface = toUtf8(unquote(tokens.rest()));
            for (int k = 0; k < 3; ++k) {
                std::string_view line;
                if (!lines.next(line))
                    return lines.failAt(lines.lastLine(), "TFACE " + std::to_string(f.id) +
                                                              " needs three key points after it (truncated file?)");
                if (Status s = lines.checkText(line, false); !s) return s;
                Tokens kt(trim(line));
                for (int a = 0; a < 3; ++a) {
                    std::optional<double> v;
                    if (!kt.next(tok) || !(v = parseDouble(tok)) || !std::isfinite(*v))
                        return lines.fail("TFACE " + std::to_string(f.id) + ": key point " + std::to_string(k + 1) +
                                          " needs three finite numbers x y z");
                    f.key[k][a] = *v;
                }
            }
            tfaces.push_back(std::move(f));
        } else if (keyword == "REGION") {
            Region r;
            r.line = lines.lineNo();
            if (Status s = readId(lines, tokens, "REGION id", r.id); !s) return s;
            std::string_view tok;
            if (!tokens.next(tok)) return lines.fail("REGION " + std::to_string(r.id) + " needs a name");
            r.name = toUtf8(unquote(tok));
            if (Status s = readZeroEndedList(lines, tokens, "REGION " + r.name, r.faces); !s) return s;
            regions.push_back(std::move(r));
        } else if (keyword == "LAYER") {
            std::string_view tok;
            if (!tokens.next(tok)) return lines.fail("LAYER needs a name");
            std::string name = toUtf8(unquote(tok));
            std::vector<std::int64_t> members;
            if (Status s = readZeroEndedList(lines, tokens, "LAYER " + name, members); !s) return s;
            layers.emplace_back(std::move(name), std::move(members));
        } else {
            handled = false;
        }
        return {};
    };
    if (Status s = readObjectBody(cx, info, "Model3d header", startLine, own); !s) return s;
    const std::string where = "the Model3d that starts on line " + std::to_string(startLine);
    if (tfaces.empty()) return lines.failAt(startLine, where + " has no TFACE");

    // TFACE ids -> index; ids are checked unique.
    std::vector<std::pair<std::uint64_t, std::size_t>> byId;
    for (std::size_t i = 0; i < tfaces.size(); ++i) byId.emplace_back(tfaces[i].id, i);
    std::sort(byId.begin(), byId.end());
    for (std::size_t i = 1; i < byId.size(); ++i)
        if (byId[i].first == byId[i - 1].first)
            return lines.failAt(tfaces[byId[i].second].line, "duplicate TFACE id " + std::to_string(byId[i].first));
    auto tfaceIndex = [&](std::uint64_t id) -> std::optional<std::size_t> {
        auto it = std::lower_bound(byId.begin(), byId.end(), std::make_pair(id, std::size_t(0)));
        if (it == byId.end() || it->first != id) return std::nullopt;
        return it->second;
    };

    // The surfaces: the GOCAD TSurf objects that follow, one per TSURF.
    std::vector<TsurfData> surfaces;
    std::vector<bool> assigned(tsurfNames.size(), false);
    std::vector<int> surfaceOfName(tsurfNames.size(), -1);
    // TSURF name -> its indices and a cursor past the ones already matched.
    std::map<std::string, std::pair<std::vector<std::size_t>, std::size_t>> byName;
    for (std::size_t i = 0; i < tsurfNames.size(); ++i) byName[tsurfNames[i]].first.push_back(i);
    std::map<std::string, std::size_t> firstByName;  // TSURF name -> its first index
    for (std::size_t i = tsurfNames.size(); i-- > 0;) firstByName[tsurfNames[i]] = i;
    std::size_t firstUnassigned = 0;
    while (surfaces.size() < tsurfNames.size()) {
        Lines::Mark m = lines.mark();
        std::string_view first;
        bool found = false;
        while (lines.next(first)) {
            std::string_view ft = trim(first);
            if (ft.empty() || ft.front() == '#') continue;
            found = true;
            break;
        }
        Tokens ft(trim(first));
        std::string_view kw, type;
        if (!found || !ft.next(kw) || kw != "GOCAD" || !ft.next(type) || lower(type) != "tsurf") {
            lines.reset(m);
            break;
        }
        TsurfData data;
        if (Status s = readTsurfData(cx, lines.lineNo(), data); !s) return s;
        // Match by name, else the first surface not yet matched.
        std::size_t k = tsurfNames.size();
        if (auto it = byName.find(data.info.name); it != byName.end()) {
            auto& [indices, cursor] = it->second;
            while (cursor < indices.size() && assigned[indices[cursor]]) ++cursor;
            if (cursor < indices.size()) k = indices[cursor++];
        }
        while (k == tsurfNames.size() && firstUnassigned < tsurfNames.size()) {
            if (!assigned[firstUnassigned]) k = firstUnassigned;
            ++firstUnassigned;
        }
        GS_ASSERT(k < tsurfNames.size(), "fewer surfaces read than named");
        assigned[k] = true;
        surfaceOfName[k] = static_cast<int>(surfaces.size());
        if (data.info.name.empty()) data.info.name = tsurfNames[k];
        surfaces.push_back(std::move(data));
    }
    for (std::size_t i = 0; i < tsurfNames.size(); ++i)
        if (!assigned[i])
            return lines.failAt(lines.lineNo(), where + " names surface " + quoteToken(tsurfNames[i]) +
                                                    " (TSURF), but no GOCAD TSurf object for it follows");

    // Patches: the k-th TFACE of a surface in the header is the k-th TFACE of its TSurf.
    std::vector<std::size_t> nextPatch(tsurfNames.size(), 0);
    std::vector<std::size_t> order(tfaces.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return tfaces[a].id < tfaces[b].id; });
    for (std::size_t i : order) {
        Tface& f = tfaces[i];
        auto it = firstByName.find(f.surface);
        if (it == firstByName.end())
            return lines.failAt(f.line, "TFACE " + std::to_string(f.id) + " names surface " + quoteToken(f.surface) +
                                            ", which is not a TSURF of the model");
        const std::size_t k = it->second;
        const TsurfData& s = surfaces[static_cast<std::size_t>(surfaceOfName[k])];
        const std::size_t patch = nextPatch[k]++;
        if (patch >= s.tfaceStart.size())
            return lines.failAt(f.line, "TFACE " + std::to_string(f.id) + " is patch " + std::to_string(patch + 1) +
                                            " of surface " + quoteToken(f.surface) + ", whose TSurf (line " +
                                            std::to_string(s.startLine) + ") has " +
                                            std::to_string(s.tfaceStart.size()) + " TFACE");
        f.surfaceIndex = surfaceOfName[k];
        f.firstTriangle = s.tfaceStart[patch];
        const std::size_t end = patch + 1 < s.tfaceStart.size() ? s.tfaceStart[patch + 1] : s.mesh.triangleCount();
        f.triangleCount = end - f.firstTriangle;
        glm::dvec3 key[3];
        for (int q = 0; q < 3; ++q) key[q] = info.crs.toWorld(f.key[q]);
        std::optional<bool> same = keyOrientation(s.mesh, f.firstTriangle, f.triangleCount, key);
        if (!same) {
            for (auto& q : key) q.z = -q.z;  // as RINGMesh: a key triangle written with the other z sign
            same = keyOrientation(s.mesh, f.firstTriangle, f.triangleCount, key);
        }
        if (!same)
            cx.warn(f.line, "TFACE " + std::to_string(f.id) +
                                ": its key triangle is not a triangle of the patch; the patch is taken to turn "
                                "like it");
        f.reversed = same.has_value() && !*same;
    }

    // Layers: region id -> layer name.
    std::vector<std::pair<std::int64_t, std::size_t>> regionById;
    for (std::size_t i = 0; i < regions.size(); ++i)
        regionById.emplace_back(static_cast<std::int64_t>(regions[i].id), i);
    std::sort(regionById.begin(), regionById.end());
    for (const auto& [name, members] : layers)
        for (std::int64_t id : members) {
            auto it = std::lower_bound(regionById.begin(), regionById.end(), std::make_pair(id, std::size_t(0)));
            for (; it != regionById.end() && it->first == id; ++it) regions[it->second].layer = name;
        }

    // One weld of every surface vertex, so that the regions' shells share positions exactly.
    std::vector<std::size_t> base(surfaces.size() + 1, 0);
    for (std::size_t i = 0; i < surfaces.size(); ++i) base[i + 1] = base[i] + surfaces[i].mesh.positions.size();
    if (base.back() >= std::numeric_limits<std::uint32_t>::max())
        return lines.failAt(startLine, where + " has too many vertices");
    std::vector<glm::dvec3> all;
    all.reserve(base.back());
    for (const TsurfData& s : surfaces) all.insert(all.end(), s.mesh.positions.begin(), s.mesh.positions.end());
    std::vector<glm::dvec3> welded;
    const std::vector<std::uint32_t> weld = weldExact(all, welded);
    all.clear();
    all.shrink_to_fit();

    std::vector<std::uint32_t> local(welded.size(), std::numeric_limits<std::uint32_t>::max());
    std::size_t bodies = 0;
    for (const Region& r : regions) {
        if (r.name == "Universe") continue;
        // A patch listed with both signs lies inside the region (a dangling fault): it bounds nothing.
        std::vector<std::int64_t> faces = r.faces;
        std::sort(faces.begin(), faces.end());
        std::vector<std::int64_t> kept;
        std::string inside;  // patches listed on both sides: inside the region
        for (std::int64_t s : faces) {
            if (std::binary_search(faces.begin(), faces.end(), -s)) {
                if (s > 0) inside += (inside.empty() ? "" : ", ") + std::to_string(s);
                continue;
            }
            if (!kept.empty() && kept.back() == s) continue;
            kept.push_back(s);
        }
        if (!inside.empty())
            cx.warn(r.line, "REGION " + r.name + " lists TFACE " + inside +
                                " on both sides (a surface ending inside the region): not part of its boundary");
        Part part;
        part.name = r.name;
        part.kind = PartKind::Body;
        Mesh& mesh = part.mesh;
        for (std::int64_t s : kept) {
            const std::uint64_t id = static_cast<std::uint64_t>(s < 0 ? -s : s);
            std::optional<std::size_t> fi = tfaceIndex(id);
            if (!fi)
                return lines.failAt(r.line, "REGION " + r.name + " names TFACE " + std::to_string(id) +
                                                ", which the model does not define");
            Tface& f = tfaces[*fi];
            if (++f.regions > 2)
                return lines.failAt(r.line, "REGION " + r.name + " names TFACE " + std::to_string(id) +
                                                ", which already bounds two other regions (a patch has two sides)");
            const TsurfData& surf = surfaces[static_cast<std::size_t>(f.surfaceIndex)];
            const std::size_t b = base[static_cast<std::size_t>(f.surfaceIndex)];
            // Outward = away from the region: flip when the triangles turn towards it.
            const bool flip = (s > 0) != f.reversed;
            for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount; ++t) {
                std::uint32_t v[3];
                for (int q = 0; q < 3; ++q) {
                    const std::uint32_t g = weld[b + surf.mesh.indices[3 * t + static_cast<std::size_t>(q)]];
                    if (local[g] == std::numeric_limits<std::uint32_t>::max()) {
                        local[g] = static_cast<std::uint32_t>(mesh.positions.size());
                        mesh.positions.push_back(welded[g]);
                    }
                    v[q] = local[g];
                }
                if (flip) std::swap(v[1], v[2]);
                mesh.indices.insert(mesh.indices.end(), {v[0], v[1], v[2]});
            }
        }
        // Reset the shared map for the next region (only the entries this one set).
        for (std::int64_t s : kept) {
            const Tface& f = tfaces[*tfaceIndex(static_cast<std::uint64_t>(s < 0 ? -s : s))];
            const TsurfData& surf = surfaces[static_cast<std::size_t>(f.surfaceIndex)];
            const std::size_t b = base[static_cast<std::size_t>(f.surfaceIndex)];
            for (std::size_t t = 3 * f.firstTriangle; t < 3 * (f.firstTriangle + f.triangleCount); ++t)
                local[weld[b + surf.mesh.indices[t]]] = std::numeric_limits<std::uint32_t>::max();
        }
        if (mesh.indices.empty()) {
            cx.warn(r.line, "REGION " + r.name + " has no triangles: no body");
            continue;
        }
        AttributeRecord rec;
        rec.name = r.name;
        rec.kind = "body";
        rec.extra["gocad_region_id"] = r.id;
        if (!r.layer.empty()) rec.extra["layer"] = r.layer;
        part.record = cx.model.attributes.add(std::move(rec));
        cx.model.bodies.push_back(std::move(part));
        ++bodies;
    }
    if (bodies == 0 && !regions.empty()) cx.warn(startLine, where + " defines no region other than the Universe");
    cx.declaredVolumes = cx.declaredVolumes || bodies > 0;
    if (!info.name.empty()) cx.model.notes["gocad_model3d"] = info.name;
    for (TsurfData& s : surfaces) addTsurfPart(cx, std::move(s));
    return {};
}

}  // namespace geoslice::gocad
