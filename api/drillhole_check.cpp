#include "api/drillhole_check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <unordered_map>

#include "api/params.hpp"

namespace geoslice::api {
namespace {

using J = nlohmann::ordered_json;

// Two logged intervals touch (a contact) when the gap between them is at most this (metres).
constexpr double kTouchM = 1e-6;

std::string lower(std::string_view s) {
    std::string o(s);
    for (char& c : o) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return o;
}

std::string normalised(std::string_view s) {
    std::string o;
    for (char c : s)
        if (std::isalnum(static_cast<unsigned char>(c)))
            o += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return o;
}

// RFC 4180: quoted when it holds a comma, quote, CR or LF; quotes doubled.
std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c;
    }
    return q + "\"";
}

std::string csvNumber(const std::optional<double>& v) { return v ? formatNumber(*v) : std::string(); }

J number(const std::optional<double>& v) { return v && std::isfinite(*v) ? J(*v) : J(nullptr); }
J share(double agreed, double logged) { return logged > 0.0 ? J(agreed / logged) : J(nullptr); }

// A model unit: the record, or the body itself when it has none.
std::int64_t unitOf(const Model& m, std::size_t body) {
    const RecordId r = m.bodies[body].record;
    return r != kNoRecord ? std::int64_t(r) : (std::int64_t(1) << 40) + std::int64_t(body);
}

struct Units {
    std::unordered_map<std::string, std::int64_t> byKey;  // lower-case name or id -> unit
    std::map<std::int64_t, std::string> name;             // unit -> display name
    std::vector<std::string> listed;                      // display names, body order
};

Units modelUnits(const Model& m) {
    Units u;
    for (std::size_t b = 0; b < m.bodies.size(); ++b) {
        const std::int64_t id = unitOf(m, b);
        const AttributeRecord* rec = m.bodies[b].record != kNoRecord ? m.attributes.find(m.bodies[b].record) : nullptr;
        if (!u.name.count(id)) {
            u.name[id] = rec && !rec->name.empty() ? rec->name : m.bodies[b].name;
            u.listed.push_back(u.name[id]);
        }
        if (rec && !rec->name.empty()) u.byKey.emplace(lower(rec->name), id);
        u.byKey.emplace(lower(m.bodies[b].name), id);
        if (m.bodies[b].record != kNoRecord) u.byKey.emplace(std::to_string(m.bodies[b].record), id);
    }
    return u;
}

// What a code resolves to: a model unit, a mapped name the model lacks, or nothing.
struct Resolved {
    enum Kind { None, Model, Lacking } kind = None;
    std::int64_t unit = 0;
    std::string name;
};

// A code resolved through the sidecar's map (when it has one) and the model's unit names.
Resolved resolveCode(const Units& units, const DrillholeDatabase& db, const std::string& code) {
    Resolved r;
    const bool mapped = db.units && !db.units->map.empty();
    std::string target = code;
    if (mapped) {
        target.clear();
        for (const auto& [k, v] : db.units->map)
            if (lower(k) == lower(code)) {
                target = v;
                break;
            }
        if (target.empty()) return r;  // not in the map
    }
    if (const auto u = units.byKey.find(lower(target)); u != units.byKey.end()) {
        r.kind = Resolved::Model;
        r.unit = u->second;
        r.name = units.name.at(u->second);
    } else if (mapped) {
        r.kind = Resolved::Lacking;
        r.name = target;
    }
    return r;
}

struct Run {
    double from, to;
    std::int64_t unit;
};

}  // namespace

Result<std::pair<std::size_t, std::size_t>> findCodeColumn(const DrillholeDatabase& db) {
    const DrillholeUnitMap none;
    const DrillholeUnitMap& u = db.units ? *db.units : none;
    static const std::vector<std::string> kNames = {"lith", "lithology", "litho", "rock", "rocktype", "rockcode",
                                                    "unit", "geology",   "geol",  "code", "lithcode"};
    std::string seen;
    for (std::size_t t = 0; t < db.intervals.size(); ++t) {
        const IntervalTable& tab = db.intervals[t];
        if (!u.table.empty() && lower(tab.name) != lower(u.table)) continue;
        for (std::size_t c = 0; c < tab.columns.size(); ++c) {
            const IntervalColumn& col = tab.columns[c];
            if (!u.column.empty()) {
                if (lower(col.name) == lower(u.column)) return std::make_pair(t, c);
                continue;
            }
            if (col.numeric) continue;
            if (std::find(kNames.begin(), kNames.end(), normalised(col.name)) != kNames.end())
                return std::make_pair(t, c);
        }
        seen += (seen.empty() ? "" : "; ") + tab.name + ":";
        for (const IntervalColumn& col : tab.columns) seen += " " + col.name + (col.numeric ? " (number)" : "");
    }
    std::string what = "no interval column of lithology codes";
    if (!u.table.empty() || !u.column.empty())
        what = "no interval table" + (u.table.empty() ? std::string() : " '" + u.table + "'") + " with a column" +
               (u.column.empty() ? std::string(" named like a lithology code") : " '" + u.column + "'");
    return makeError(ErrorCode::NotFound, db.source + ": " + what + " (tables: " + (seen.empty() ? "none" : seen) +
                                              "); name it in the sidecar's \"units\": {\"table\", \"column\"}");
}

