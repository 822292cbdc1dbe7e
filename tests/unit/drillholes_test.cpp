// The drillhole database (model/drillholes/drillholes.hpp): minimum curvature desurvey against
// closed forms (straight holes, circular arcs in vertical and inclined planes), reading the
// Copper Creek subset and other column spellings, every validation message, and `geoslice info`.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "model/drillholes/drillholes.hpp"
#include "tests/common/run_command.hpp"

namespace geoslice {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Positions to 1e-9 m: collars within 1 km of the origin (a double's step there is 1.1e-13 m),
// holes up to 1 km long with up to 40 stations; the arithmetic error stays below 1e-11 m.
constexpr double kTol = 1e-9;

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tol, const std::string& what) {
    EXPECT_LE(glm::length(a - b), tol) << what << ": (" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", "
                                       << b.y << ", " << b.z << ")";
}

// Azimuth/dip (degrees, dip negative down) of a unit direction that is not vertical.
SurveyStation stationOf(double depth, const glm::dvec3& t) {
    double az = std::atan2(t.x, t.y) * 180.0 / kPi;
    if (az < 0.0) az += 360.0;
    return {depth, az, std::asin(std::clamp(t.z, -1.0, 1.0)) * 180.0 / kPi};
}

std::vector<double> randomDepths(std::mt19937_64& rng, std::size_t n, double length, bool startAtZero) {
    std::uniform_real_distribution<double> u(0.0, length);
    std::vector<double> d(n);
    for (double& x : d) x = u(rng);
    if (startAtZero) d[0] = 0.0;
    std::sort(d.begin(), d.end());
    d.erase(std::unique(d.begin(), d.end(), [](double a, double b) { return b - a < 1e-3; }), d.end());
    return d;
}

TEST(DrillholesDesurvey, StraightInclinedHolesLieOnALine) {
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> coord(-1000.0, 1000.0), az(0.0, 360.0), dip(-90.0, 0.0);
    std::uniform_int_distribution<int> count(1, 40);
    for (int hole = 0; hole < 200; ++hole) {
        const glm::dvec3 collar(coord(rng), coord(rng), coord(rng) / 10.0);
        const double a = az(rng), d = dip(rng);
        const glm::dvec3 t = drillDirection(a, d);
        std::vector<SurveyStation> st;
        for (double depth : randomDepths(rng, std::size_t(count(rng)), 1000.0, hole % 2 == 0))
            st.push_back({depth, a, d});
        const HolePath p = desurvey(collar, st, 1000.0);
        ASSERT_EQ(p.depth.front(), 0.0);
        ASSERT_EQ(p.depth.back(), 1000.0);
        for (std::size_t i = 0; i < p.depth.size(); ++i)
            expectNear(p.position[i], collar + p.depth[i] * t, kTol, "node " + std::to_string(i));
        std::uniform_real_distribution<double> any(-10.0, 1100.0);
        for (int k = 0; k < 20; ++k) {
            const double md = any(rng);
            expectNear(p.at(md), collar + md * t, kTol, "depth " + std::to_string(md));
        }
        EXPECT_STREQ(p.method, st.size() == 1 ? "tangent (one station)" : "minimum curvature");
    }
}

// A hole along a circular arc: P(s) = C + R sin(s/R) t0 + R (1 - cos(s/R)) n, tangent
// cos(s/R) t0 + sin(s/R) n, with t0 and n orthonormal. Minimum curvature is exact on it.
struct Arc {
    glm::dvec3 collar, t0, n;
    double radius;
    glm::dvec3 at(double s) const {
        return collar + radius * std::sin(s / radius) * t0 + radius * (1.0 - std::cos(s / radius)) * n;
    }
    glm::dvec3 tangent(double s) const { return std::cos(s / radius) * t0 + std::sin(s / radius) * n; }
};

// Checks every node and mid-station position of the desurveyed arc.
void checkArc(const Arc& arc, const std::vector<double>& depths, std::mt19937_64& rng) {
    std::vector<SurveyStation> st;
    for (double s : depths) st.push_back(stationOf(s, arc.tangent(s)));
    const HolePath p = desurvey(arc.collar, st);
    ASSERT_EQ(p.depth.size(), depths.size());
    for (std::size_t i = 0; i < depths.size(); ++i) {
        expectNear(p.position[i], arc.at(depths[i]), kTol, "station " + std::to_string(i));
        if (i + 1 < depths.size()) {
            std::uniform_real_distribution<double> f(0.0, 1.0);
            for (double frac : {0.5, f(rng), f(rng)}) {
                const double s = depths[i] + frac * (depths[i + 1] - depths[i]);
                expectNear(p.at(s), arc.at(s), kTol, "between stations at " + std::to_string(s));
            }
        }
    }
}

TEST(DrillholesDesurvey, ArcInAVerticalPlaneIsExact) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-1000.0, 1000.0), az(0.0, 360.0), dip0(-85.0, -30.0),
        radius(300.0, 3000.0);
    std::uniform_int_distribution<int> count(2, 40);
    for (int hole = 0; hole < 200; ++hole) {
        const double a = az(rng), d0 = dip0(rng), r = radius(rng);
        // Flattening (n towards the horizontal in the hole's vertical plane) or steepening.
        const bool flatten = hole % 2 == 0;
        const glm::dvec3 t0 = drillDirection(a, d0), n = drillDirection(a, flatten ? d0 + 90.0 : d0 - 90.0);
        // Keep the dip between -88 and -2 degrees (azimuth defined, hole going down).
        const double room = (flatten ? -2.0 - d0 : d0 + 88.0) * kPi / 180.0;
        const double length = std::min(1000.0, r * room);
        const Arc arc{glm::dvec3(coord(rng), coord(rng), coord(rng) / 10.0), t0, n, r};
        checkArc(arc, randomDepths(rng, std::size_t(count(rng)), length, true), rng);
    }
}

