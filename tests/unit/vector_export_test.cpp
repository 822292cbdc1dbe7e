// Vector export: GeoJSON (plane and world frames) and SVG of a box with a nested lens and
// a fault trace, and of a polyline section; the exported rings give back the areas.
#include <gtest/gtest.h>

#include <cmath>

#include "section/fill/vector_export.hpp"
#include "section_test_util.hpp"
#include "test_meshes.hpp"

using namespace geoslice;
using namespace geoslice::test;

namespace {

// Square metres: areas of a few hundred m^2 from coordinates of tens of metres, exported
// and re-summed: rounding only.
constexpr double kAreaTolM2 = 1e-9;
// Square metres: an area of about 1e4 m^2: relative 1e-12 of rounding.
constexpr double kLargeAreaTolM2 = 1e-8;
// Metres: the elevation of a horizontal slice written as world z: rounding only.
constexpr double kElevationTolM = 1e-9;

Model boxLensFault() {
    Mesh sheet;  // vertical fault sheet x = 5, y 0..100, z 0..50
    sheet.positions = {{5, 0, 0}, {5, 100, 0}, {5, 100, 50}, {5, 0, 50}};
    sheet.indices = {0, 1, 2, 0, 2, 3};
    Model m;
    m.bodies = {makePart("host", PartKind::Body, 1, boxMesh({0, 0, 0}, {100, 100, 50})),
                makePart("lens", PartKind::Body, 2, boxMesh({40, 40, 20}, {60, 60, 30}))};
    m.surfaces = {makePart("F1", PartKind::Surface, 3, sheet)};
    AttributeRecord r;
    r.id = 2;
    r.name = "Lens <ore>";
    r.kind = "orebody";
    r.density = 2.6;
    r.grade = 12.5;
    r.gradeUnit = "% SiO2";
    m.attributes.put(r);
    m.recentre();
    validate(m);
    return m;
}

// The GeoJSON of a section in `frame`; Projected names UTM zone 50N (the positions are the
// model's own: the box is local, the CRS only a label here).
nlohmann::json geoJson(const SectionIndex& idx, const VectorSource& src, VectorFrame frame) {
    const Crs crs = frame == VectorFrame::Plane ? Crs::local() : Crs::fromEpsg(32650).value();  // a label only
    auto space = geoJsonSpace(src, frame, crs, nullptr, "");
    EXPECT_TRUE(space.ok()) << space.error().message;
    auto doc = toGeoJson(idx, src, space.value());
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return nlohmann::json::parse(doc.value().dump());
}

// Shoelace area of a GeoJSON ring of 2D positions (first position repeated last).
double ringAreaJson(const nlohmann::json& ring) {
    double a = 0.0;
    for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        a += ring[i][0].get<double>() * ring[i + 1][1].get<double>() -
             ring[i + 1][0].get<double>() * ring[i][1].get<double>();
    return 0.5 * a;
}

}  // namespace

