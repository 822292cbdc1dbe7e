// The model checked against its drillholes (api/drillhole_check.hpp) on horizontal strata whose
// contacts along a hole are known in closed form: a straight inclined hole and two
// minimum-curvature arcs (constant dip rate in a vertical plane: a circular arc, on which the
// depth of elevation c is solved exactly). Logged exactly at the model's contacts: agreement
// 100 % and contact distances within 1e-9 m; logged contacts shifted by known amounts: the
// distances and shares are those amounts. Then the mapping: a sidecar map, a map naming a unit
// the model lacks (a warning), codes naming no unit (left out, listed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "api/drillhole_check.hpp"
#include "section/rays/borehole.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

constexpr double kPi = 3.14159265358979323846;
// Metres: contacts exact in double precision (regula falsi on the arc, double plane
// crossing); the goal of the check.
constexpr double kExactM = 1e-9;
// Strata: tops at z = 0, -100, -200, -300, base -400; 3 km x 3 km.
const std::vector<std::string> kUnits = {"Sandstone", "Shale", "Limestone", "Granite"};
const std::vector<double> kContactZ = {0.0, -100.0, -200.0, -300.0, -400.0};

Model strata() {
    std::vector<Part> parts;
    for (std::size_t i = 0; i < kUnits.size(); ++i)
        parts.push_back(makePart(kUnits[i], PartKind::Body, RecordId(10 * (i + 1)),
                                 boxMesh({-500.0, -500.0, kContactZ[i + 1]}, {2500.0, 2500.0, kContactZ[i]})));
    return modelOf(std::move(parts));
}

// A hole from (x, y, 10) along azimuth `az` whose dip goes linearly from a0 to a1 (degrees,
// negative down) over `len` m (two stations: minimum curvature is then a circular arc in the
// vertical plane of `az`; a0 == a1: straight). Depth where it reaches elevation c, exactly.
struct ArcHole {
    std::string id;
    double x, y, az, a0, a1, len;
    double depthAt(double c) const {
        const double z0 = 10.0, al0 = a0 * kPi / 180.0, al1 = a1 * kPi / 180.0;
        if (a0 == a1) return (z0 - c) / -std::sin(al0);
        const double k = (al1 - al0) / len;  // rad per metre
        // z(s) = z0 - (cos(al0 + k s) - cos al0) / k
        const double ca = std::cos(al0) + k * (z0 - c);
        const double al = -std::acos(ca);
        return (al - al0) / k;
    }
};

const std::vector<ArcHole> kHoles = {
    {"straight-60", 1000.0, 1000.0, 120.0, -60.0, -60.0, 700.0},
    {"arc-from-vertical", 900.0, 1100.0, 30.0, -90.0, -30.0, 700.0},
    {"arc-steepening", 1100.0, 900.0, 250.0, -50.0, -80.0, 800.0},
};

std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// The database text: collar, survey, and a lithology log with overburden (code OVB, in no
// unit) down to the first contact and then one interval per stratum; `shift[h][i]` moves
// logged contact i (1..3, between strata) of hole h down by that many metres.
DrillholeSources sources(const std::vector<std::vector<double>>& shift, const std::vector<std::string>& codes) {
    std::string collar = "hole,x,y,z,depth\n", survey = "hole,depth,azimuth,dip\n", lith = "hole,from,to,lith\n";
    for (std::size_t h = 0; h < kHoles.size(); ++h) {
        const ArcHole& a = kHoles[h];
        collar += a.id + "," + num(a.x) + "," + num(a.y) + ",10," + num(a.len) + "\n";
        survey += a.id + ",0," + num(a.az) + "," + num(a.a0) + "\n";
        survey += a.id + "," + num(a.len) + "," + num(a.az) + "," + num(a.a1) + "\n";
        std::vector<double> d;
        for (std::size_t i = 0; i < kContactZ.size(); ++i)
            d.push_back(a.depthAt(kContactZ[i]) + (shift.empty() ? 0.0 : shift[h][i]));
        lith += a.id + ",0," + num(d[0]) + ",OVB\n";
        for (std::size_t i = 0; i < kUnits.size(); ++i)
            lith += a.id + "," + num(d[i]) + "," + num(d[i + 1]) + "," + codes[i] + "\n";
    }
    DrillholeSources s;
    s.source = "strata test";
    s.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    s.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, {}};
    s.intervals.push_back({"lithology", "lithology.csv", lith, {}, {}, {}});
    return s;
}

