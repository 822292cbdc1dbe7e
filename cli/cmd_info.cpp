// geoslice info [--json] [--drillholes SIDECAR] FILE...: parts, triangles, bounds (world and
// lon/lat), CRS, the validation report and the drillhole database (a <stem>.drillholes.json
// beside the model, or --drillholes): holes, stations, intervals, which column was read as
// what, every warning. Exits 1 when a file fails to load or has validation errors, or when
// the drillhole database cannot be loaded.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "cli/commands.hpp"
#include "model/drillholes/drillholes.hpp"
#include "model/io/loaders.hpp"
#include "model/json_text.hpp"

namespace geoslice::cli {
namespace {

using json = nlohmann::ordered_json;

const char* severityName(ValidationIssue::Severity s) {
    switch (s) {
        case ValidationIssue::Severity::Note:
            return "note";
        case ValidationIssue::Severity::Warning:
            return "warning";
        case ValidationIssue::Severity::Error:
            return "error";
    }
    return "error";
}

json partJson(const Model& m, const Part& p) {
    const MeshReport& r = p.report;
    json j = {{"name", p.name},
              {"record", p.record},
              {"triangles", r.triangles},
              {"vertices", r.vertices},
              {"closed", r.closed},
              {"consistently_oriented", r.consistentlyOriented},
              {"components", r.components},
              {"boundary_edges", r.boundaryEdges},
              {"non_manifold_edges", r.nonManifoldEdges},
              {"inconsistent_edges", r.inconsistentEdges},
              {"degenerate_triangles", r.degenerateTriangles},
              {"duplicate_triangles", r.duplicateTriangles},
              {"non_finite_vertices", r.nonFiniteVertices}};
    if (const AttributeRecord* rec = m.attributes.find(p.record)) {
        j["colour"] = formatColour(rec->colour);
        j["colour_source"] = rec->colourSource.empty() ? "default" : rec->colourSource;
        j["name_source"] = rec->nameSource.empty() ? "file" : rec->nameSource;
    }
    if (p.kind == PartKind::Body) {
        j["volume_m3"] = r.signedVolume;
        j["flipped"] = r.flipped;
        j["nesting_depth"] = r.nestingDepth;
        j["parent"] = r.parent >= 0 ? json(m.bodies[static_cast<std::size_t>(r.parent)].name) : json(nullptr);
    }
    return j;
}

// Lon/lat box of the model's map footprint (model/crs/crs.hpp lonLatBoxOf, as the API's
// lonlatBounds), projected CRS only.
std::optional<std::pair<glm::dvec2, glm::dvec2>> lonLatBounds(const Model& m, const Aabb& b) {
    if (!m.crs.isProjected() || !b.valid()) return std::nullopt;
    auto box = lonLatBoxOf(m.crs, {b.min.x, b.min.y}, {b.max.x, b.max.y});
    if (!box) return std::nullopt;
    return std::make_pair(glm::dvec2(box->west, box->south), glm::dvec2(box->east, box->north));
}

json modelJson(const std::string& file, const Model& m) {
    Aabb b = m.bounds();
    json j;
    j["file"] = file;
    j["name"] = m.name;
    j["crs"] = {{"id", m.crs.id()}, {"name", m.crs.name()}};
    if (!m.crs.isLocal()) j["crs"]["geographic"] = m.crs.geographicId();
    j["axes"] = "x easting, y northing, z elevation up; metres";
    j["triangles"] = m.triangleCount();
    j["origin"] = {m.origin.x, m.origin.y, m.origin.z};
    j["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
    if (auto ll = lonLatBounds(m, b))
        j["lonlat_bounds"] = {
            {"min", {ll->first.x, ll->first.y}}, {"max", {ll->second.x, ll->second.y}}, {"crs", m.crs.geographicId()}};
    j["bodies"] = json::array();
    for (const auto& p : m.bodies) j["bodies"].push_back(partJson(m, p));
    j["surfaces"] = json::array();
    for (const auto& p : m.surfaces) j["surfaces"].push_back(partJson(m, p));
    j["grids"] = json::array();
    for (const Grid& g : m.grids) {
        json gj = {{"name", g.name},
                   {"type", g.type},
                   {"dims", {g.dims[0], g.dims[1], g.dims[2]}},
                   {"samples", g.sampleCount()},
                   {"cell_centred", g.cellCentred}};
        if (g.points.empty()) {
            gj["origin"] = {g.origin.x, g.origin.y, g.origin.z};
            gj["steps"] = json::array();
            for (const auto& s : g.step) gj["steps"].push_back({s.x, s.y, s.z});
        } else {
            gj["points"] = g.points.size();
        }
        Aabb gb = g.bounds();
        if (gb.valid())
            gj["bounds"] = {{"min", {gb.min.x, gb.min.y, gb.min.z}}, {"max", {gb.max.x, gb.max.y, gb.max.z}}};
        gj["properties"] = json::array();
        for (const GridProperty& p : g.properties) {
            std::size_t noData = 0;
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (float v : p.values) {
                if (std::isnan(v)) {
                    ++noData;
                    continue;
                }
                lo = std::min(lo, double(v));
                hi = std::max(hi, double(v));
            }
            json pj = {{"name", p.name}, {"unit", p.unit}, {"values", p.values.size()}, {"no_data_samples", noData}};
            pj["no_data_value"] = p.noDataValue ? json(*p.noDataValue) : json(nullptr);
            if (lo <= hi) pj["range"] = {lo, hi};
            gj["properties"].push_back(std::move(pj));
        }
        j["grids"].push_back(std::move(gj));
    }
    j["lines"] = json::array();
    for (const Polyline& l : m.lines) {
        double length = 0.0;
        for (std::size_t s = 0; s + 1 < l.segments.size(); s += 2)
            length += glm::distance(l.points[l.segments[s]], l.points[l.segments[s + 1]]);
        j["lines"].push_back({{"name", l.name},
                              {"record", l.record},
                              {"points", l.points.size()},
                              {"segments", l.segments.size() / 2},
                              {"length_m", length},
                              {"properties", l.propertyNames}});
    }
    j["attributes"] = m.attributes.toJson()["records"];
    j["notes"] = m.notes;
    j["issues"] = json::array();
    for (const auto& i : m.validation.issues)
        j["issues"].push_back({{"severity", severityName(i.severity)}, {"part", i.part}, {"message", i.message}});
    j["ok"] = !m.validation.hasErrors();
    return j;
}

json drillholesJson(const DrillholeDatabase& db) {
    json j;
    j["source"] = db.source;
    j["crs"] = db.crs.empty() ? json(nullptr) : json(db.crs);
    if (!db.conversion.empty()) j["converted"] = db.conversion;
    j["holes"] = db.holes.size();
    j["stations"] = db.stationCount();
    j["tables"] = json::array();
    for (const DrillholeTableInfo& t : db.tables) {
        json tj = {{"kind", t.kind}, {"name", t.name}, {"file", t.file}, {"rows", t.rows}, {"rows_used", t.rowsUsed}};
        if (t.dip) tj["dip"] = dipConventionName(*t.dip);
        tj["columns"] = json::array();
        for (const ColumnUse& c : t.columns)
            tj["columns"].push_back({{"header", c.header}, {"role", c.role}, {"how", c.how}});
        j["tables"].push_back(std::move(tj));
    }
    j["intervals"] = json::array();
    for (const IntervalTable& t : db.intervals) {
        json tj = {{"name", t.name}, {"file", t.file}, {"intervals", t.size()}, {"columns", json::array()}};
        for (const IntervalColumn& c : t.columns)
            tj["columns"].push_back({{"name", c.name}, {"type", c.numeric ? "number" : "text"}, {"unit", c.unit}});
        j["intervals"].push_back(std::move(tj));
    }
    std::map<std::string, std::size_t> methods;
    for (const Drillhole& h : db.holes) ++methods[h.path.method];
    j["desurvey"] = methods;
    j["warnings"] = json::array();
    for (const DrillholeIssue& w : db.warnings)
        j["warnings"].push_back({{"file", w.file}, {"row", w.row}, {"hole", w.hole}, {"message", w.message}});
    return j;
}

void printDrillholes(const json& d) {
    if (d.contains("error")) {
        std::printf("  drillholes %s: %s\n", d["source"].get<std::string>().c_str(),
                    d["error"]["message"].get<std::string>().c_str());
        return;
    }
    std::printf("  drillholes %s: %zu holes, %zu survey stations, CRS %s\n", d["source"].get<std::string>().c_str(),
                d["holes"].get<std::size_t>(), d["stations"].get<std::size_t>(),
                d["crs"].is_null() ? "not stated" : d["crs"].get<std::string>().c_str());
    for (const auto& t : d["tables"]) {
        std::printf("    %-8s %-16s %-24s %zu rows, %zu used", t["kind"].get<std::string>().c_str(),
                    t["name"].get<std::string>().c_str(), t["file"].get<std::string>().c_str(),
                    t["rows"].get<std::size_t>(), t["rows_used"].get<std::size_t>());
        if (t.contains("dip")) std::printf(", dip %s", t["dip"].get<std::string>().c_str());
        std::printf("\n      columns:");
        const char* sep = " ";
        for (const auto& c : t["columns"]) {
            std::printf("%s'%s' as %s", sep, c["header"].get<std::string>().c_str(),
                        c["role"].get<std::string>().c_str());
            if (!c["how"].get<std::string>().empty()) std::printf(" (%s)", c["how"].get<std::string>().c_str());
            sep = ", ";
        }
        std::printf("\n");
    }
    for (const auto& t : d["intervals"]) {
        std::printf("    intervals %-16s %zu intervals;", t["name"].get<std::string>().c_str(),
                    t["intervals"].get<std::size_t>());
        for (const auto& c : t["columns"]) {
            std::printf(" %s (%s", c["name"].get<std::string>().c_str(), c["type"].get<std::string>().c_str());
            if (!c["unit"].get<std::string>().empty()) std::printf(", %s", c["unit"].get<std::string>().c_str());
            std::printf(")");
        }
        std::printf("\n");
    }
    for (const auto& [method, n] : d["desurvey"].items())
        std::printf("    desurvey %s: %zu holes\n", method.c_str(), n.get<std::size_t>());
    for (const auto& w : d["warnings"]) {
        std::printf("    warning  %s", w["file"].get<std::string>().c_str());
        if (w["row"].get<std::size_t>()) std::printf(" row %zu", w["row"].get<std::size_t>());
        if (!w["hole"].get<std::string>().empty()) std::printf(", hole '%s'", w["hole"].get<std::string>().c_str());
        std::printf(": %s\n", w["message"].get<std::string>().c_str());
    }
    std::printf("    drillholes %zu warnings\n", d["warnings"].size());
}

void printText(const json& j) {
    std::printf("%s: %s\n", j["file"].get<std::string>().c_str(), j["name"].get<std::string>().c_str());
    if (j["crs"]["id"] == "local")
        std::printf("  CRS        %s\n", j["crs"]["name"].get<std::string>().c_str());
    else
        std::printf("  CRS        %s (%s)\n", j["crs"]["id"].get<std::string>().c_str(),
                    j["crs"]["name"].get<std::string>().c_str());
    for (const auto& [k, v] : j["notes"].items())
        std::printf("  note       %s: %s\n", k.c_str(), v.get<std::string>().c_str());
    std::printf("  parts      %zu bodies, %zu surfaces, %zu triangles, %zu grids, %zu lines\n", j["bodies"].size(),
                j["surfaces"].size(), j["triangles"].get<std::size_t>(), j["grids"].size(), j["lines"].size());
    const auto& mn = j["bounds"]["min"];
    const auto& mx = j["bounds"]["max"];
    std::printf("  bounds     x %.3f .. %.3f  y %.3f .. %.3f  z %.3f .. %.3f (m, easting/northing/elevation)\n",
                mn[0].get<double>(), mx[0].get<double>(), mn[1].get<double>(), mx[1].get<double>(), mn[2].get<double>(),
                mx[2].get<double>());
    if (j.contains("lonlat_bounds"))
        std::printf("  lon/lat    %.6f .. %.6f E, %.6f .. %.6f N (%s)\n", j["lonlat_bounds"]["min"][0].get<double>(),
                    j["lonlat_bounds"]["max"][0].get<double>(), j["lonlat_bounds"]["min"][1].get<double>(),
                    j["lonlat_bounds"]["max"][1].get<double>(), j["lonlat_bounds"]["crs"].get<std::string>().c_str());
    for (const char* list : {"bodies", "surfaces"}) {
        for (const auto& p : j[list]) {
            std::printf("  %-8s %-48s record %-4u %9zu tri  %s", list[0] == 'b' ? "body" : "surface",
                        p["name"].get<std::string>().c_str(), p["record"].get<unsigned>(),
                        p["triangles"].get<std::size_t>(), p["closed"].get<bool>() ? "closed" : "open");
            if (p.contains("volume_m3"))
                std::printf("  %.4g m3  depth %d", p["volume_m3"].get<double>(), p["nesting_depth"].get<int>());
            if (p.contains("colour"))
                std::printf("  colour %s: %s; name: %s", p["colour"].get<std::string>().c_str(),
                            p["colour_source"].get<std::string>().c_str(), p["name_source"].get<std::string>().c_str());
            std::printf("\n");
        }
    }
    for (const auto& g : j["grids"]) {
        std::printf("  grid     %-48s %s %zu x %zu x %zu%s", g["name"].get<std::string>().c_str(),
                    g["type"].get<std::string>().c_str(), g["dims"][0].get<std::size_t>(),
                    g["dims"][1].get<std::size_t>(), g["dims"][2].get<std::size_t>(),
                    g["cell_centred"].get<bool>() ? " (cell-centred properties)" : "");
        if (g.contains("origin")) {
            const auto& o = g["origin"];
            std::printf("  origin %.3f %.3f %.3f  steps", o[0].get<double>(), o[1].get<double>(), o[2].get<double>());
            for (const auto& s : g["steps"])
                std::printf(" (%.4g %.4g %.4g)", s[0].get<double>(), s[1].get<double>(), s[2].get<double>());
        } else {
            std::printf("  %zu points", g["points"].get<std::size_t>());
        }
        std::printf("\n");
        for (const auto& p : g["properties"]) {
            std::printf("    property %-32s %zu values, %zu no-data", p["name"].get<std::string>().c_str(),
                        p["values"].get<std::size_t>(), p["no_data_samples"].get<std::size_t>());
            if (!p["no_data_value"].is_null()) std::printf(" (no-data value %g)", p["no_data_value"].get<double>());
            if (p.contains("range"))
                std::printf(", range %g .. %g", p["range"][0].get<double>(), p["range"][1].get<double>());
            std::printf("\n");
        }
    }
    for (const auto& l : j["lines"])
        std::printf("  line     %-48s record %-4u %zu points, %zu segments, %.3f m\n",
                    l["name"].get<std::string>().c_str(), l["record"].get<unsigned>(), l["points"].get<std::size_t>(),
                    l["segments"].get<std::size_t>(), l["length_m"].get<double>());
    std::size_t errors = 0, warnings = 0;
    for (const auto& i : j["issues"]) {
        std::string sev = i["severity"];
        errors += sev == "error";
        warnings += sev == "warning";
        std::printf("  %-8s %s: %s\n", sev.c_str(), i["part"].get<std::string>().c_str(),
                    i["message"].get<std::string>().c_str());
    }
    std::printf("  validation %zu errors, %zu warnings\n", errors, warnings);
    if (j.contains("drillholes")) printDrillholes(j["drillholes"]);
}

}  // namespace

void addInfo(CLI::App& app, int& exitCode) {
    auto files = std::make_shared<std::vector<std::string>>();
    auto asJson = std::make_shared<bool>(false);
    auto load = std::make_shared<LoadOptions>();
    CLI::App* cmd = app.add_subcommand("info", "Describe and validate model files");
    cmd->add_option("FILE", *files,
                    "Model files (.glb .gltf .obj .vtu, GOCAD .ts .ml .so .vo .sg .pl .gp, Geo3DML .xml)")
        ->required();
    cmd->add_flag("--json", *asJson, "One JSON document (an array when several files are given)");
    addLoadOptions(cmd, *load);
    auto drillholes = std::make_shared<std::string>();
    cmd->add_option("--drillholes", *drillholes,
                    "drillhole database: a sidecar JSON or a folder of collar.csv, survey.csv and interval tables "
                    "(default: the <stem>.drillholes.json sidecar beside the model); docs/drillholes.md");
    cmd->callback([files, asJson, load, drillholes, &exitCode] {
        json all = json::array();
        for (const auto& f : *files) {
            auto m = loadModel(f, *load);
            if (!m) {
                std::fprintf(stderr, "geoslice info: %s\n", m.error().message.c_str());
                all.push_back({{"file", f},
                               {"ok", false},
                               {"error", {{"code", errorCodeName(m.error().code)}, {"message", m.error().message}}}});
                exitCode = 1;
                continue;
            }
            json j = modelJson(f, m.value());
            if (!j["ok"].get<bool>()) exitCode = 1;
            const std::string dh = drillholes->empty() ? drillholeSidecarFor(f) : *drillholes;
            if (!dh.empty()) {
                auto db = loadDrillholes(dh);
                if (db) {
                    // Placed as the server places them (converted to the model's CRS when theirs differs).
                    if (auto s = placeDrillholes(db.value(), m.value().crs, m.value().bounds()); !s) db = s.error();
                }
                if (db) {
                    j["drillholes"] = drillholesJson(db.value());
                } else {
                    std::fprintf(stderr, "geoslice info: %s\n", db.error().message.c_str());
                    j["drillholes"] = {
                        {"source", dh},
                        {"error", {{"code", errorCodeName(db.error().code)}, {"message", db.error().message}}}};
                    exitCode = 1;
                }
            }
            if (!*asJson) printText(j);
            all.push_back(std::move(j));
        }
        if (*asJson) std::printf("%s\n", jsonText(all.size() == 1 ? all[0] : all, 2).c_str());
    });
}

}  // namespace geoslice::cli
