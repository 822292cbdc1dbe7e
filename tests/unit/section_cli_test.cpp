// `geoslice section` end to end: images, areas JSON, and errors for bad input.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "tests/common/run_command.hpp"

// Metres: the first interval starts at the collar: the tracer's float tolerance (0.1 mm +
// 1e-6 x extent, section/rays/borehole.hpp) is under 1 mm.
constexpr double kCollarM = 1e-3;
// Relative: east + west halves against the whole: the plane offset passes through
// std::to_string (1e-6 m) and the JSON volumes are printed.
constexpr double kHalvesRelTol = 1e-6;

using geoslice::test::CmdResult;
using geoslice::test::runGeoslice;

TEST(SectionCli, ImagesAreasAndErrors) {
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 20000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const double ymid = 0.5 * (info["bounds"]["min"][1].get<double>() + info["bounds"]["max"][1].get<double>());

    const std::string ppm = (dir / "c.ppm").string(), pgm = (dir / "i.pgm").string();
    CmdResult r = runGeoslice("section " + glb + " --plane 0,1,0," + std::to_string(-ymid) + " --size 64x32 --out " +
                              ppm + " --out " + pgm + " --areas");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["image"]["width"], 64);
    EXPECT_GE(j["bodies"].size(), 7u);
    double total = 0.0;
    for (const auto& b : j["bodies"]) {
        EXPECT_GT(b["area_m2"].get<double>(), 0.0);
        EXPECT_EQ(b["open_chains"], 0);
        total += b["area_m2"].get<double>();
    }
    EXPECT_GT(total, 1e6);  // a 6 km x ~2.5 km section
    EXPECT_EQ(j["traces"], 2);
    EXPECT_EQ(std::filesystem::file_size(ppm), std::string("P6\n64 32\n255\n").size() + 64 * 32 * 3);
    EXPECT_EQ(std::filesystem::file_size(pgm), std::string("P5\n64 32\n65535\n").size() + 64 * 32 * 2);

    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 32x32").exitCode, 0);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane nan,0,1,0").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane 0,0,0,1").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --plane 1,2,3").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 99999").exitCode, 1);  // misses the model
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 0x10").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --size 100000x100000").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --out x.tiff").exitCode, 2);
    EXPECT_NE(runGeoslice("section " + (dir / "missing.glb").string() + " --elevation 900").exitCode, 0);
    std::filesystem::remove_all(dir);
}

