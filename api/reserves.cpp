#include "api/reserves.hpp"

#include <algorithm>
#include <cctype>
#include <map>

#include "api/plan.hpp"

namespace geoslice::api {
namespace {

using J = nlohmann::ordered_json;

J optional(const std::optional<double>& v) { return v ? J(*v) : J(nullptr); }

struct Totals {
    std::size_t bodies = 0, withTonnage = 0;
    double netVolume = 0.0, tonnage = 0.0;
    std::map<std::string, double> metal;  // unit -> amount
};

Totals totalsOf(const Reserves& r) {
    Totals t;
    for (const BodyReserves& b : r.bodies) {
        ++t.bodies;
        t.netVolume += b.netVolume;
        if (b.tonnage) {
            ++t.withTonnage;
            t.tonnage += *b.tonnage;
        }
        if (b.metal) t.metal[b.metalUnit] += *b.metal;
    }
    return t;
}

const AttributeRecord* recordOf(const Model& m, RecordId id) { return m.attributes.find(id); }

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

}  // namespace

J reservesJson(const Model& model, const Reserves& r, const std::string& modelLabel) {
    J bodies = J::array();
    for (const BodyReserves& b : r.bodies) {
        const AttributeRecord* rec = recordOf(model, b.record);
        bodies.push_back({{"body", model.bodies[b.body].name},
                          {"record", b.record},
                          {"record_name", rec ? rec->name : std::string()},
                          {"lithology", rec ? rec->lithology : std::string()},
                          {"gross_volume_m3", b.grossVolume},
                          {"net_volume_m3", b.netVolume},
                          {"density_t_per_m3", optional(b.density)},
                          {"tonnage_t", optional(b.tonnage)},
                          {"grade", optional(b.grade)},
                          {"grade_unit", b.gradeUnit},
                          {"metal", optional(b.metal)},
                          {"metal_unit", b.metalUnit}});
    }
    const Totals t = totalsOf(r);
    J metal = J::array();
    for (const auto& [unit, amount] : t.metal) metal.push_back({{"unit", unit}, {"amount", amount}});
    return J{{"model", modelLabel},
             {"plane",
              r.plane ? J::array({r.plane->normal.x, r.plane->normal.y, r.plane->normal.z, r.plane->d}) : J(nullptr)},
             {"method",
              "divergence theorem over each closed shell; net = gross minus directly nested "
              "bodies; with a plane, the shell clipped to the kept side (reference point on "
              "the plane, so the cap adds zero)"},
             {"bodies", std::move(bodies)},
             {"totals",
              {{"bodies", t.bodies},
               {"net_volume_m3", t.netVolume},
               {"tonnage_t", t.withTonnage ? J(t.tonnage) : J(nullptr)},
               {"bodies_with_tonnage", t.withTonnage},
               {"metal", std::move(metal)}}},
             {"skipped_open_bodies", r.skippedOpenBodies}};
}

std::string reservesCsv(const Model& model, const Reserves& r) {
    std::string s =
        "body,record,record_name,lithology,gross_volume_m3,net_volume_m3,density_t_per_m3,tonnage_t,grade,grade_unit,"
        "metal,metal_unit\n";
    for (const BodyReserves& b : r.bodies) {
        const AttributeRecord* rec = recordOf(model, b.record);
        s += csvField(model.bodies[b.body].name) + ',' + std::to_string(b.record) + ',' +
             csvField(rec ? rec->name : std::string()) + ',' + csvField(rec ? rec->lithology : std::string()) + ',' +
             formatNumber(b.grossVolume) + ',' + formatNumber(b.netVolume) + ',' + csvNumber(b.density) + ',' +
             csvNumber(b.tonnage) + ',' + csvNumber(b.grade) + ',' + csvField(b.gradeUnit) + ',' + csvNumber(b.metal) +
             ',' + csvField(b.metalUnit) + '\n';
    }
    const Totals t = totalsOf(r);
    const bool oneUnit = t.metal.size() == 1;
    s += "(total),,,,," + formatNumber(t.netVolume) + ",," + (t.withTonnage ? formatNumber(t.tonnage) : std::string()) +
         ",,," + (oneUnit ? formatNumber(t.metal.begin()->second) : std::string()) + ',' +
         (oneUnit ? csvField(t.metal.begin()->first) : std::string()) + '\n';
    return s;
}

std::string ReservesRequest::canonical() const {
    std::string s = "whole";
    if (plane) {
        const double v[4] = {plane->normal.x, plane->normal.y, plane->normal.z, plane->d};
        s = "plane=";
        for (int i = 0; i < 4; ++i) s += (i ? "," : "") + formatNumber(v[i]);
    }
    if (cutoffs) {
        s += "|cutoffs=";
        for (std::size_t i = 0; i < cutoffs->size(); ++i) s += (i ? "," : "") + formatNumber((*cutoffs)[i]);
        s += "|property=" + property;
    }
    return s + (csv ? "|csv" : "|json");
}

Result<ReservesRequest> parseReservesRequest(const Params& params, bool csvPath) {
    if (auto s = checkKnownParams(params, {"plane", "format", "cutoffs", "property"}); !s) return s.error();
    ReservesRequest r;
    r.csv = csvPath;
    if (const auto f = param(params, "format")) {
        if (*f != "json" && *f != "csv")
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'format': '" + std::string(f->substr(0, 64)) + "' is not 'json' or 'csv'");
        if (csvPath && *f == "json")
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'format': 'json' conflicts with the path reserves.csv");
        r.csv = *f == "csv";
    }
    if (const auto p = param(params, "plane")) {
        // The same parser, normalisation and limits as a section's plane.
        auto def = parseSectionDef(Params{{"plane", std::string(*p)}}, "", Crs::local());
        if (!def) return def.error();
        r.plane = def.value().plane;
    }
    if (const auto c = param(params, "cutoffs")) {
        auto v = parseNumberList("cutoffs", *c, 0, 64);
        if (!v) return v.error();
        for (std::size_t i = 1; i < v.value().size(); ++i)
            if (!(v.value()[i] > v.value()[i - 1]))
                return makeError(ErrorCode::InvalidArgument, "parameter 'cutoffs': values must increase strictly");
        r.cutoffs = std::move(v.value());
    }
    if (const auto p = param(params, "property")) {
        if (!r.cutoffs)
            return makeError(ErrorCode::InvalidArgument,
                             "parameter 'property' needs 'cutoffs' (a grade-tonnage table)");
        r.property = std::string(p->substr(0, 128));
    }
    return r;
}

Result<std::string> gradeProperty(const Model& model, const std::string& requested) {
    if (!model.blocks)
        return makeError(ErrorCode::InvalidArgument,
                         "grade-tonnage tables need a block model (a <stem>.blocks.json or .blocks.csv sidecar, or "
                         "--blocks)");
    if (!requested.empty()) return requested;
    for (const BlockProperty& p : model.blocks->properties) {
        std::string n = p.name;
        std::transform(n.begin(), n.end(), n.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
        if (n != "density") return p.name;
    }
    return model.blocks->properties.front().name;
}

J gradeTonnageJson(const Model& model, const GradeTonnage& table) {
    J bodies = J::array();
    for (const BodyGradeTonnage& b : table.bodies) {
        J rows = J::array();
        for (const GradeTonnageRow& r : b.rows)
            rows.push_back({{"cutoff", r.cutoff},
                            {"cells", r.cells},
                            {"volume_m3", r.volume},
                            {"tonnage_t", optional(r.tonnage)},
                            {"mean_grade", optional(r.meanGrade)},
                            {"metal", optional(r.metal)},
                            {"metal_unit", r.metalUnit}});
        bodies.push_back({{"body", model.bodies[b.body].name},
                          {"record", b.record},
                          {"volume_m3", b.volume},
                          {"volume_without_grade_m3", b.volumeNoGrade},
                          {"density_source", b.densitySource},
                          {"rows", std::move(rows)}});
    }
    return J{{"property", table.property},
             {"unit", table.unit},
             {"cutoffs", table.cutoffs},
             {"plane", table.plane ? J::array({table.plane->normal.x, table.plane->normal.y, table.plane->normal.z,
                                               table.plane->d})
                                   : J(nullptr)},
             {"method",
              "exact cell ∩ body volumes (divergence theorem on the body clipped to each cell: 3D, then the section "
              "of the body on the cell's face, then the body's crossings of that face's edge); net of directly nested "
              "bodies; a row counts the cells whose grade >= its cut-off; with a plane, the body's part on the kept "
              "side closed by a fan of cap triangles on the plane, measured the same way"},
             {"bodies", std::move(bodies)}};
}

std::string gradeTonnageCsv(const Model& model, const GradeTonnage& table) {
    std::string s = "body,record,cutoff,cells,volume_m3,tonnage_t,mean_grade,grade_unit,metal,metal_unit\n";
    for (const BodyGradeTonnage& b : table.bodies)
        for (const GradeTonnageRow& r : b.rows)
            s += csvField(model.bodies[b.body].name) + ',' + std::to_string(b.record) + ',' + formatNumber(r.cutoff) +
                 ',' + std::to_string(r.cells) + ',' + formatNumber(r.volume) + ',' + csvNumber(r.tonnage) + ',' +
                 csvNumber(r.meanGrade) + ',' + csvField(table.unit) + ',' + csvNumber(r.metal) + ',' +
                 csvField(r.metalUnit) + '\n';
    return s;
}

}  // namespace geoslice::api
