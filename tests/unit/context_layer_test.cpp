// The plan's context layer (api/context_layer.hpp): coordinates in the model's own CRS pass
// through exactly; WGS 84 lon/lat (RFC 7946) and another CRS (EPSG:4326 as a `crs` member,
// EPSG:4490 CGCS2000 geographic) are converted to the model's Gauss-Kruger coordinates as PROJ's
// cs2cs converts them; properties and ids are kept, unlocated features left out; every bad
// file is refused naming the file, the feature and what is wrong.
#include <cstdio>
#include <sstream>

#include <gtest/gtest.h>

#include "api/context_layer.hpp"
#include "model/json_text.hpp"
#include "tests/common/run_command.hpp"

namespace geoslice::api {
namespace {

using J = nlohmann::ordered_json;

// cs2cs prints 10 decimals of metres; PROJ's operation is the same: well under a millimetre.
constexpr double kSameOperationM = 1e-3;

Crs gk() { return Crs::fromEpsg(4523).value(); }
Aabb demoBox() {
    Aabb b;
    b.min = {35502000.0, 3387000.0, -800.0};
    b.max = {35506000.0, 3390000.0, 600.0};
    return b;
}

// EPSG:4490 / 4326 lat lon -> EPSG:4523 easting northing through cs2cs.
std::pair<double, double> cs2cs(const char* from, double lon, double lat) {
    char cmd[256];
    std::snprintf(cmd, sizeof cmd, "echo '%.12f %.12f' | cs2cs -f %%.10f %s EPSG:4523", lat, lon, from);
    const auto r = test::runCommand(cmd);
    std::istringstream in(r.out);
    double northing = 0.0, easting = 0.0;
    in >> northing >> easting;
    return {easting, northing};
}

TEST(ContextLayer, TheModelsOwnCrsPassesThroughExactly) {
    const std::string text = R"({"type": "FeatureCollection",
        "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::4523"}},
        "features": [
          {"type": "Feature", "id": 7, "properties": {"name": "Lease", "kind": "lease"},
           "geometry": {"type": "Polygon", "coordinates": [[[35502100.25, 3387100.5], [35505900, 3387100.5],
                                                            [35505900, 3389900], [35502100.25, 3387100.5]]]}},
          {"type": "Feature", "properties": null, "geometry": null},
          {"type": "Feature", "properties": {"name": "Shaft"}, "geometry": {"type": "Point", "coordinates": [35504000, 3388000, 412]}}]})";
    auto r = parseContextLayer(text, "ctx.geojson", gk(), demoBox());
    ASSERT_TRUE(r) << r.error().message;
    const J& f = r.value()["features"];
    ASSERT_EQ(f.size(), 2u);  // the unlocated feature is left out
    EXPECT_EQ(f[0]["id"], 7);
    EXPECT_EQ(f[0]["properties"]["name"], "Lease");
    EXPECT_EQ(f[0]["geometry"]["coordinates"][0][0], J::array({35502100.25, 3387100.5}));
    EXPECT_EQ(f[1]["geometry"]["coordinates"], J::array({35504000, 3388000, 412}));
    EXPECT_EQ(r.value()["geoslice"]["crs"], "EPSG:4523");
    EXPECT_NE(r.value()["geoslice"]["read"].get<std::string>().find("the model's CRS"), std::string::npos);
}

TEST(ContextLayer, LonLatIsConvertedAsCs2csConvertsIt) {
    const double lon = 105.04321, lat = 30.61234;
    for (const char* crs : {"", "EPSG:4490"}) {
        std::string text = R"({"type": "FeatureCollection",)";
        if (*crs) text += R"("crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::4490"}},)";
        char geom[200];
        std::snprintf(geom, sizeof geom, R"({"type": "LineString", "coordinates": [[%.12f, %.12f], [%.12f, %.12f]]})",
                      lon, lat, lon + 0.01, lat);
        text += std::string(R"("features": [{"type": "Feature", "properties": {}, "geometry": )") + geom + "}]}";
        auto r = parseContextLayer(text, "ctx.geojson", gk(), demoBox());
        ASSERT_TRUE(r) << crs << ": " << r.error().message;
        const J& p = r.value()["features"][0]["geometry"]["coordinates"];
        for (int i = 0; i < 2; ++i) {
            const auto [e, n] = cs2cs(*crs ? "EPSG:4490" : "EPSG:4326", lon + 0.01 * i, lat);
            EXPECT_NEAR(p[i][0].get<double>(), e, kSameOperationM) << crs;
            EXPECT_NEAR(p[i][1].get<double>(), n, kSameOperationM) << crs;
        }
        if (!*crs) {
            EXPECT_TRUE(r.value()["geoslice"].contains("note")) << jsonText(r.value()["geoslice"]);
        }
    }
}

TEST(ContextLayer, BadFilesAreNamed) {
    const auto local = Crs::local();
    const std::pair<const char*, const char*> cases[] = {
        {R"([1])", "not a GeoJSON FeatureCollection"},
        {R"({"type": "Feature"})", "not a GeoJSON FeatureCollection"},
        {R"({"type": "FeatureCollection", "features": [5]})", "features[0]: not a Feature"},
        {R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "GeometryCollection", "geometries": []}}]})",
         "geometry type 'GeometryCollection'"},
        {R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Point", "coordinates": [1]}}]})",
         "array of 2 or 3 numbers"},
        {R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "LineString", "coordinates": [1, 2]}}]})",
         "array of 2 or 3 numbers"},
        {R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Point", "coordinates": ["1", 2]}}]})",
         "not a number"},
        {R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon"}}]})",
         "without coordinates"},
        {R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "my local grid"}}, "features": []})",
         "names no CRS PROJ knows"},
        {"{", "not valid JSON"},
        {"\xFF\xFE{}", "not valid UTF-8"},
    };
    for (const auto& [text, needle] : cases) {
        auto r = parseContextLayer(text, "ctx.geojson", gk(), demoBox());
        ASSERT_FALSE(r) << text;
        EXPECT_NE(r.error().message.find(needle), std::string::npos) << text << " -> " << r.error().message;
        EXPECT_EQ(r.error().message.rfind("ctx.geojson", 0), 0u) << r.error().message;
    }
    auto withCrs = parseContextLayer(R"({"type": "FeatureCollection", "crs": "EPSG:4523", "features": []})",
                                     "ctx.geojson", local, demoBox());
    ASSERT_FALSE(withCrs);
    EXPECT_NE(withCrs.error().message.find("the model has no CRS"), std::string::npos);
    auto own = parseContextLayer(
        R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Point", "coordinates": [5, 6]}}]})",
        "ctx.geojson", local, demoBox());
    ASSERT_TRUE(own) << own.error().message;
    EXPECT_EQ(own.value()["features"][0]["geometry"]["coordinates"], J::array({5, 6}));
}

}  // namespace
}  // namespace geoslice::api
