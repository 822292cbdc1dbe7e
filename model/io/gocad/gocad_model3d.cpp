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

// TFACE id type surface, then three key points on lines of their own.
Status readTface(Lines& lines, Tokens& tokens, Tface& f) {
    f.line = lines.lineNo();
    if (Status s = readId(lines, tokens, "TFACE id", f.id); !s) return s;
    std::string_view tok;
    if (tokens.next(tok)) f.type = toUtf8(tok);
    f.surface = toUtf8(unquote(tokens.rest()));
    for (int k = 0; k < 3; ++k) {
        std::string_view line;
        if (!lines.next(line))
            return lines.failAt(lines.lastLine(),
                                "TFACE " + std::to_string(f.id) + " needs three key points after it (truncated file?)");
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
    return {};
}

// What the Model3d header lists.
struct Model3dHeader {
    std::vector<std::string> tsurfNames;
    std::vector<Tface> tfaces;
    std::vector<Region> regions;
    std::vector<std::pair<std::string, std::vector<std::int64_t>>> layers;
    std::vector<std::pair<std::uint64_t, std::size_t>> tfaceById;  // sorted (id, index in tfaces)

    // TSURF, TFACE, REGION, LAYER (a KeywordReader for readObjectBody).
    Status readKeyword(Lines& lines, Lines::Statement& st, bool& handled) {
        const std::string_view keyword = st.keyword;
        Tokens& tokens = st.tokens;
        if (keyword == "TSURF") {
            tsurfNames.push_back(toUtf8(unquote(tokens.rest())));
        } else if (keyword == "TFACE") {
            Tface f;
            if (Status s = readTface(lines, tokens, f); !s) return s;
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
    }

    // Sorts the TFACE ids, checking they are unique.
    Status indexTfaces(const Lines& lines) {
        for (std::size_t i = 0; i < tfaces.size(); ++i) tfaceById.emplace_back(tfaces[i].id, i);
        std::sort(tfaceById.begin(), tfaceById.end());
        for (std::size_t i = 1; i < tfaceById.size(); ++i)
            if (tfaceById[i].first == tfaceById[i - 1].first)
                return lines.failAt(tfaces[tfaceById[i].second].line,
                                    "duplicate TFACE id " + std::to_string(tfaceById[i].first));
        return {};
    }
    std::optional<std::size_t> tfaceIndex(std::uint64_t id) const {
        auto it = std::lower_bound(tfaceById.begin(), tfaceById.end(), std::make_pair(id, std::size_t(0)));
        if (it == tfaceById.end() || it->first != id) return std::nullopt;
        return it->second;
    }

    // Region id -> layer name.
    void assignLayers() {
        std::vector<std::pair<std::int64_t, std::size_t>> regionById;
        for (std::size_t i = 0; i < regions.size(); ++i)
            regionById.emplace_back(static_cast<std::int64_t>(regions[i].id), i);
        std::sort(regionById.begin(), regionById.end());
        for (const auto& [name, members] : layers)
            for (std::int64_t id : members) {
                auto it = std::lower_bound(regionById.begin(), regionById.end(), std::make_pair(id, std::size_t(0)));
                for (; it != regionById.end() && it->first == id; ++it) regions[it->second].layer = name;
            }
    }
};

// The surfaces: the GOCAD TSurf objects after the header, one per TSURF, matched by name,
// else to the first TSURF not yet matched. surfaceOfName[k]: the surface of TSURF k.
Status readSurfaces(Context& cx, const std::vector<std::string>& tsurfNames, const std::string& where,
                    std::vector<TsurfData>& surfaces, std::vector<int>& surfaceOfName) {
    Lines& lines = cx.lines;
    std::vector<bool> assigned(tsurfNames.size(), false);
    surfaceOfName.assign(tsurfNames.size(), -1);
    // TSURF name -> its indices and a cursor past the ones already matched.
    std::map<std::string, std::pair<std::vector<std::size_t>, std::size_t>> byName;
    for (std::size_t i = 0; i < tsurfNames.size(); ++i) byName[tsurfNames[i]].first.push_back(i);
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
    return {};
}

// Patches: the k-th TFACE of a surface in the header is the k-th TFACE of its TSurf. Sets
// each TFACE's surface, triangles and orientation against its key triangle.
Status placePatches(Context& cx, const CoordinateSystem& crs, const std::vector<TsurfData>& surfaces,
                    const std::vector<int>& surfaceOfName, Model3dHeader& h) {
    const Lines& lines = cx.lines;
    std::map<std::string, std::size_t> firstByName;  // TSURF name -> its first index
    for (std::size_t i = h.tsurfNames.size(); i-- > 0;) firstByName[h.tsurfNames[i]] = i;
    std::vector<std::size_t> nextPatch(h.tsurfNames.size(), 0);
    std::vector<std::size_t> order(h.tfaces.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return h.tfaces[a].id < h.tfaces[b].id; });
    for (std::size_t i : order) {
        Tface& f = h.tfaces[i];
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
        for (int q = 0; q < 3; ++q) key[q] = crs.toWorld(f.key[q]);
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
    return {};
}

// Every surface vertex welded by exact position, so that the regions' shells share positions.
struct WeldedSurfaces {
    std::vector<std::size_t> base;    // first vertex of each surface in the concatenation
    std::vector<std::uint32_t> weld;  // concatenated vertex -> welded vertex
    std::vector<glm::dvec3> welded;
    std::vector<std::uint32_t> local;  // welded vertex -> vertex of the shell being built
};

Status weldSurfaces(const Lines& lines, std::size_t startLine, const std::string& where,
                    const std::vector<TsurfData>& surfaces, WeldedSurfaces& w) {
    w.base.assign(surfaces.size() + 1, 0);
    for (std::size_t i = 0; i < surfaces.size(); ++i) w.base[i + 1] = w.base[i] + surfaces[i].mesh.positions.size();
    if (w.base.back() >= std::numeric_limits<std::uint32_t>::max())
        return lines.failAt(startLine, where + " has too many vertices");
    std::vector<glm::dvec3> all;
    all.reserve(w.base.back());
    for (const TsurfData& s : surfaces) all.insert(all.end(), s.mesh.positions.begin(), s.mesh.positions.end());
    w.weld = weldExact(all, w.welded);
    w.local.assign(w.welded.size(), std::numeric_limits<std::uint32_t>::max());
    return {};
}

// The patches of region `r` that bound it: a patch listed with both signs lies inside the
// region (a dangling fault) and bounds nothing.
std::vector<std::int64_t> boundingFaces(Context& cx, const Region& r) {
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
    return kept;
}

// The shell of region `r`: its patches oriented outward, on the welded vertices.
Status regionShell(Context& cx, const Region& r, const std::vector<TsurfData>& surfaces, Model3dHeader& h,
                   WeldedSurfaces& w, Mesh& mesh) {
    const Lines& lines = cx.lines;
    const std::vector<std::int64_t> kept = boundingFaces(cx, r);
    for (std::int64_t s : kept) {
        const std::uint64_t id = static_cast<std::uint64_t>(s < 0 ? -s : s);
        std::optional<std::size_t> fi = h.tfaceIndex(id);
        if (!fi)
            return lines.failAt(r.line, "REGION " + r.name + " names TFACE " + std::to_string(id) +
                                            ", which the model does not define");
        Tface& f = h.tfaces[*fi];
        if (++f.regions > 2)
            return lines.failAt(r.line, "REGION " + r.name + " names TFACE " + std::to_string(id) +
                                            ", which already bounds two other regions (a patch has two sides)");
        const TsurfData& surf = surfaces[static_cast<std::size_t>(f.surfaceIndex)];
        const std::size_t b = w.base[static_cast<std::size_t>(f.surfaceIndex)];
        // Outward = away from the region: flip when the triangles turn towards it.
        const bool flip = (s > 0) != f.reversed;
        for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount; ++t) {
            std::uint32_t v[3];
            for (int q = 0; q < 3; ++q) {
                const std::uint32_t g = w.weld[b + surf.mesh.indices[3 * t + static_cast<std::size_t>(q)]];
                if (w.local[g] == std::numeric_limits<std::uint32_t>::max()) {
                    w.local[g] = static_cast<std::uint32_t>(mesh.positions.size());
                    mesh.positions.push_back(w.welded[g]);
                }
                v[q] = w.local[g];
            }
            if (flip) std::swap(v[1], v[2]);
            mesh.indices.insert(mesh.indices.end(), {v[0], v[1], v[2]});
        }
    }
    // Reset the shared map for the next region (only the entries this one set).
    for (std::int64_t s : kept) {
        const Tface& f = h.tfaces[*h.tfaceIndex(static_cast<std::uint64_t>(s < 0 ? -s : s))];
        const TsurfData& surf = surfaces[static_cast<std::size_t>(f.surfaceIndex)];
        const std::size_t b = w.base[static_cast<std::size_t>(f.surfaceIndex)];
        for (std::size_t t = 3 * f.firstTriangle; t < 3 * (f.firstTriangle + f.triangleCount); ++t)
            w.local[w.weld[b + surf.mesh.indices[t]]] = std::numeric_limits<std::uint32_t>::max();
    }
    return {};
}

// One closed body per region other than the Universe; returns how many.
Result<std::size_t> addRegionBodies(Context& cx, std::size_t startLine, const std::string& where,
                                    const std::vector<TsurfData>& surfaces, Model3dHeader& h) {
    WeldedSurfaces w;
    if (Status s = weldSurfaces(cx.lines, startLine, where, surfaces, w); !s) return s.error();
    std::size_t bodies = 0;
    for (const Region& r : h.regions) {
        if (r.name == "Universe") continue;
        Part part;
        part.name = r.name;
        part.kind = PartKind::Body;
        if (Status s = regionShell(cx, r, surfaces, h, w, part.mesh); !s) return s.error();
        if (part.mesh.indices.empty()) {
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
    return bodies;
}

}  // namespace

Status readModel3d(Context& cx, std::size_t startLine) {
    Lines& lines = cx.lines;
    ObjectInfo info;
    info.crs = cx.fileCrs;
    Model3dHeader h;
    auto own = [&](Lines::Statement& st, bool& handled) { return h.readKeyword(lines, st, handled); };
    if (Status s = readObjectBody(cx, info, "Model3d header", startLine, own); !s) return s;
    const std::string where = "the Model3d that starts on line " + std::to_string(startLine);
    if (h.tfaces.empty()) return lines.failAt(startLine, where + " has no TFACE");
    if (Status s = h.indexTfaces(lines); !s) return s;
    std::vector<TsurfData> surfaces;
    std::vector<int> surfaceOfName;
    if (Status s = readSurfaces(cx, h.tsurfNames, where, surfaces, surfaceOfName); !s) return s;
    if (Status s = placePatches(cx, info.crs, surfaces, surfaceOfName, h); !s) return s;
    h.assignLayers();
    auto bodies = addRegionBodies(cx, startLine, where, surfaces, h);
    if (!bodies) return bodies.error();
    if (bodies.value() == 0 && !h.regions.empty())
        cx.warn(startLine, where + " defines no region other than the Universe");
    cx.declaredVolumes = cx.declaredVolumes || bodies.value() > 0;
    if (!info.name.empty()) cx.model.notes["gocad_model3d"] = info.name;
    for (TsurfData& s : surfaces) addTsurfPart(cx, std::move(s));
    return {};
}

}  // namespace geoslice::gocad