TEST(VectorExport, GeoJsonPlaneAndWorld) {
    Model m = boxLensFault();
    auto idx = indexFor(m);
    auto s = computeSection(*idx, horizontalPlane(25.0));
    ASSERT_TRUE(s.ok());
    const auto plane = geoJson(*idx, vectorSource(s.value()), VectorFrame::Plane);
    EXPECT_EQ(plane["type"], "FeatureCollection");
    ASSERT_EQ(plane["features"].size(), 3u);  // host, lens, fault trace
    double hostArea = 0.0;
    for (const auto& f : plane["features"]) {
        if (f["properties"]["kind"] == "trace") {
            EXPECT_EQ(f["geometry"]["type"], "LineString");
            EXPECT_EQ(f["properties"]["name"], "F1");
            EXPECT_EQ(f["properties"]["part"], 0);
            continue;
        }
        EXPECT_EQ(f["geometry"]["type"], "MultiPolygon");
        double a = 0.0;
        for (const auto& poly : f["geometry"]["coordinates"]) {
            for (std::size_t r = 0; r < poly.size(); ++r) {
                EXPECT_EQ(poly[r].front(), poly[r].back());  // closed rings
                const double ra = ringAreaJson(poly[r]);
                EXPECT_EQ(ra > 0, r == 0);  // exterior counter-clockwise, holes clockwise
                a += ra;
            }
        }
        EXPECT_NEAR(a, f["properties"]["area_m2"].get<double>(), kAreaTolM2);
        if (f["properties"]["record"] == 1) {
            hostArea = a;
            EXPECT_TRUE(f["properties"]["attributes"].is_null());
        } else {
            EXPECT_NEAR(a, 400.0, kAreaTolM2);
            EXPECT_EQ(f["properties"]["attributes"]["name"], "Lens <ore>");
            EXPECT_EQ(f["properties"]["attributes"]["grade"], 12.5);
        }
    }
    EXPECT_NEAR(hostArea, 10000.0 - 400.0, kLargeAreaTolM2);
    // World frame: 3D positions at z = 25 inside the box.
    const auto world = geoJson(*idx, vectorSource(s.value()), VectorFrame::Projected);
    EXPECT_EQ(world["geoslice"]["frame"], "projected");
    EXPECT_EQ(world["crs"]["properties"]["name"], "urn:ogc:def:crs:EPSG::32650");
    // The plane frame names an engineering CRS, so that no GIS reads u/v as degrees.
    EXPECT_EQ(plane["crs"]["properties"]["name"].get<std::string>().rfind("ENGCRS[", 0), 0u);
    for (const auto& f : world["features"]) {
        if (f["properties"]["kind"] != "body") continue;
        for (const auto& poly : f["geometry"]["coordinates"])
            for (const auto& ring : poly)
                for (const auto& p : ring) {
                    ASSERT_EQ(p.size(), 3u);
                    EXPECT_NEAR(p[2].get<double>(), 25.0, kElevationTolM);
                    EXPECT_GE(p[0].get<double>(), -1e-9);
                    EXPECT_LE(p[0].get<double>(), 100.0 + 1e-9);
                }
    }
}

TEST(VectorExport, SvgOverlaysTheRaster) {
    Model m = boxLensFault();
    auto idx = indexFor(m);
    auto s = computeSection(*idx, horizontalPlane(25.0));
    ASSERT_TRUE(s.ok());
    auto svg = toSvg(*idx, vectorSource(s.value()), FrameRect{-10, -10, 110, 110}, 240, 240);
    ASSERT_TRUE(svg.ok());
    const std::string& t = svg.value();
    EXPECT_EQ(t.rfind("</svg>\n"), t.size() - 7);
    EXPECT_NE(t.find("fill-rule=\"evenodd\" data-record=\"1\""), std::string::npos);
    EXPECT_NE(t.find("data-record=\"2\""), std::string::npos);
    EXPECT_NE(t.find("<polyline"), std::string::npos);
    // The host's outer corner (u, v) = (0, 0) in plane units is pixel (20, 220): plan view,
    // u east, v north, origin at the world origin for a horizontal plane.
    EXPECT_NE(t.find("20.000,220.000"), std::string::npos);
    EXPECT_FALSE(toSvg(*idx, vectorSource(s.value()), FrameRect{0, 0, 0, 1}, 10, 10).ok());
}

TEST(VectorExport, PolylineSectionInWorldCoordinates) {
    Model m = boxLensFault();
    auto idx = indexFor(m);
    auto s = computePolylineSection(*idx, {{-10, 50}, {50, 50}, {50, 150}});
    ASSERT_TRUE(s.ok());
    const auto j = geoJson(*idx, vectorSource(s.value()), VectorFrame::Projected);
    std::size_t bodies = 0;
    for (const auto& f : j["features"]) {
        if (f["properties"]["kind"] != "body") continue;
        ++bodies;
        for (const auto& poly : f["geometry"]["coordinates"])
            for (const auto& ring : poly)
                for (const auto& p : ring) {
                    // On the line: y = 50 (first leg) or x = 50 (second leg).
                    const double x = p[0].get<double>(), y = p[1].get<double>();
                    EXPECT_TRUE(std::abs(y - 50.0) < 1e-9 || std::abs(x - 50.0) < 1e-9) << x << " " << y;
                }
    }
    EXPECT_EQ(bodies, 2u);
    const auto plane = geoJson(*idx, vectorSource(s.value()), VectorFrame::Plane);
    for (const auto& f : plane["features"])
        if (f["properties"]["record"] == 2) {
            EXPECT_NEAR(f["properties"]["area_m2"].get<double>(), 200.0, kAreaTolM2);
        }
}