Result<Borehole> traceHole(const BoreholeTracer& tracer, const DrillholeDatabase& db, const Drillhole& hole) {
    double to = std::isfinite(hole.totalDepth) ? hole.totalDepth : 0.0;
    const auto it = db.index.find(hole.id);
    if (it != db.index.end())
        for (const IntervalTable& t : db.intervals) {
            const auto lo = std::lower_bound(t.hole.begin(), t.hole.end(), it->second);
            for (auto k = std::size_t(lo - t.hole.begin()); k < t.size() && t.hole[k] == it->second; ++k)
                to = std::max(to, t.to[k]);
        }
    const HolePolyline line = holePolyline(hole.path, to);
    auto bh = tracer.tracePath(line);
    if (!bh) return makeError(bh.error().code, "hole '" + hole.id + "': " + bh.error().message);
    // Depths from the collar (the path's depth 0), not from the first surface hit.
    for (auto& iv : bh.value().intervals) {
        iv.fromCollar = iv.from;
        iv.toCollar = iv.to;
    }
    for (auto& c : bh.value().crossings) c.depthCollar = c.depth;
    return bh;
}

Result<DrillholeCheck> checkDrillholes(const Model& model, const DrillholeDatabase& db, const BoreholeTracer& tracer) {
    auto where = findCodeColumn(db);
    if (!where) return where.error();
    const IntervalTable& tab = db.intervals[where.value().first];
    const IntervalColumn& col = tab.columns[where.value().second];
    DrillholeCheck out;
    out.table = tab.name;
    out.column = col.name;
    out.sidecarMap = db.units && !db.units->map.empty();
    const Units units = modelUnits(model);

    // Codes -> units, once per distinct code.
    std::map<std::string, Resolved> resolved;  // code as written
    std::map<std::string, CodeUse> codeUse;
    std::map<std::string, std::size_t> lackingWarned;
    auto resolve = [&](const std::string& code) -> const Resolved& {
        auto [it, fresh] = resolved.try_emplace(code);
        if (!fresh) return it->second;
        it->second = resolveCode(units, db, code);
        if (it->second.kind == Resolved::Lacking) {
            it->second.unit = -1 - std::int64_t(lackingWarned.size());
            lackingWarned.emplace(it->second.name, 0);
        }
        return it->second;
    };

    std::vector<UnitAgreement> totals;
    auto totalFor = [&](std::vector<UnitAgreement>& list, const Resolved& r) -> UnitAgreement& {
        for (auto& a : list)
            if (a.unit == r.name && a.inModel == (r.kind == Resolved::Model)) return a;
        list.push_back(UnitAgreement{r.name, r.kind == Resolved::Model, 0.0, 0.0});
        return list.back();
    };

    std::size_t row = 0;  // the table is sorted by hole: one pass
    out.holes.reserve(db.holes.size());
    for (std::uint32_t h = 0; h < db.holes.size(); ++h) {
        const Drillhole& hole = db.holes[h];
        HoleCheck hc;
        hc.hole = hole.id;
        while (row < tab.size() && tab.hole[row] < h) ++row;
        std::size_t end = row;
        while (end < tab.size() && tab.hole[end] == h) ++end;
        auto traced = traceHole(tracer, db, hole);
        if (!traced) {
            hc.error = traced.error().message;
            out.warnings.push_back(hc.error);
            out.holes.push_back(std::move(hc));
            row = end;
            continue;
        }
        hc.model = std::move(traced).value();
        hc.tracedTo = hc.model.length;
        // The model's units down the hole, neighbours of one unit merged.
        std::vector<Run> runs;
        for (const BoreholeInterval& iv : hc.model.intervals) {
            const std::int64_t u = unitOf(model, iv.body);
            if (!runs.empty() && runs.back().unit == u && iv.from - runs.back().to <= kTouchM)
                runs.back().to = iv.to;
            else
                runs.push_back(Run{iv.from, iv.to, u});
        }
        const std::string* prevCode = nullptr;
        const Resolved* prevUnit = nullptr;
        std::size_t prevRow = 0;
        double prevTo = -1.0;
        for (std::size_t k = row; k < end; ++k) {
            const std::string& code = col.texts[k];
            const double f = tab.from[k], t = tab.to[k];
            if (code.empty()) {
                prevUnit = nullptr;
                continue;
            }
            const Resolved& r = resolve(code);
            CodeUse& use = codeUse[code];
            use.code = code;
            use.unit = r.name;
            use.inModel = r.kind == Resolved::Model;
            ++use.intervals;
            use.length += t - f;
            if (r.kind == Resolved::None) {
                hc.unmatched += t - f;
                prevUnit = nullptr;
                continue;
            }
            double agreed = 0.0;
            if (r.kind == Resolved::Model)
                for (const Run& run : runs)
                    if (run.unit == r.unit) agreed += std::max(0.0, std::min(t, run.to) - std::max(f, run.from));
            hc.logged += t - f;
            hc.agreed += agreed;
            UnitAgreement& hu = totalFor(hc.units, r);
            hu.logged += t - f;
            hu.agreed += agreed;
            UnitAgreement& tu = totalFor(totals, r);
            tu.logged += t - f;
            tu.agreed += agreed;
            // A logged contact: this interval touches the previous one and names another unit.
            if (prevUnit && std::abs(f - prevTo) <= kTouchM &&
                !(prevUnit->kind == r.kind && prevUnit->unit == r.unit && prevUnit->name == r.name)) {
                ContactCheck c;
                c.depth = 0.5 * (f + prevTo);
                c.codeAbove = *prevCode;
                c.codeBelow = code;
                c.unitAbove = prevUnit->name;
                c.unitBelow = r.name;
                c.rowAbove = prevRow;
                c.rowBelow = tab.row[k];
                if (prevUnit->kind == Resolved::Model && r.kind == Resolved::Model)
                    for (std::size_t j = 0; j + 1 < runs.size(); ++j) {
                        if (runs[j].unit != prevUnit->unit || runs[j + 1].unit != r.unit) continue;
                        if (runs[j + 1].from - runs[j].to > kTouchM) continue;
                        const double md = 0.5 * (runs[j].to + runs[j + 1].from);
                        if (!c.modelDepth || std::abs(md - c.depth) < std::abs(*c.modelDepth - c.depth))
                            c.modelDepth = md;
                    }
                if (c.modelDepth) c.distance = *c.modelDepth - c.depth;
                hc.contacts.push_back(std::move(c));
            }
            prevCode = &code;
            prevUnit = &r;
            prevRow = tab.row[k];
            prevTo = t;
        }
        row = end;
        out.holes.push_back(std::move(hc));
    }
    out.units = std::move(totals);
    for (auto& [code, use] : codeUse) out.codes.push_back(use);
    std::vector<std::string> unmatched;
    for (const CodeUse& c : out.codes)
        if (c.unit.empty()) unmatched.push_back(c.code);
    if (!unmatched.empty()) {
        std::string list;
        for (std::size_t i = 0; i < unmatched.size() && i < 20; ++i) list += (i ? ", " : "") + unmatched[i];
        if (unmatched.size() > 20) list += ", ... (" + std::to_string(unmatched.size()) + " in all)";
        out.warnings.push_back(std::to_string(unmatched.size()) + " code(s) of column '" + col.name +
                               "' name no unit of the model" +
                               (out.sidecarMap ? " and are not in the sidecar's units.map" : "") + ": " + list +
                               "; their intervals are left out of the shares (codes lists their lengths)");
    }
    for (const auto& [name, unused] : lackingWarned) {
        std::string listed;
        for (std::size_t i = 0; i < units.listed.size() && i < 30; ++i) listed += (i ? ", " : "") + units.listed[i];
        out.warnings.push_back("the sidecar's units.map names unit '" + name + "', which the model lacks (its units: " +
                               listed + "); its logged length counts as disagreeing");
    }
    return out;
}