TEST(SectionCli, LineVectorsImagesBoreholeAndReserves) {
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_cli2_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 20000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const auto& lo = info["bounds"]["min"];
    const auto& hi = info["bounds"]["max"];
    auto at = [&](double fx, double fy) {
        const double x = lo[0].get<double>() + fx * (hi[0].get<double>() - lo[0].get<double>());
        const double y = lo[1].get<double>() + fy * (hi[1].get<double>() - lo[1].get<double>());
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.3f,%.3f", x, y);
        return std::string(buf);
    };
    // A bent line A-B-C: images (PNG, JPEG, PGM), GeoJSON in world coordinates, SVG, areas.
    const std::string line = at(0.1, 0.2) + "," + at(0.5, 0.5) + "," + at(0.9, 0.4);
    const std::string png = (dir / "c.png").string(), jpg = (dir / "c.jpg").string(), pgm = (dir / "i.pgm").string(),
                      gj = (dir / "s.geojson").string(), svg = (dir / "s.svg").string();
    CmdResult r =
        runGeoslice("section " + glb + " --line " + line + " --size 96x48 --out " + png + " --out " + jpg + " --out " +
                    pgm + " --geojson " + gj + " --geojson-frame projected --svg " + svg + " --areas");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frame"]["line"].size(), 3u);
    EXPECT_GE(j["bodies"].size(), 7u);
    for (const auto& b : j["bodies"]) EXPECT_GT(b["area_m2"].get<double>(), 0.0);
    std::ifstream png1(png, std::ios::binary);
    char sig[8] = {};
    png1.read(sig, 8);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG");
    EXPECT_GT(std::filesystem::file_size(jpg), 100u);
    std::ifstream gjIn(gj);
    auto g = nlohmann::json::parse(gjIn);
    EXPECT_EQ(g["type"], "FeatureCollection");
    EXPECT_EQ(g["crs"]["properties"]["name"], "urn:ogc:def:crs:EPSG::4523");
    EXPECT_GE(g["features"].size(), 7u);
    std::ifstream svgIn(svg);
    const std::string svgText((std::istreambuf_iterator<char>(svgIn)), std::istreambuf_iterator<char>());
    EXPECT_NE(svgText.find("<svg"), std::string::npos);
    EXPECT_NE(svgText.find("fill-rule=\"evenodd\""), std::string::npos);
    EXPECT_EQ(runGeoslice("section " + glb + " --line 1,2,3").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --line 1,2,x,4").exitCode, 2);
    EXPECT_EQ(runGeoslice("section " + glb + " --line 0,0,1,1").exitCode, 1);  // misses the model
    EXPECT_EQ(runGeoslice("section " + glb + " --elevation 900 --geojson-frame lonlat").exitCode, 2);

    // Borehole at the map centre: JSON intervals, collar, attributes.
    const std::string c = at(0.5, 0.5);
    const std::string cx = c.substr(0, c.find(',')), cy = c.substr(c.find(',') + 1);
    r = runGeoslice("borehole " + glb + " --x " + cx + " --y " + cy + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto bh = nlohmann::json::parse(r.out);
    ASSERT_GE(bh["intervals"].size(), 3u);
    EXPECT_NEAR(bh["intervals"][0]["from_collar_m"].get<double>(), 0.0, kCollarM);
    EXPECT_FALSE(bh["intervals"][0]["attributes"].is_null());
    for (std::size_t i = 1; i < bh["intervals"].size(); ++i)
        EXPECT_LE(bh["intervals"][i - 1]["to_m"].get<double>(), bh["intervals"][i]["from_m"].get<double>());
    EXPECT_EQ(runGeoslice("borehole " + glb + " --x " + cx + " --y " + cy).exitCode, 0);
    EXPECT_EQ(runGeoslice("borehole " + glb + " --x 0 --y 0").exitCode, 1);  // outside the map extent
    EXPECT_EQ(runGeoslice("borehole " + glb + " --x nan --y 0").exitCode, 2);
    EXPECT_EQ(runGeoslice("borehole " + glb + " --from 1,2 --dir 0,0,-1").exitCode, 2);

    // Reserves: whole model, and the two sides of a vertical plane adding up.
    r = runGeoslice("reserves " + glb + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto whole = nlohmann::json::parse(r.out);
    const double xm = 0.5 * (lo[0].get<double>() + hi[0].get<double>());
    auto east =
        nlohmann::json::parse(runGeoslice("reserves " + glb + " --json --plane 1,0,0," + std::to_string(-xm)).out);
    auto west =
        nlohmann::json::parse(runGeoslice("reserves " + glb + " --json --plane -1,0,0," + std::to_string(xm)).out);
    ASSERT_EQ(whole["bodies"].size(), east["bodies"].size());
    for (std::size_t i = 0; i < whole["bodies"].size(); ++i) {
        const double v = whole["bodies"][i]["net_volume_m3"].get<double>();
        EXPECT_GT(v, 0.0);
        EXPECT_NEAR(east["bodies"][i]["net_volume_m3"].get<double>() + west["bodies"][i]["net_volume_m3"].get<double>(),
                    v, kHalvesRelTol * v);
    }
    EXPECT_EQ(runGeoslice("reserves " + glb).exitCode, 0);
    EXPECT_EQ(runGeoslice("reserves " + glb + " --plane 0,0,0,1").exitCode, 2);
    std::filesystem::remove_all(dir);
}

// `geoslice section --print`: a sheet as PDF, SVG and PNG; bad sheet flags exit 2 naming the flag.
TEST(SectionCli, PrintSheets) {
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_cli3_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 20000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const double ymid = 0.5 * (info["bounds"]["min"][1].get<double>() + info["bounds"]["max"][1].get<double>());
    const std::string plane = " --plane 0,1,0," + std::to_string(-ymid);
    auto withStderr = [](const std::string& args) {  // stdout and stderr, for the error messages
        return geoslice::test::runCommand(std::string(GEOSLICE_BINARY) + " " + args + " 2>&1");
    };
    auto read = [](const std::filesystem::path& p) {
        std::ifstream f(p, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    };
    CmdResult r = runGeoslice("section " + glb + plane + " --vx 2 --paper A4 --print " + (dir / "s.pdf").string());
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_EQ(read(dir / "s.pdf").rfind("%PDF-", 0), 0u);
    r = runGeoslice("section " + glb + " --elevation 300 --orientation portrait --print " + (dir / "s.svg").string());
    ASSERT_EQ(r.exitCode, 0) << r.out;
    const std::string svg = read(dir / "s.svg");
    EXPECT_NE(svg.find("<text"), std::string::npos);
    EXPECT_NE(svg.find("Horizontal slice at elevation 300 m"), std::string::npos);
    r = runGeoslice("section " + glb + plane + " --paper A5 --dpi 50 --print " + (dir / "s.png").string());
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_EQ(read(dir / "s.png").substr(1, 3), "PNG");

    struct Bad {
        std::string flags, needle;
    };
    for (const Bad& b : {Bad{"--paper B7", "--paper"}, Bad{"--orientation sideways", "--orientation"},
                         Bad{"--scale 0", "--scale"}, Bad{"--scale 100 --paper A5", "--scale: at 1:100"},
                         Bad{"--dpi 5000", "--dpi"}, Bad{"--vx 0", "--vx"}, Bad{"--date 2026-02-30", "--date"}}) {
        r = withStderr("section " + glb + plane + " " + b.flags + " --print " + (dir / "bad.pdf").string());
        EXPECT_EQ(r.exitCode, 2) << b.flags;
        EXPECT_NE(r.out.find(b.needle), std::string::npos) << b.flags << ": " << r.out;
    }
    r = withStderr("section " + glb + plane + " --print " + (dir / "s.doc").string());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.out.find("--print"), std::string::npos) << r.out;
    std::filesystem::remove_all(dir);
}

namespace {

// GDAL's reading of a GeoJSON file: the layer SRS (WKT) and extent, from `ogrinfo -so -al`.
struct GdalLayer {
    std::string text;  // ogrinfo's whole report
    double x0 = NAN, y0 = NAN, x1 = NAN, y1 = NAN;
};

GdalLayer gdalRead(const std::string& path) {
    GdalLayer l;
    l.text = geoslice::test::runCommand("ogrinfo -ro -so -al '" + path + "' 2>&1").out;
    const auto at = l.text.find("Extent: (");
    if (at != std::string::npos)
        std::sscanf(l.text.c_str() + at, "Extent: (%lf, %lf) - (%lf, %lf)", &l.x0, &l.y0, &l.x1, &l.y1);
    return l;
}

}  // namespace

// GeoJSON as GIS tools read it (GDAL's ogrinfo and ogr2ogr to GeoPackage, the real client):
// space world is WGS 84 lon/lat inside the model's lon/lat box, projected keeps the model's
// EPSG code, plane is an engineering CRS (metres on a local plane, never degrees).
TEST(SectionCli, GeoJsonAsGdalReadsIt) {
    if (geoslice::test::runCommand("command -v ogrinfo ogr2ogr >/dev/null 2>&1").exitCode != 0)
        GTEST_FAIL() << "ogrinfo/ogr2ogr not installed (gdal-bin, scripts/install-deps.sh)";
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_gdal_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 8000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    const auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const auto& ll = info["lonlat_bounds"];
    const auto& b = info["bounds"];
    const double zmid = 0.5 * (b["min"][2].get<double>() + b["max"][2].get<double>());
    auto write = [&](const std::string& frame) {
        const std::string out = (dir / (frame + ".geojson")).string();
        CmdResult r =
            runGeoslice("section " + glb + " --elevation " + std::to_string(zmid) + " --size 64x64 --geojson " + out +
                        (frame.empty() ? "" : " --geojson-frame " + frame));
        EXPECT_EQ(r.exitCode, 0) << frame;
        return out;
    };
    // Default = world: WGS 84 degrees inside the model's lon/lat box.
    for (const std::string frame : {"", "world"}) {
        const GdalLayer l = gdalRead(write(frame));
        EXPECT_NE(l.text.find("GEOGCRS[\"WGS 84\""), std::string::npos) << l.text;
        EXPECT_GE(l.x0, ll["min"][0].get<double>() - 1e-6) << l.text;
        EXPECT_LE(l.x1, ll["max"][0].get<double>() + 1e-6) << l.text;
        EXPECT_GE(l.y0, ll["min"][1].get<double>() - 1e-6) << l.text;
        EXPECT_LE(l.y1, ll["max"][1].get<double>() + 1e-6) << l.text;
        EXPECT_GT(l.x1 - l.x0, 0.001) << l.text;  // a section across the model, in degrees
    }
    // Projected: EPSG:4523 as GDAL reads the crs member, kept by ogr2ogr in a GeoPackage.
    const std::string projected = write("projected");
    const GdalLayer p = gdalRead(projected);
    EXPECT_NE(p.text.find("ID[\"EPSG\",4523]"), std::string::npos) << p.text;
    EXPECT_GE(p.x0, b["min"][0].get<double>() - 1e-6);
    EXPECT_LE(p.x1, b["max"][0].get<double>() + 1e-6);
    EXPECT_GE(p.y0, b["min"][1].get<double>() - 1e-6);
    EXPECT_LE(p.y1, b["max"][1].get<double>() + 1e-6);
    const std::string gpkg = (dir / "p.gpkg").string();
    ASSERT_EQ(geoslice::test::runCommand("ogr2ogr -f GPKG '" + gpkg + "' '" + projected + "' 2>&1").exitCode, 0);
    const GdalLayer g = gdalRead(gpkg);
    EXPECT_NE(g.text.find("ID[\"EPSG\",4523]"), std::string::npos) << g.text;
    EXPECT_NEAR(g.x0, p.x0, 1e-6);
    EXPECT_NEAR(g.y1, p.y1, 1e-6);
    // Plane: an engineering CRS; not WGS 84, whatever the numbers.
    const std::string plane = write("plane");
    const GdalLayer e = gdalRead(plane);
    EXPECT_NE(e.text.find("ENGCRS[\"geoslice section plane\""), std::string::npos) << e.text;
    EXPECT_EQ(e.text.find("WGS 84"), std::string::npos) << e.text;
    const std::string gpkg2 = (dir / "e.gpkg").string();
    ASSERT_EQ(geoslice::test::runCommand("ogr2ogr -f GPKG '" + gpkg2 + "' '" + plane + "' 2>&1").exitCode, 0);
    EXPECT_EQ(gdalRead(gpkg2).text.find("EPSG\",4326"), std::string::npos);
    std::filesystem::remove_all(dir);
}

// DXF for CAD, read back by ezdxf (python3-ezdxf, the real client): R2000, no audit errors,
// a layer per unit in its colour, each unit's hatched area equal to the exact section's
// area from the GeoJSON, a name label per unit that fits; the projected form is 3D
// polylines at the slice's elevation inside the model's extent.
TEST(SectionCli, DxfReadBackByEzdxf) {
    const std::string python = "/usr/bin/python3";  // Debian's, which has python3-ezdxf
    if (geoslice::test::runCommand(python + " -c 'import ezdxf' 2>&1").exitCode != 0)
        GTEST_FAIL() << "python3-ezdxf is not installed (scripts/install-deps.sh)";
    const auto dir = std::filesystem::temp_directory_path() / ("gs_section_dxf_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string glb = (dir / "m.glb").string();
    ASSERT_EQ(runGeoslice("generate --triangles 8000 --crs EPSG:4523 --out " + glb).exitCode, 0);
    const auto info = nlohmann::json::parse(runGeoslice("info --json " + glb).out);
    const auto& b = info["bounds"];
    const double zmid = 0.5 * (b["min"][2].get<double>() + b["max"][2].get<double>());
    const std::string dxf = (dir / "s.dxf").string(), gj = (dir / "s.geojson").string(),
                      dxf3 = (dir / "s3.dxf").string();
    const std::string common = "section " + glb + " --elevation " + std::to_string(zmid) + " --size 64x64";
    ASSERT_EQ(runGeoslice(common + " --dxf " + dxf + " --geojson " + gj + " --geojson-frame plane").exitCode, 0);
    ASSERT_EQ(runGeoslice(common + " --dxf " + dxf3 + " --dxf-frame projected").exitCode, 0);
    EXPECT_EQ(runGeoslice(common + " --dxf " + dxf3 + " --dxf-frame world").exitCode, 2);
    const std::string script = std::string(GEOSLICE_TEST_DATA_DIR) + "/../unit/dxf_readback.py";
    CmdResult r = geoslice::test::runCommand(python + " " + script + " " + dxf);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    const auto d = nlohmann::json::parse(r.out);
    EXPECT_EQ(d["version"], "AC1015");
    EXPECT_EQ(d["audit_errors"], 0);
    std::ifstream gjIn(gj);
    const auto g = nlohmann::json::parse(gjIn);
    std::map<std::string, double> area;
    for (const auto& f : g["features"])
        if (f["properties"]["kind"] == "body")
            area[f["properties"]["name"].get<std::string>()] += f["properties"]["area_m2"].get<double>();
    ASSERT_GE(area.size(), 3u);
    for (const auto& [name, a] : area) {
        ASSERT_TRUE(d["hatch_area"].contains(name)) << name << " " << d.dump();
        // Square metres: the same rings, summed by ezdxf's reading of the DXF's decimals.
        EXPECT_NEAR(d["hatch_area"][name].get<double>(), a, 1e-6 * a + 1e-3) << name;
        EXPECT_TRUE(d["layers"].contains(name)) << name;
        EXPECT_FALSE(d["layers"][name].is_null()) << name;  // the unit's true colour
        EXPECT_GE(d["polylines"][name].get<int>(), 1) << name;
    }
    EXPECT_GE(d["texts"].size(), 1u);
    for (const auto& t : d["texts"]) EXPECT_EQ(t["text"], t["layer"]);
    r = geoslice::test::runCommand(python + " " + script + " " + dxf3);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    const auto d3 = nlohmann::json::parse(r.out);
    EXPECT_EQ(d3["audit_errors"], 0);
    EXPECT_TRUE(d3["hatch_area"].empty());
    for (int k = 0; k < 2; ++k) {
        EXPECT_GE(d3["bounds"]["min"][k].get<double>(), b["min"][k].get<double>() - 1e-6);
        EXPECT_LE(d3["bounds"]["max"][k].get<double>(), b["max"][k].get<double>() + 1e-6);
    }
    EXPECT_NEAR(d3["bounds"]["min"][2].get<double>(), zmid, 1e-6);
    EXPECT_NEAR(d3["bounds"]["max"][2].get<double>(), zmid, 1e-6);
    std::filesystem::remove_all(dir);
}