struct Fixture {
    Model model = strata();
    std::unique_ptr<BoreholeTracer> tracer;
    Fixture() {
        auto t = BoreholeTracer::build(model);
        EXPECT_TRUE(t.ok()) << (t.ok() ? "" : t.error().message);
        tracer = std::move(t).value();
    }
    api::DrillholeCheck check(DrillholeSources src) {
        auto db = buildDrillholes(std::move(src));
        EXPECT_TRUE(db.ok()) << (db.ok() ? "" : db.error().message);
        EXPECT_TRUE(db->warnings.empty()) << db->warnings.front().text();
        auto c = api::checkDrillholes(model, db.value(), *tracer);
        EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
        return std::move(c).value();
    }
};

const std::vector<std::string> kLowerCodes = {"sandstone", "SHALE", "30", "granite"};  // 30: Limestone's record

}  // namespace

TEST(DrillholeCheck, ClosedFormHolesAgreeExactly) {
    Fixture f;
    const auto c = f.check(sources({}, {"sandstone", "SHALE", "limestone", "Granite"}));
    ASSERT_EQ(c.holes.size(), kHoles.size());
    EXPECT_EQ(c.table, "lithology");
    EXPECT_EQ(c.column, "lith");
    for (std::size_t h = 0; h < kHoles.size(); ++h) {
        const api::HoleCheck& hc = c.holes[h];
        SCOPED_TRACE(hc.hole);
        ASSERT_TRUE(hc.error.empty()) << hc.error;
        // The model's own boundaries along the hole are the closed form's.
        ASSERT_EQ(hc.model.intervals.size(), kUnits.size());
        for (std::size_t i = 0; i < kUnits.size(); ++i) {
            EXPECT_NEAR(hc.model.intervals[i].from, kHoles[h].depthAt(kContactZ[i]), kExactM);
            EXPECT_NEAR(hc.model.intervals[i].to, kHoles[h].depthAt(kContactZ[i + 1]), kExactM);
        }
        const double logged = kHoles[h].depthAt(-400.0) - kHoles[h].depthAt(0.0);
        EXPECT_NEAR(hc.logged, logged, kExactM);
        EXPECT_NEAR(hc.agreed, logged, kExactM);
        EXPECT_NEAR(hc.unmatched, kHoles[h].depthAt(0.0), kExactM);  // overburden: no unit
        ASSERT_EQ(hc.units.size(), kUnits.size());
        for (const auto& u : hc.units) EXPECT_NEAR(u.agreed, u.logged, kExactM) << u.unit;
        ASSERT_EQ(hc.contacts.size(), 3u);  // OVB -> Sandstone is not compared (OVB names no unit)
        for (const auto& k : hc.contacts) {
            ASSERT_TRUE(k.distance.has_value()) << k.unitAbove << " / " << k.unitBelow;
            EXPECT_LE(std::abs(*k.distance), kExactM) << k.unitAbove << " / " << k.unitBelow;
        }
    }
    ASSERT_EQ(c.codes.size(), 5u);
    EXPECT_EQ(c.codes[0].code, "Granite");
    EXPECT_EQ(c.codes[1].code, "OVB");
    EXPECT_TRUE(c.codes[1].unit.empty());
    EXPECT_EQ(c.codes[2].unit, "Shale");  // "SHALE": capitals sort first
    ASSERT_EQ(c.warnings.size(), 1u);     // OVB
    EXPECT_NE(c.warnings[0].find("OVB"), std::string::npos) << c.warnings[0];
}

