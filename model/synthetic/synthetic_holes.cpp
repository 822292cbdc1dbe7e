// The demo mine's drillholes (model/synthetic/synthetic_holes.hpp).
#include "model/synthetic/synthetic_holes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace geoslice {
namespace {

std::uint64_t splitmix(std::uint64_t& s) {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
double uniform(std::uint64_t& s) { return double(splitmix(s) >> 11) * (1.0 / 9007199254740992.0); }

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// The age symbol in a record's age ("Late Triassic (T3x)" -> "T3x"), "ORE" for an orebody.
std::string codeOf(const AttributeRecord* r) {
    if (!r) return "";
    if (r->kind == "orebody") return "ORE";
    const auto open = r->age.rfind('('), close = r->age.rfind(')');
    if (open != std::string::npos && close != std::string::npos && close > open + 1)
        return r->age.substr(open + 1, close - open - 1);
    return r->name;
}

// A CSV cell: quoted when it holds a comma or a quote.
std::string cell(const std::string& s) {
    if (s.find_first_of(",\"") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

struct Interval {
    double from = 0.0, to = 0.0;
    RecordId record = kNoRecord;
};

}  // namespace

SyntheticHoleSources syntheticHoleSources(const Model& model, const std::function<double(double, double)>& topAt,
                                          const std::function<RecordId(const glm::dvec3&)>& recordAt,
                                          std::uint64_t seed) {
    const Aabb b = model.bounds();
    std::uint64_t rng = seed * 0x2545F4914F6CDD1Dull + 17;
    std::string collar = "hole_id,x,y,z,total_depth\n", survey = "hole_id,depth,azimuth,dip\n",
                lith = "hole_id,from,to,code,unit\n", assay = "hole_id,from,to,SiO2_pct\n";
    SyntheticHoleSources out;
    const double sx = b.max.x - b.min.x, sy = b.max.y - b.min.y;
    int number = 0;
    for (int k = 0; k < 32; ++k) {
        const bool deviated = k >= 24;
        double x, y;
        if (!deviated) {
            x = b.min.x + sx * (0.1 + 0.8 * ((k % 6) + 0.2 + 0.6 * uniform(rng)) / 6.0);
            y = b.min.y + sy * (0.1 + 0.8 * ((k / 6) + 0.2 + 0.6 * uniform(rng)) / 4.0);
            // The third row is a fence along the model's middle northing (within 20 m), which the
            // demo's default east-west section shows.
            if (k / 6 == 2) y = 0.5 * (b.min.y + b.max.y) + 40.0 * (uniform(rng) - 0.5);
        } else {
            x = b.min.x + sx * (0.3 + 0.4 * uniform(rng));
            y = b.min.y + sy * (0.3 + 0.4 * uniform(rng));
        }
        const double z = topAt(x, y);
        if (!std::isfinite(z)) continue;
        char id[16];
        std::snprintf(id, sizeof id, "DDH-%02d", ++number);
        const double length = std::floor(0.7 * (z - b.min.z));
        if (length < 30.0) continue;
        std::vector<SurveyStation> stations;
        if (deviated) {
            const double az0 = 360.0 * uniform(rng), turn = 40.0 * (uniform(rng) < 0.5 ? -1.0 : 1.0);
            for (double d = 0.0; d <= length; d += 30.0) {
                const double f = d / length;
                stations.push_back({d, std::fmod(az0 + turn * f + 360.0, 360.0), -60.0 - 20.0 * f * f});
            }
        } else {
            stations.push_back({0.0, 0.0, -90.0});
        }
        const glm::dvec3 c(std::round(x * 100.0) / 100.0, std::round(y * 100.0) / 100.0, std::round(z * 100.0) / 100.0);
        collar += std::string(id) + "," + fmt("%.2f", c.x) + "," + fmt("%.2f", c.y) + "," + fmt("%.2f", c.z) + "," +
                  fmt("%.1f", length) + "\n";
        for (const SurveyStation& s : stations)
            survey += std::string(id) + "," + fmt("%.1f", s.depth) + "," + fmt("%.2f", s.azimuth) + "," +
                      fmt("%.2f", s.dip) + "\n";
        const HolePath path = desurvey(c, stations, length);
        // Runs of one record, sampled at the middle of every metre.
        std::vector<Interval> runs;
        for (double d = 0.0; d < length; d += 1.0) {
            const RecordId r = recordAt(path.at(d + 0.5));
            if (!runs.empty() && runs.back().record == r && runs.back().to == d)
                runs.back().to = d + 1.0;
            else
                runs.push_back({d, d + 1.0, r});
        }
        runs.erase(std::remove_if(runs.begin(), runs.end(), [](const Interval& i) { return i.record == kNoRecord; }),
                   runs.end());
        std::vector<RecordId> logged;
        for (const Interval& i : runs) logged.push_back(i.record);
        if ((number == 4 || number == 12 || number == 20) && runs.size() >= 3) {
            logged[1] = runs[2].record;
            out.disagreements.push_back(std::string(id) + " " + fmt("%g", runs[1].from) + "-" + fmt("%g", runs[1].to) +
                                        " m: logged " + codeOf(model.attributes.find(logged[1])) + ", model " +
                                        codeOf(model.attributes.find(runs[1].record)));
        }
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const AttributeRecord* r = model.attributes.find(logged[i]);
            lith += std::string(id) + "," + fmt("%g", runs[i].from) + "," + fmt("%g", runs[i].to) + "," +
                    cell(codeOf(r)) + "," + cell(r ? r->name : std::string()) + "\n";
        }
        for (double d = 0.0; d + 10.0 <= length; d += 10.0) {
            const RecordId r = recordAt(path.at(d + 5.0));
            const AttributeRecord* a = model.attributes.find(r);
            if (!a) continue;
            const double level = a->kind == "orebody"                                  ? 98.6
                                 : a->lithology.find("sandstone") != std::string::npos ? 90.0
                                 : a->lithology.find("limestone") != std::string::npos ? 8.0
                                                                                       : 45.0;
            const double spread = a->kind == "orebody" ? 0.6 : 4.0;
            const double v = std::clamp(level + spread * (2.0 * uniform(rng) - 1.0), 0.0, 100.0);
            assay += std::string(id) + "," + fmt("%g", d) + "," + fmt("%g", d + 10.0) + "," + fmt("%.2f", v) + "\n";
        }
    }
    DrillholeSources& s = out.sources;
    s.source = "demo (generated drillholes)";
    s.crs = model.crs.id();
    s.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    s.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, DipConvention::NegativeDown};
    s.intervals.push_back({"lith", "lith.csv", lith, {}, {}, DipConvention::NegativeDown});
    s.intervals.push_back({"assay", "assay.csv", assay, {}, {{"SiO2_pct", "%"}}, DipConvention::NegativeDown});
    // The logged codes are age symbols (J2s, T3x, ORE), as a mine's logs are: map each to its
    // unit, as a real project's sidecar "units" does, so that the model can be checked
    // against the holes (api/drillhole_check.hpp).
    DrillholeUnitMap units;
    units.table = "lith";
    units.column = "code";
    std::map<std::string, std::string> byCode;
    for (const auto& [id, r] : model.attributes.records()) byCode.emplace(codeOf(&r), r.name);
    units.map.assign(byCode.begin(), byCode.end());
    s.units = std::move(units);
    return out;
}

}  // namespace geoslice