J drillholeLogJson(const Model& model, const DrillholeDatabase& db, const Drillhole& hole, const Borehole& trace) {
    const auto holeIndex = db.index.at(hole.id);
    auto vec3 = [](const glm::dvec3& v) { return J::array({v.x, v.y, v.z}); };
    J stations = J::array(), path = J::array(), tables = J::array(), modelled = J::array();
    for (const SurveyStation& st : hole.stations)
        stations.push_back({{"depth_m", st.depth}, {"azimuth", st.azimuth}, {"dip", st.dip}});
    for (std::size_t i = 0; i < hole.path.depth.size(); ++i)
        path.push_back({{"depth_m", hole.path.depth[i]},
                        {"world", vec3(hole.path.position[i])},
                        {"direction", vec3(hole.path.direction[i])}});
    const auto codes = findCodeColumn(db);
    const Units units = modelUnits(model);
    for (std::size_t t = 0; t < db.intervals.size(); ++t) {
        const IntervalTable& tab = db.intervals[t];
        J cols = J::array();
        for (const IntervalColumn& c : tab.columns)
            cols.push_back({{"name", c.name}, {"unit", c.unit}, {"numeric", c.numeric}});
        const bool codeTable = codes && codes.value().first == t;
        J rows = J::array();
        const auto lo = std::lower_bound(tab.hole.begin(), tab.hole.end(), holeIndex);
        for (auto k = std::size_t(lo - tab.hole.begin()); k < tab.size() && tab.hole[k] == holeIndex; ++k) {
            J values = J::array();
            for (const IntervalColumn& c : tab.columns)
                values.push_back(c.numeric ? number(c.numbers[k]) : J(c.texts[k]));
            J row = {{"from_m", tab.from[k]}, {"to_m", tab.to[k]}, {"row", tab.row[k]}, {"values", std::move(values)}};
            if (codeTable) {
                const std::string& code = tab.columns[codes.value().second].texts[k];
                const Resolved r = code.empty() ? Resolved{} : resolveCode(units, db, code);
                row["unit"] = r.kind == Resolved::None ? J(nullptr) : J(r.name);
                row["unit_in_model"] = r.kind == Resolved::Model;
            }
            rows.push_back(std::move(row));
        }
        J tj = {{"name", tab.name}, {"file", tab.file}, {"columns", std::move(cols)}};
        if (codeTable) tj["code_column"] = tab.columns[codes.value().second].name;
        tj["intervals"] = std::move(rows);
        tables.push_back(std::move(tj));
    }
    for (const BoreholeInterval& iv : trace.intervals) {
        const AttributeRecord* rec = iv.record != kNoRecord ? model.attributes.find(iv.record) : nullptr;
        char colour[8] = "";
        if (rec) std::snprintf(colour, sizeof colour, "#%02x%02x%02x", rec->colour.r, rec->colour.g, rec->colour.b);
        modelled.push_back({{"from_m", iv.from},
                            {"to_m", iv.to},
                            {"unit", units.name.at(unitOf(model, iv.body))},
                            {"body", model.bodies[iv.body].name},
                            {"record", iv.record},
                            {"colour", rec ? J(colour) : J(nullptr)},
                            {"from_elevation_m", iv.fromElevation},
                            {"to_elevation_m", iv.toElevation}});
    }
    J crossings = J::array();
    for (const BoreholeCrossing& c : trace.crossings)
        crossings.push_back({{"depth_m", c.depth},
                             {"surface", model.surfaces[c.surface].name},
                             {"record", c.record},
                             {"elevation_m", c.elevation}});
    return {{"hole", hole.id},
            {"collar", vec3(hole.collar)},
            {"total_depth_m", number(hole.totalDepth)},
            {"desurvey", hole.path.method},
            {"axes",
             "world: x easting, y northing, z elevation, metres; depths in metres along the hole from the "
             "collar"},
            {"stations", std::move(stations)},
            {"path", std::move(path)},
            {"tables", std::move(tables)},
            {"model",
             {{"traced_to_m", trace.length}, {"intervals", std::move(modelled)}, {"crossings", std::move(crossings)}}}};
}