TEST(DrillholesDesurvey, ArcInAnInclinedPlaneIsExact) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> coord(-1000.0, 1000.0), u(-1.0, 1.0), radius(200.0, 3000.0);
    std::uniform_int_distribution<int> count(2, 40);
    int made = 0;
    while (made < 200) {
        const glm::dvec3 t0 = glm::normalize(glm::dvec3(u(rng), u(rng), -1.0 + 0.5 * u(rng)));
        glm::dvec3 n = glm::dvec3(u(rng), u(rng), u(rng));
        n = n - glm::dot(n, t0) * t0;
        if (glm::length(n) < 0.1) continue;
        n = glm::normalize(n);
        const double r = radius(rng), length = std::min(1000.0, r * kPi / 3.0);
        const Arc arc{glm::dvec3(coord(rng), coord(rng), coord(rng) / 10.0), t0, n, r};
        // The tangent must go down and stay away from vertical along the whole arc.
        bool ok = true;
        for (int k = 0; k <= 50 && ok; ++k) {
            const double z = arc.tangent(length * k / 50.0).z;
            ok = z < -0.05 && z > -0.999;
        }
        if (!ok) continue;
        // Not a vertical plane: the normal of the arc's plane has a vertical component.
        if (std::abs(glm::cross(t0, n).z) < 0.05) continue;
        checkArc(arc, randomDepths(rng, std::size_t(count(rng)), length, true), rng);
        ++made;
    }
}