// WGS 84 lon/lat (RFC 7946): a 100 m box placed in UTM zone 50N converts through PROJ to the
// positions an independent per-point conversion gives, rings keep the right-hand rule in
// lon/lat, there is no "crs" member, and frames that cannot be are refused by name.
TEST(VectorExport, GeoJsonLonLatFollowsRfc7946) {
    Model m = boxLensFault();
    auto idx = indexFor(m);
    auto s = computeSection(*idx, horizontalPlane(25.0));
    ASSERT_TRUE(s.ok());
    VectorSource src = vectorSource(s.value());
    const auto local = src.toWorld;
    const glm::dvec3 shift{500000.0, 3400000.0, 0.0};  // UTM 50N: lon 117, lat ~30.7
    src.toWorld = [local, shift](const glm::dvec2& p) { return local(p) + shift; };
    const Crs utm = Crs::fromEpsg(32650).value(), wgs84 = Crs::fromEpsg(4326).value();
    auto t = CrsTransform::forArea(utm, wgs84, {116.9, 30.6, 117.1, 30.8});
    ASSERT_TRUE(t.ok()) << t.error().message;
    auto space = geoJsonSpace(src, VectorFrame::LonLat, utm, &t.value(), "");
    ASSERT_TRUE(space.ok()) << space.error().message;
    auto doc = toGeoJson(*idx, src, space.value());
    ASSERT_TRUE(doc.ok()) << doc.error().message;
    const auto j = nlohmann::json::parse(doc.value().dump());
    EXPECT_FALSE(j.contains("crs"));
    EXPECT_EQ(j["geoslice"]["frame"], "world");
    EXPECT_EQ(j["geoslice"]["modelCrs"], "EPSG:32650");
    std::size_t positions = 0;
    for (const auto& f : j["features"]) {
        if (f["properties"]["kind"] != "body") continue;
        for (const auto& poly : f["geometry"]["coordinates"])
            for (std::size_t r = 0; r < poly.size(); ++r) {
                EXPECT_EQ(ringAreaJson(poly[r]) > 0, r == 0);  // right-hand rule in lon/lat
                for (const auto& p : poly[r]) {
                    ASSERT_EQ(p.size(), 3u);
                    const double lon = p[0].get<double>(), lat = p[1].get<double>();
                    EXPECT_GT(lon, 116.99);
                    EXPECT_LT(lon, 117.01);
                    EXPECT_GT(lat, 30.7);
                    EXPECT_LT(lat, 30.8);
                    EXPECT_NEAR(p[2].get<double>(), 25.0, kElevationTolM);
                    // Back to UTM with a separate conversion: inside the shifted box.
                    auto back = convertPoint(wgs84, utm, {lon, lat, 0.0});
                    ASSERT_TRUE(back.ok());
                    EXPECT_GT(back.value().x, shift.x - 1e-3);
                    EXPECT_LT(back.value().x, shift.x + 100.0 + 1e-3);
                    EXPECT_GT(back.value().y, shift.y - 1e-3);
                    EXPECT_LT(back.value().y, shift.y + 100.0 + 1e-3);
                    ++positions;
                }
            }
    }
    EXPECT_GT(positions, 8u);
    // A model without CRS has neither lon/lat nor projected coordinates; no operation: refused.
    auto none = geoJsonSpace(src, VectorFrame::LonLat, Crs::local(), nullptr, "");
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("space=plane"), std::string::npos) << none.error().message;
    auto own = geoJsonSpace(src, VectorFrame::Projected, Crs::local(), nullptr, "");
    ASSERT_TRUE(own.ok());  // the model's own x, y, z, named as a local engineering CRS
    EXPECT_EQ(own.value().crsMember["properties"]["name"].get<std::string>().rfind("ENGCRS[", 0), 0u);
    auto noOp = geoJsonSpace(src, VectorFrame::LonLat, utm, nullptr, "no WGS 84 coordinates: ballpark only");
    ASSERT_FALSE(noOp.ok());
    EXPECT_NE(noOp.error().message.find("ballpark only"), std::string::npos);
}