J drillholeCheckJson(const DrillholeCheck& c, const std::string& modelLabel, const std::string& drillholesLabel) {
    auto unitsJson = [](const std::vector<UnitAgreement>& list) {
        J a = J::array();
        for (const UnitAgreement& u : list)
            a.push_back({{"unit", u.unit},
                         {"in_model", u.inModel},
                         {"logged_m", u.logged},
                         {"agreed_m", u.agreed},
                         {"share", share(u.agreed, u.logged)}});
        return a;
    };
    double logged = 0.0, agreed = 0.0, maxAbs = 0.0;
    std::size_t contacts = 0, found = 0, traced = 0;
    std::vector<double> dist;
    J holes = J::array();
    for (const HoleCheck& h : c.holes) {
        J cs = J::array();
        for (const ContactCheck& k : h.contacts) {
            ++contacts;
            if (k.distance) {
                ++found;
                dist.push_back(std::abs(*k.distance));
                maxAbs = std::max(maxAbs, std::abs(*k.distance));
            }
            cs.push_back({{"depth_m", k.depth},
                          {"above", {{"code", k.codeAbove}, {"unit", k.unitAbove}, {"row", k.rowAbove}}},
                          {"below", {{"code", k.codeBelow}, {"unit", k.unitBelow}, {"row", k.rowBelow}}},
                          {"model_depth_m", number(k.modelDepth)},
                          {"distance_m", number(k.distance)}});
        }
        logged += h.logged;
        agreed += h.agreed;
        if (h.error.empty()) ++traced;
        J hj = {{"hole", h.hole},
                {"logged_m", h.logged},
                {"agreed_m", h.agreed},
                {"share", share(h.agreed, h.logged)},
                {"unmatched_m", h.unmatched},
                {"traced_to_m", h.tracedTo},
                {"units", unitsJson(h.units)},
                {"contacts", std::move(cs)}};
        if (!h.error.empty()) hj["error"] = h.error;
        holes.push_back(std::move(hj));
    }
    std::sort(dist.begin(), dist.end());
    J codes = J::array();
    for (const CodeUse& u : c.codes)
        codes.push_back({{"code", u.code},
                         {"unit", u.unit.empty() ? J(nullptr) : J(u.unit)},
                         {"in_model", u.inModel},
                         {"intervals", u.intervals},
                         {"length_m", u.length}});
    char method[400];
    std::snprintf(method, sizeof method,
                  "minimum-curvature legs cut into chords (sagitta <= %g m) cast as rays with the section engine's "
                  "rule; every boundary moved onto the arc in double precision against the plane of the face hit",
                  c.sagitta);
    return {{"model", modelLabel},
            {"drillholes", drillholesLabel},
            {"table", c.table},
            {"column", c.column},
            {"mapping", c.sidecarMap ? "the sidecar's units.map" : "codes name units (record or body name, record id)"},
            {"method", method},
            {"distance",
             "model depth - logged depth, metres along the hole (positive: the model's contact is "
             "deeper); null: the hole has no model contact between the same units"},
            {"summary",
             {{"holes", c.holes.size()},
              {"holes_traced", traced},
              {"logged_m", logged},
              {"agreed_m", agreed},
              {"share", share(agreed, logged)},
              {"contacts", contacts},
              {"contacts_found", found},
              {"median_abs_distance_m", dist.empty() ? J(nullptr) : J(dist[dist.size() / 2])},
              {"max_abs_distance_m", dist.empty() ? J(nullptr) : J(maxAbs)}}},
            {"units", unitsJson(c.units)},
            {"codes", std::move(codes)},
            {"holes", std::move(holes)},
            {"warnings", c.warnings}};
}