TEST(DrillholesDesurvey, TinyDoglegsAreStable) {
    // Stations 1e-9 degrees apart: RF = 1 + beta^2/12 + ... is 1 to within 1e-22, so the
    // balanced tangent is the answer; acos(t1.t2) would give beta = 0 or 1e-8 here, not 1.7e-11.
    const std::vector<SurveyStation> st = {{0.0, 45.0, -60.0}, {500.0, 45.0 + 1e-9, -60.0}, {1000.0, 45.0, -60.0}};
    const glm::dvec3 t1 = drillDirection(45.0, -60.0), t2 = drillDirection(45.0 + 1e-9, -60.0);
    const HolePath p = desurvey(glm::dvec3(0.0), st);
    expectNear(p.at(500.0), 250.0 * (t1 + t2), 1e-12, "second station");
    expectNear(p.at(1000.0), 500.0 * (t1 + t2), 1e-12, "end");
    // Halfway: the slerped tangent integrated, s(2-s)/2 t1 + s^2/2 t2 at s = 1/2.
    expectNear(p.at(250.0), 500.0 * (0.375 * t1 + 0.125 * t2), 1e-12, "quarter");
}

TEST(DrillholesDesurvey, VerticalHoleWithoutSurvey) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> coord(-1000.0, 1000.0), td(1.0, 1500.0);
    for (int hole = 0; hole < 100; ++hole) {
        const glm::dvec3 c(coord(rng), coord(rng), coord(rng));
        const double total = td(rng);
        const HolePath p = desurvey(c, {}, total);
        EXPECT_STREQ(p.method, "straight down (no survey)");
        ASSERT_EQ(p.depth.size(), 2u);
        expectNear(p.position.back(), c - glm::dvec3(0, 0, total), kTol, "end");
        expectNear(p.at(0.3 * total), c - glm::dvec3(0, 0, 0.3 * total), kTol, "inside");
    }
}

// ---- Reading -------------------------------------------------------------------------------

const std::string kData = std::string(GEOSLICE_TEST_DATA_DIR) + "/drillholes/copper_creek";

const DrillholeTableInfo* tableNamed(const DrillholeDatabase& db, const std::string& name) {
    for (const auto& t : db.tables)
        if (t.name == name) return &t;
    return nullptr;
}

std::string roleOf(const DrillholeTableInfo& t, const std::string& header) {
    for (const auto& c : t.columns)
        if (c.header == header) return c.role + "/" + c.how;
    return "absent";
}

TEST(DrillholesRead, CopperCreekSubset) {
    auto db = loadDrillholes(kData);
    ASSERT_TRUE(db.ok()) << db.error().message;
    EXPECT_EQ(db->holes.size(), 5u);
    EXPECT_EQ(db->stationCount(), 49u);
    EXPECT_TRUE(db->warnings.empty()) << db->warnings.front().text();
    ASSERT_EQ(db->intervals.size(), 2u);
    EXPECT_EQ(db->intervals[0].name, "assay");
    EXPECT_EQ(db->intervals[0].size(), 241u);
    EXPECT_EQ(db->intervals[1].name, "lithology");
    EXPECT_EQ(db->intervals[1].size(), 58u);
    // The BOM is not part of the first header; every column recorded with its role.
    const DrillholeTableInfo* collar = tableNamed(db.value(), "collar");
    ASSERT_NE(collar, nullptr);
    EXPECT_EQ(roleOf(*collar, "hole_ID"), "hole/recognised");
    EXPECT_EQ(roleOf(*collar, "z"), "z/recognised");
    const DrillholeTableInfo* lith = tableNamed(db.value(), "lithology");
    ASSERT_NE(lith, nullptr);
    EXPECT_EQ(roleOf(*lith, "to_depth"), "to/recognised");
    EXPECT_EQ(roleOf(*lith, "rock code"), "column/");
    const auto& assay = db->intervals[0];
    ASSERT_EQ(assay.columns.size(), 4u);
    EXPECT_EQ(assay.columns[0].name, "Cu_pct");
    EXPECT_TRUE(assay.columns[0].numeric);
    EXPECT_EQ(assay.columns[0].unit, "%");
    EXPECT_EQ(assay.columns[2].unit, "ppm");
    EXPECT_TRUE(std::isnan(assay.columns[1].numbers[0]));  // a blank Mo_pct cell
    EXPECT_FALSE(db->intervals[1].columns[0].numeric);
    // A-11: one station (360, -90) at 441.96 m: straight down from the collar.
    const Drillhole* a11 = db->find("A-11");
    ASSERT_NE(a11, nullptr);
    EXPECT_STREQ(a11->path.method, "tangent (one station)");
    // 1e-9 m at UTM coordinates (3.6e6 m: a double's step is 4.7e-10 m).
    expectNear(a11->path.at(100.0), a11->collar - glm::dvec3(0, 0, 100.0), 2e-9, "A-11 at 100 m");
    // AH-4: stations (0 m, 83, -59) and (30.78 m, 88, -64); the second station by the textbook
    // formula, (MD2-MD1)/2 (t1+t2) RF with beta = acos(t1.t2), RF = 2/beta tan(beta/2).
    const Drillhole* ah4 = db->find("AH-4");
    ASSERT_NE(ah4, nullptr);
    EXPECT_STREQ(ah4->path.method, "minimum curvature");
    const glm::dvec3 t1 = drillDirection(83.0, -59.0), t2 = drillDirection(88.0, -64.0);
    const double beta = std::acos(glm::dot(t1, t2)), rf = 2.0 / beta * std::tan(beta / 2.0);
    expectNear(ah4->path.at(30.78), ah4->collar + 30.78 / 2.0 * (t1 + t2) * rf, 2e-9, "AH-4 at 30.78 m");
}

class DrillholesFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir =
            std::filesystem::temp_directory_path() / ("gs_dh_" + std::to_string(::getpid()) + "_" +
                                                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::filesystem::create_directories(dir);
    }
    void TearDown() override { std::filesystem::remove_all(dir); }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; }
    std::filesystem::path dir;
};

TEST_F(DrillholesFiles, OtherSpellingsAndPositiveDownDipFromTheSidecar) {
    write("collar.csv", "HOLEID,EAST,NORTH,RL,EOH\nDH1,100,200,50,300\nDH2,150,250,60,\n");
    write("survey.csv", "HOLEID,DEPTH,AZI,DIP\nDH1,0,90,60\nDH1,150,100,55\nDH2,0,0,90\n");
    write("geology.csv", "HOLEID,FROM,TO,LITH,AU_GPT\nDH1,0,10,ox,0.5\nDH1,10,300,fr,\nDH2,0,5,ox,1.25\n");
    write("holes.drillholes.json", R"({"crs": "EPSG:28350", "dip": "positive_down",
        "collar": "collar.csv", "survey": {"file": "survey.csv"},
        "intervals": [{"name": "geology", "file": "geology.csv", "units": {"AU_GPT": "g/t"}}]})");
    auto db = loadDrillholes((dir / "holes.drillholes.json").string());
    ASSERT_TRUE(db.ok()) << db.error().message;
    EXPECT_TRUE(db->warnings.empty()) << db->warnings.front().text();
    EXPECT_EQ(db->crs, "EPSG:28350");
    const DrillholeTableInfo* collar = tableNamed(db.value(), "collar");
    ASSERT_NE(collar, nullptr);
    EXPECT_EQ(roleOf(*collar, "HOLEID"), "hole/recognised");
    EXPECT_EQ(roleOf(*collar, "EAST"), "x/recognised");
    EXPECT_EQ(roleOf(*collar, "NORTH"), "y/recognised");
    EXPECT_EQ(roleOf(*collar, "RL"), "z/recognised");
    EXPECT_EQ(roleOf(*collar, "EOH"), "total_depth/recognised");
    const DrillholeTableInfo* survey = tableNamed(db.value(), "survey");
    ASSERT_NE(survey, nullptr);
    EXPECT_EQ(survey->dip, DipConvention::PositiveDown);
    EXPECT_EQ(roleOf(*survey, "AZI"), "azimuth/recognised");
    // Positive down 60 is negative down -60.
    const Drillhole* dh1 = db->find("DH1");
    ASSERT_NE(dh1, nullptr);
    EXPECT_DOUBLE_EQ(dh1->stations[0].dip, -60.0);
    const HolePath same = desurvey({100, 200, 50}, {{0, 90, -60}, {150, 100, -55}}, 300.0);
    expectNear(dh1->path.at(250.0), same.at(250.0), 1e-12, "DH1 at 250 m");
    EXPECT_EQ(dh1->path.depth.back(), 300.0);
    EXPECT_TRUE(std::isnan(db->find("DH2")->totalDepth));
    ASSERT_EQ(db->intervals.size(), 1u);
    EXPECT_EQ(db->intervals[0].columns[1].unit, "g/t");
    EXPECT_TRUE(std::isnan(db->intervals[0].columns[1].numbers[1]));
}