TEST(DrillholeCheck, ShiftedContactsReportTheShift) {
    Fixture f;
    // Hole 0: Sandstone/Shale logged 2.5 m deep; hole 1: Limestone/Granite logged 1.25 m
    // shallow; hole 2: Shale/Limestone 0.75 m deep. Record ids and mixed case name units too.
    const std::vector<std::vector<double>> shift = {{0, 2.5, 0, 0, 0}, {0, 0, 0, -1.25, 0}, {0, 0, 0.75, 0, 0}};
    const auto c = f.check(sources(shift, kLowerCodes));
    const double kShift[3][2] = {{1, 2.5}, {3, -1.25}, {2, 0.75}};  // contact index 1..3, metres
    for (std::size_t h = 0; h < kHoles.size(); ++h) {
        const api::HoleCheck& hc = c.holes[h];
        SCOPED_TRACE(hc.hole);
        ASSERT_EQ(hc.contacts.size(), 3u);
        for (std::size_t k = 0; k < 3; ++k) {
            const double want = (k + 1 == std::size_t(kShift[h][0])) ? -kShift[h][1] : 0.0;
            ASSERT_TRUE(hc.contacts[k].distance.has_value());
            EXPECT_NEAR(*hc.contacts[k].distance, want, kExactM) << "contact " << k + 1;
        }
        // The shifted contact's units: the one logged too long agrees on its true length.
        const double moved = std::abs(kShift[h][1]);
        EXPECT_NEAR(hc.logged - hc.agreed, moved, kExactM);
        const std::size_t i = std::size_t(kShift[h][0]);  // contact between unit i-1 and i
        const std::size_t tooLong = kShift[h][1] > 0.0 ? i - 1 : i;
        for (std::size_t u = 0; u < hc.units.size(); ++u) {
            EXPECT_EQ(hc.units[u].unit, kUnits[u]);
            EXPECT_NEAR(hc.units[u].logged - hc.units[u].agreed, u == tooLong ? moved : 0.0, kExactM) << kUnits[u];
        }
    }
    // Over all holes, per unit.
    ASSERT_EQ(c.units.size(), kUnits.size());
    EXPECT_NEAR(c.units[0].logged - c.units[0].agreed, 2.5, kExactM);
    EXPECT_NEAR(c.units[1].logged - c.units[1].agreed, 0.75, kExactM);
    EXPECT_NEAR(c.units[2].logged - c.units[2].agreed, 0.0, kExactM);
    EXPECT_NEAR(c.units[3].logged - c.units[3].agreed, 1.25, kExactM);
    // The CSV carries the same.
    const std::string csv = api::drillholeCheckCsv(c, true);
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "hole,depth_m,code_above,code_below,unit_above,unit_below,model_depth_m,distance_m");
    EXPECT_NE(csv.find("straight-60,"), std::string::npos);
}

TEST(DrillholeCheck, SidecarMapAndAUnitTheModelLacks) {
    Fixture f;
    auto src = sources({}, {"SST", "SH", "LST", "GRN"});
    src.units = DrillholeUnitMap{"", "lith", {{"GRN", "Gneiss"}, {"LST", "limestone"}, {"SH", "Shale"}, {"SST", "20"}}};
    const auto c = f.check(std::move(src));
    ASSERT_TRUE(c.sidecarMap);
    // SST -> record 20 (Shale): wrong on purpose, disagrees everywhere; GRN -> Gneiss: lacking.
    bool warned = false;
    for (const auto& w : c.warnings) warned = warned || w.find("'Gneiss', which the model lacks") != std::string::npos;
    EXPECT_TRUE(warned);
    ASSERT_EQ(c.units.size(), 3u);  // Shale (SST and SH), Limestone, Gneiss
    EXPECT_EQ(c.units[0].unit, "Shale");
    EXPECT_EQ(c.units[2].unit, "Gneiss");
    EXPECT_FALSE(c.units[2].inModel);
    EXPECT_EQ(c.units[2].agreed, 0.0);
    for (const auto& hc : c.holes) {
        SCOPED_TRACE(hc.hole);
        const ArcHole* a = nullptr;
        for (const auto& k : kHoles)
            if (k.id == hc.hole) a = &k;
        ASSERT_NE(a, nullptr);
        const double shale = a->depthAt(-200.0) - a->depthAt(-100.0), lime = a->depthAt(-300.0) - a->depthAt(-200.0);
        EXPECT_NEAR(hc.agreed, shale + lime, kExactM);
        // SST(Shale)->SH(Shale) is no contact; Shale->Limestone is found; Limestone->Gneiss: null.
        ASSERT_EQ(hc.contacts.size(), 2u);
        ASSERT_TRUE(hc.contacts[0].distance.has_value());
        EXPECT_LE(std::abs(*hc.contacts[0].distance), kExactM);
        EXPECT_FALSE(hc.contacts[1].distance.has_value());
    }
    const auto j = api::drillholeCheckJson(c, "strata", "test");
    EXPECT_TRUE(j["holes"][0]["contacts"][1]["distance_m"].is_null());
}

TEST(DrillholeCheck, NoCodeColumnIsANamedError) {
    Fixture f;
    auto src = sources({}, {"a", "b", "c", "d"});
    src.units = DrillholeUnitMap{"", "rocktype", {}};
    auto db = buildDrillholes(std::move(src));
    ASSERT_TRUE(db.ok());
    auto c = api::checkDrillholes(f.model, db.value(), *f.tracer);
    ASSERT_FALSE(c.ok());
    EXPECT_NE(c.error().message.find("'rocktype'"), std::string::npos) << c.error().message;
    EXPECT_NE(c.error().message.find("lithology: lith"), std::string::npos) << c.error().message;
}