std::string drillholeCheckCsv(const DrillholeCheck& c, bool contacts) {
    std::string s;
    if (contacts) {
        s = "hole,depth_m,code_above,code_below,unit_above,unit_below,model_depth_m,distance_m\n";
        for (const HoleCheck& h : c.holes)
            for (const ContactCheck& k : h.contacts)
                s += csvField(h.hole) + ',' + formatNumber(k.depth) + ',' + csvField(k.codeAbove) + ',' +
                     csvField(k.codeBelow) + ',' + csvField(k.unitAbove) + ',' + csvField(k.unitBelow) + ',' +
                     csvNumber(k.modelDepth) + ',' + csvNumber(k.distance) + '\n';
        return s;
    }
    s = "hole,unit,in_model,logged_m,agreed_m,share\n";
    auto row = [&](const std::string& hole, const UnitAgreement& u) {
        s += csvField(hole) + ',' + csvField(u.unit) + ',' + (u.inModel ? "true" : "false") + ',' +
             formatNumber(u.logged) + ',' + formatNumber(u.agreed) + ',' +
             csvNumber(u.logged > 0.0 ? std::optional<double>(u.agreed / u.logged) : std::nullopt) + '\n';
    };
    for (const HoleCheck& h : c.holes)
        for (const UnitAgreement& u : h.units) row(h.hole, u);
    for (const UnitAgreement& u : c.units) row("*", u);
    return s;
}

}  // namespace geoslice::api