TEST_F(DrillholesFiles, ExplicitColumnMappingAndCollarDirection) {
    write("c.csv", "Nombre,Este,Norte,Cota,Rumbo,Inclinacion\nS1,0,0,0,180,-45\n");
    write("s.drillholes.json", R"({"collar": {"file": "c.csv", "columns": {"hole": "nombre", "x": "Este",
        "y": "Norte", "z": "Cota", "azimuth": "Rumbo", "dip": "Inclinacion"}}})");
    auto db = loadDrillholes((dir / "s.drillholes.json").string());
    ASSERT_TRUE(db.ok()) << db.error().message;
    EXPECT_EQ(roleOf(db->tables[0], "Este"), "x/sidecar");
    const Drillhole* s1 = db->find("S1");
    ASSERT_NE(s1, nullptr);
    EXPECT_STREQ(s1->path.method, "straight along the collar's azimuth/dip (no survey)");
    expectNear(s1->path.at(10.0), 10.0 * drillDirection(180.0, -45.0), 1e-12, "S1 at 10 m");
}

TEST_F(DrillholesFiles, SidecarErrorsNameTheProblem) {
    write("c.csv", "hole,x,y,z\nA,0,0,0\n");
    write("bad.drillholes.json", R"({"collar": {"file": "c.csv", "columns": {"x": "EASTING"}}})");
    auto bad = loadDrillholes((dir / "bad.drillholes.json").string());
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("'EASTING'"), std::string::npos) << bad.error().message;
    write("dip.drillholes.json", R"({"dip": "sideways", "collar": "c.csv"})");
    auto dip = loadDrillholes((dir / "dip.drillholes.json").string());
    ASSERT_FALSE(dip.ok());
    EXPECT_NE(dip.error().message.find("sideways"), std::string::npos) << dip.error().message;
}

// ---- Validation: one message each, naming file, row and hole ----------------------------------

DrillholeSources sources(const std::string& collar, const std::string& survey = "", const std::string& interval = "") {
    DrillholeSources s;
    s.source = "test";
    s.collar = {"collar", "collar.csv", collar, {}, {}, DipConvention::NegativeDown};
    if (!survey.empty()) s.survey = DrillholeTableSource{"survey", "survey.csv", survey, {}, {}, {}};
    if (!interval.empty()) s.intervals.push_back({"lith", "lith.csv", interval, {}, {}, {}});
    return s;
}

// The one warning of a database, as text.
std::string onlyWarning(const Result<DrillholeDatabase>& db) {
    if (!db.ok()) return "error: " + db.error().message;
    if (db->warnings.size() != 1) {
        std::string all = std::to_string(db->warnings.size()) + " warnings:";
        for (const auto& w : db->warnings) all += " [" + w.text() + "]";
        return all;
    }
    return db->warnings[0].text();
}

const std::string kCollar = "hole,x,y,z,depth\nA,0,0,0,100\nB,10,0,0,\n";

TEST(DrillholesValidate, MissingCollar) {
    auto db = buildDrillholes(sources(kCollar, "", "hole,from,to\nA,0,10\nZ,0,5\nZ,5,9\n"));
    EXPECT_EQ(onlyWarning(db),
              "lith.csv row 3, hole 'Z': no collar for this hole in collar.csv: its 2 rows (first "
              "row 3) skipped");
    EXPECT_EQ(db->intervals[0].size(), 1u);
}

TEST(DrillholesValidate, DuplicateCollar) {
    auto db = buildDrillholes(sources(kCollar + "A,5,5,5,10\n"));
    EXPECT_EQ(onlyWarning(db), "collar.csv row 4, hole 'A': duplicate collar (the first is row 2): row skipped");
    EXPECT_EQ(db->find("A")->collar, glm::dvec3(0.0));
}

TEST(DrillholesValidate, SurveyDepthsNotIncreasing) {
    auto db = buildDrillholes(sources(kCollar, "hole,depth,azimuth,dip\nA,0,0,-60\nA,50,0,-60\nA,50,10,-60\n"));
    EXPECT_EQ(onlyWarning(db),
              "survey.csv row 4, hole 'A': survey depths not increasing: 50 m after 50 m (row 3): row skipped");
    EXPECT_EQ(db->find("A")->stations.size(), 2u);
}

TEST(DrillholesValidate, AzimuthAndDipOutOfRange) {
    auto az = buildDrillholes(sources(kCollar, "hole,depth,azimuth,dip\nA,0,361,-60\n"));
    EXPECT_EQ(onlyWarning(az), "survey.csv row 2, hole 'A': azimuth 361 outside [0, 360]: row skipped");
    auto dip = buildDrillholes(sources(kCollar, "hole,depth,azimuth,dip\nB,0,0,-91\n"));
    EXPECT_EQ(onlyWarning(dip), "survey.csv row 2, hole 'B': dip -91 outside [-90, 90]: row skipped");
}

TEST(DrillholesValidate, OverlappingIntervals) {
    auto db = buildDrillholes(sources(kCollar, "", "hole,from,to\nA,0,10\nA,20,30\nA,8,12\n"));
    EXPECT_EQ(onlyWarning(db),
              "lith.csv row 4, hole 'A': interval 8..12 m overlaps the interval 0..10 m (row 2): kept");
    EXPECT_EQ(db->intervals[0].from, (std::vector<double>{0, 8, 20}));  // sorted by from
}

TEST(DrillholesValidate, ReversedInterval) {
    auto db = buildDrillholes(sources(kCollar, "", "hole,from,to\nA,10,5\n"));
    EXPECT_EQ(onlyWarning(db),
              "lith.csv row 2, hole 'A': interval 10..5 m is reversed or empty (from >= to): row skipped");
}

TEST(DrillholesValidate, IntervalPastTheEnd) {
    auto db = buildDrillholes(sources(kCollar, "", "hole,from,to\nA,90,110\nB,90,110\n"));  // B: no total depth
    EXPECT_EQ(onlyWarning(db),
              "lith.csv row 2, hole 'A': interval 90..110 m ends past the hole's total depth 100 m: kept");
}

TEST(DrillholesValidate, UnknownHoleInSurvey) {
    auto db = buildDrillholes(sources(kCollar, "hole,depth,azimuth,dip\nQ,0,0,-90\n"));
    EXPECT_EQ(onlyWarning(db),
              "survey.csv row 2, hole 'Q': no collar for this hole in collar.csv: its 1 row (first "
              "row 2) skipped");
}

TEST(DrillholesValidate, BlankAndNanCells) {
    auto x = buildDrillholes(sources(kCollar + "C,,0,0,\n"));
    EXPECT_EQ(onlyWarning(x), "collar.csv row 4, hole 'C': x cell blank: row skipped");
    auto nan = buildDrillholes(sources(kCollar, "hole,depth,azimuth,dip\nA,nan,0,-90\n"));
    EXPECT_EQ(onlyWarning(nan), "survey.csv row 2, hole 'A': depth cell not a finite number: 'nan': row skipped");
    auto id = buildDrillholes(sources(kCollar, "", "hole,from,to\n,0,1\n"));
    EXPECT_EQ(onlyWarning(id), "lith.csv row 2: blank hole id: row skipped");
    auto to = buildDrillholes(sources(kCollar, "", "hole,from,to\nA,0,\n"));
    EXPECT_EQ(onlyWarning(to), "lith.csv row 2, hole 'A': to cell blank: row skipped");
}

TEST(DrillholesValidate, TableWithoutARequiredColumnIsSkippedWithAWarning) {
    auto db = buildDrillholes(sources(kCollar, "hole,depth,azimuth\nA,0,0\n"));
    ASSERT_TRUE(db.ok());
    ASSERT_EQ(db->warnings.size(), 1u);
    EXPECT_NE(db->warnings[0].text().find("survey.csv: no column for dip"), std::string::npos)
        << db->warnings[0].text();
}

TEST(DrillholesValidate, NothingUsableIsAnError) {
    auto db = buildDrillholes(sources("hole,x,y,z\nA,,0,0\n"));
    ASSERT_FALSE(db.ok());
    EXPECT_EQ(db.error().message,
              "collar.csv: no usable collar (1 warnings; the first: collar.csv row 2, hole 'A': x cell blank: row "
              "skipped)");
    auto noZ = buildDrillholes(sources("hole,x,y\nA,0,0\n"));
    ASSERT_FALSE(noZ.ok());
    EXPECT_NE(noZ.error().message.find("no column for z"), std::string::npos) << noZ.error().message;
}

// ---- geoslice info --------------------------------------------------------------------------

TEST_F(DrillholesFiles, InfoListsTheDatabaseFromTheSidecar) {
    write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    write("m.drillholes.json", R"({"crs": "EPSG:26912", "collar": ")" + kData + R"(/collar.csv",
        "survey": ")" + kData + R"(/survey.csv", "intervals": [")" +
                                   kData + R"(/lithology.csv"]})");
    const std::string model = (dir / "m.obj").string();
    test::CmdResult r = test::runGeoslice("info --json " + model);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("drillholes")) << r.out;
    const auto& d = j["drillholes"];
    EXPECT_EQ(d["holes"], 5);
    EXPECT_EQ(d["stations"], 49);
    EXPECT_EQ(d["crs"], "EPSG:26912");
    EXPECT_EQ(d["tables"][1]["dip"], "negative_down");
    EXPECT_EQ(d["tables"][2]["columns"][2]["header"], "to_depth");
    EXPECT_EQ(d["tables"][2]["columns"][2]["role"], "to");
    EXPECT_EQ(d["intervals"][0]["intervals"], 58);
    // The model (an OBJ) has no CRS: the holes' EPSG:26912 coordinates are taken as its own, said.
    ASSERT_EQ(d["warnings"].size(), 1u) << d["warnings"].dump();
    EXPECT_NE(d["warnings"][0].dump().find("the model has no CRS"), std::string::npos) << d["warnings"].dump();

    // --drillholes over the sidecar, with a warning in the text output.
    write("extra.csv", "hole_ID,x,y,z\nA-11,0,0,0\nA-11,1,1,1\n");
    write("other.drillholes.json", R"({"collar": "extra.csv"})");
    test::CmdResult t =
        test::runGeoslice("info " + model + " --drillholes " + (dir / "other.drillholes.json").string());
    EXPECT_EQ(t.exitCode, 0) << t.out;
    EXPECT_NE(t.out.find("1 holes, 0 survey stations"), std::string::npos) << t.out;
    EXPECT_NE(t.out.find("'hole_ID' as hole (recognised)"), std::string::npos) << t.out;
    EXPECT_NE(t.out.find("warning  extra.csv row 3, hole 'A-11': duplicate collar"), std::string::npos) << t.out;

    // A database with nothing usable fails the command.
    write("none.drillholes.json", R"({"collar": "missing.csv"})");
    test::CmdResult f = test::runGeoslice("info " + model + " --drillholes " + (dir / "none.drillholes.json").string());
    EXPECT_EQ(f.exitCode, 1) << f.out;
}

}  // namespace
}  // namespace geoslice
