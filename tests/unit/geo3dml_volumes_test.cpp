// Geo3DML volumes (tetrahedra, cuboids, truncated grids, rectified grids), the <GeoModel>
// root and Geo3DProject includes, on the samples in tests/data/geo3dml (WuZixing/Geo3DML,
// MIT). Counts and volumes are computed here from the XML with pugixml and plain double
// arithmetic, independently of the loader. Volumes compare to 1e-9 relative: the samples'
// coordinates are short decimals below 1000 m, so the divergence sum over the boundary
// triangles rounds at about 1e-13 relative; 1e-9 is the issue's bar.
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "tests/common/tolerances.hpp"

namespace geoslice {
namespace {

namespace fs = std::filesystem;
using test::kShellVsCellSumRelTol;  // relative, a body's shell volume against its cells' sum
const fs::path kDataDir = fs::path(GEOSLICE_TEST_DATA_DIR) / "geo3dml";

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string u8s(const char8_t* s) { return std::string(reinterpret_cast<const char*>(s)); }

// Expected parts of a Geo3DModel file, by this rule: a feature whose shape is a GeoTin with
// triangles is a body (the samples' TINs are closed); a volume element (tetrahedra,
// cuboids, prisms, truncated grid) with at least one Vertex, or a gml:RectifiedGrid, is a
// body; points and lines are neither.
struct Expected {
    std::size_t bodies = 0, surfaces = 0;
};
Expected expectedParts(const std::string& xml) {
    pugi::xml_document doc;
    EXPECT_TRUE(doc.load_string(xml.c_str()));
    Expected e;
    for (const auto& x : doc.select_nodes("//*[local-name()='Shape']")) {
        const pugi::xml_node g = x.node().first_child();
        const std::string name = g.name();
        const std::string local = name.substr(name.find(':') == std::string::npos ? 0 : name.find(':') + 1);
        const bool hasVertex = !g.select_nodes(".//*[local-name()='Vertex']").empty();
        if (local == "GeoTin" && !g.select_nodes(".//*[local-name()='Triangle']").empty())
            ++e.bodies;
        else if (local == "RectifiedGrid")
            ++e.bodies;
        else if ((local == "GeoTetrahedronVolume" || local == "GeoCuboidVolume" ||
                  local == "GeoTriangularPrismVolume" || local == "GeoTruncatedRegularGrid") &&
                 hasVertex)
            ++e.bodies;
    }
    return e;
}

const Part* bodyNamed(const Model& m, const std::string& name) {
    for (const auto& b : m.bodies)
        if (b.name == name) return &b;
    return nullptr;
}

std::vector<glm::dvec3> vertices(pugi::xml_node volume) {
    std::vector<glm::dvec3> out;
    for (const auto& v : volume.select_nodes(".//*[local-name()='Vertex']")) {
        std::istringstream ss(v.node().text().get());
        glm::dvec3 p;
        ss >> p.x >> p.y >> p.z;
        out.push_back(p);
    }
    return out;
}

TEST(Geo3dmlVolumes, EverySampleModelLoadsWithTheRightCounts) {
    for (const char* file : {"model_Volume_1.xml", "model_Volume_2.xml"}) {
        SCOPED_TRACE(file);
        const std::string xml = readText(kDataDir / file);
        const Expected e = expectedParts(xml);
        auto m = loadModel((kDataDir / file).string());
        ASSERT_TRUE(m) << m.error().message;
        EXPECT_EQ(m->bodies.size(), e.bodies);
        EXPECT_EQ(m->surfaces.size(), e.surfaces);
        EXPECT_FALSE(m->validation.hasErrors());
        for (const auto& b : m->bodies) EXPECT_TRUE(b.report.closed) << b.name;
    }
    EXPECT_EQ(expectedParts(readText(kDataDir / "model_Volume_1.xml")).bodies, 3u);
    EXPECT_EQ(expectedParts(readText(kDataDir / "model_Volume_2.xml")).bodies, 4u);
}

TEST(Geo3dmlVolumes, VolumesEqualTheCellsOfTheFile) {
    const std::string xml = readText(kDataDir / "model_Volume_1.xml");
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(xml.c_str()));
    auto m = parseGeo3dml(xml, "model_Volume_1.xml");
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_EQ(m->crs.epsg(), 4526);  // declared CRS kept

    // 地层D: the sum of its tetrahedra.
    const pugi::xml_node tets = doc.select_node("//*[local-name()='GeoTetrahedronVolume']").node();
    const std::vector<glm::dvec3> tv = vertices(tets);
    double tetSum = 0;
    for (const auto& t : tets.select_nodes(".//*[local-name()='Tetrahedron']")) {
        std::istringstream ss(t.node().first_child().text().get());
        int a, b, c, d;
        ss >> a >> b >> c >> d;
        tetSum += std::abs(glm::dot(tv[b] - tv[a], glm::cross(tv[c] - tv[a], tv[d] - tv[a]))) / 6.0;
    }
    const Part* d = bodyNamed(m.value(), u8s(u8"地层D"));
    ASSERT_TRUE(d);
    EXPECT_NEAR(signedVolume(d->mesh), tetSum, kShellVsCellSumRelTol * tetSum);

    // 地层E: three axis-aligned cuboids: the products of their extents.
    const pugi::xml_node cub = doc.select_node("//*[local-name()='GeoCuboidVolume']").node();
    const std::vector<glm::dvec3> cv = vertices(cub);
    double boxSum = 0;
    for (const auto& c : cub.select_nodes(".//*[local-name()='Cuboid']")) {
        std::istringstream ss(c.node().first_child().text().get());
        glm::dvec3 lo(1e300), hi(-1e300);
        int i;
        while (ss >> i) lo = glm::min(lo, cv[i]), hi = glm::max(hi, cv[i]);
        boxSum += (hi.x - lo.x) * (hi.y - lo.y) * (hi.z - lo.z);
    }
    EXPECT_EQ(boxSum, 1462500.0);  // 100x100x100 + 100x50x80 + 50x25x50
    const Part* e = bodyNamed(m.value(), u8s(u8"地层E"));
    ASSERT_TRUE(e);
    EXPECT_NEAR(signedVolume(e->mesh), boxSum, kShellVsCellSumRelTol * boxSum);

    // 地层C: a gml:RectifiedGrid: |det(offset vectors)| x cells between the limits.
    const Part* c = bodyNamed(m.value(), u8s(u8"地层C"));
    ASSERT_TRUE(c);
    const double grid =
        4.8 * 10 * 6.8 * (7 * 6 * 4);  // offsets (4.8 4.8 2) (0 10 0) (0 0 6.8); limits -1..6, -1..5, -1..3
    EXPECT_NEAR(signedVolume(c->mesh), grid, kShellVsCellSumRelTol * grid);

    // model_Volume_2 地层B: 4 x 2 x 2 hexahedra given by faces; x 250..450, y 0..100, from
    // z = 10 up to z = 100 + y / 10: 200 * (90 * 100 + 0.1 * 100^2 / 2).
    auto m2 = parseGeo3dml(readText(kDataDir / "model_Volume_2.xml"), "model_Volume_2.xml");
    ASSERT_TRUE(m2) << m2.error().message;
    const Part* b = bodyNamed(m2.value(), u8s(u8"地层B"));
    ASSERT_TRUE(b);
    EXPECT_NEAR(signedVolume(b->mesh), 1.9e6, kShellVsCellSumRelTol * 1.9e6);

    // model_Volume_2 地层D: prisms with vertical edges and planar ends, each of volume
    // area(xy triangle) x (mean top z - mean bottom z); the file's two volume models name
    // their features alike, and this one is the prism feature.
    pugi::xml_document doc2;
    const std::string xml2 = readText(kDataDir / "model_Volume_2.xml");
    ASSERT_TRUE(doc2.load_string(xml2.c_str()));
    const pugi::xml_node prisms = doc2.select_node("//*[local-name()='GeoTriangularPrismVolume']").node();
    const std::vector<glm::dvec3> pv = vertices(prisms);
    double prismSum = 0;
    for (const auto& pr : prisms.select_nodes(".//*[local-name()='Prism']")) {
        std::array<int, 3> bot{}, top{};
        std::istringstream sb(pr.node().select_node("*[local-name()='BottomTriangle']").node().text().get());
        std::istringstream st(pr.node().select_node("*[local-name()='TopTriangle']").node().text().get());
        sb >> bot[0] >> bot[1] >> bot[2];
        st >> top[0] >> top[1] >> top[2];
        const glm::dvec3 a = pv[bot[0]], bb = pv[bot[1]], cc = pv[bot[2]];
        const double area = std::abs((bb.x - a.x) * (cc.y - a.y) - (cc.x - a.x) * (bb.y - a.y)) / 2;
        prismSum += area * ((pv[top[0]].z + pv[top[1]].z + pv[top[2]].z) - (a.z + bb.z + cc.z)) / 3;
    }
    const Part* d2 = bodyNamed(m2.value(), u8s(u8"地层D"));
    ASSERT_TRUE(d2);
    EXPECT_GT(prismSum, 0);
    EXPECT_NEAR(signedVolume(d2->mesh), prismSum, kShellVsCellSumRelTol * prismSum);
}

// <GeoModel> roots (as Chinese tools write them), with or without a namespace, with http or
// https namespace URIs, load like <Geo3DModel>.
TEST(Geo3dmlVolumes, GeoModelRootInAnyNamespace) {
    const std::string xml = readText(kDataDir / "model_Volume_1.xml");
    auto reference = parseGeo3dml(xml, "v1.xml");
    ASSERT_TRUE(reference) << reference.error().message;
    auto replaceAll = [](std::string s, const std::string& from, const std::string& to) {
        for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
            s.replace(at, from.size(), to);
        return s;
    };
    const std::vector<std::string> variants = {
        replaceAll(xml, "geo3dml:Geo3DModel", "geo3dml:GeoModel"),
        replaceAll(replaceAll(xml, "geo3dml:Geo3DModel", "GeoModel"), "https://www.iheg", "http://www.iheg"),
        replaceAll(replaceAll(xml, "geo3dml:Geo3DModel", "GeoModel"),
                   " xmlns=\"https://www.iheg.cgs.gov.cn/Standard/geo3dml\"", ""),
    };
    for (const std::string& v : variants) {
        auto m = parseGeo3dml(v, "geomodel.xml");
        ASSERT_TRUE(m) << m.error().message;
        EXPECT_EQ(m->bodies.size(), reference->bodies.size());
        EXPECT_EQ(m->name, reference->name);
        EXPECT_EQ(m->crs.epsg(), 4526);
    }
}

// Borehole intervals and section boundaries (gml:LineString) load as model lines, one per
// feature; the borehole's marker points are not lines.
TEST(Geo3dmlVolumes, LineFilesLoadAsLines) {
    for (const char* file : {"model_drill.xml", "model_section.xml"}) {
        SCOPED_TRACE(file);
        const std::string xml = readText(kDataDir / file);
        pugi::xml_document doc;
        ASSERT_TRUE(doc.load_string(xml.c_str()));
        std::size_t expectedLines = 0, expectedPoints = 0;
        for (const auto& x : doc.select_nodes("//*[local-name()='GeoFeature']"))
            if (!x.node()
                     .select_nodes("*[local-name()='Geometry']/*[local-name()='Shape']//*[local-name()='LineString']")
                     .empty())
                ++expectedLines;
        // Lines of feature shapes; the section's coverage domains (ShapeProperty) are not geometry.
        for (const auto& x : doc.select_nodes("//*[local-name()='Shape']//*[local-name()='LineString']"))
            for (const auto& pl : x.node().select_nodes(".//*[local-name()='posList']")) {
                std::istringstream ss(pl.node().text().get());
                double v;
                std::size_t n = 0;
                while (ss >> v) ++n;
                expectedPoints += n / 3;
            }
        auto m = loadModel((kDataDir / file).string());
        ASSERT_TRUE(m) << m.error().message;
        EXPECT_TRUE(m->bodies.empty());
        EXPECT_TRUE(m->surfaces.empty());
        EXPECT_EQ(m->lines.size(), expectedLines);
        std::size_t points = 0;
        for (const auto& l : m->lines) {
            points += l.points.size();
            EXPECT_EQ(l.segments.size(), 2 * (l.points.size() - 1)) << l.name;
            EXPECT_TRUE(m->attributes.find(l.record)) << l.name;
        }
        EXPECT_EQ(points, expectedPoints);
        EXPECT_GT(expectedLines, 0u);
    }
}

// project.xml as delivered: its four models are included from the same folder; two of its
// three maps are missing (a warning names them), the third (map_stratum.xml) styles 地层A by
// its gml:id with a texture without coordinates whose border colour is 0 1 0 1.
TEST(Geo3dmlVolumes, ProjectIncludesAsDelivered) {
    auto m = loadModel((kDataDir / "project.xml").string());
    ASSERT_TRUE(m) << m.error().message;
    std::size_t bodies = 0, surfaces = 0;
    for (const char* f : {"model_drill.xml", "model_section.xml", "model_Volume_1.xml", "model_Volume_2.xml"}) {
        const Expected e = expectedParts(readText(kDataDir / f));
        bodies += e.bodies;
        surfaces += e.surfaces;
    }
    EXPECT_EQ(bodies, 7u);
    EXPECT_EQ(m->bodies.size(), bodies);
    EXPECT_EQ(m->surfaces.size(), surfaces);
    EXPECT_EQ(m->name, u8s(u8"示例项目"));
    EXPECT_EQ(m->crs.epsg(), 4526);
    // 地层C and 地层D are in both volume models: the second of each is told apart.
    // 地层C and 地层D are in both volume models: the second of each is told apart.
    EXPECT_TRUE(bodyNamed(m.value(), u8s(u8"地层C")));
    EXPECT_TRUE(bodyNamed(m.value(), u8s(u8"地层C (体数据示例模型-2)")));
    EXPECT_TRUE(bodyNamed(m.value(), u8s(u8"地层D (体数据示例模型-2)")));
    EXPECT_TRUE(bodyNamed(m.value(), u8s(u8"地层A")));
    EXPECT_TRUE(bodyNamed(m.value(), u8s(u8"地层B")));
    const std::string& warnings = m->notes.at("geo3dml_warnings");
    EXPECT_NE(warnings.find("xi:include 'map_drill.xml' is missing"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("xi:include 'map_section.xml' is missing"), std::string::npos) << warnings;
    EXPECT_FALSE(m->notes.count("geo3dml_maps_not_read"));
    EXPECT_EQ(m->notes.at("geo3dml_styles"), "1 map, 1 colour rules, 1 features coloured");
    const Part* a = bodyNamed(m.value(), u8s(u8"地层A"));
    ASSERT_TRUE(a);
    const AttributeRecord* rec = m->attributes.find(a->record);
    ASSERT_TRUE(rec);
    EXPECT_EQ(formatColour(rec->colour), "#00ff00");
    EXPECT_NE(rec->colourSource.find(u8s(u8"Geo3DML map '地层' style")), std::string::npos) << rec->colourSource;
    // The other strata keep the palette's colours (no rule selects them).
    const AttributeRecord* b = m->attributes.find(bodyNamed(m.value(), u8s(u8"地层B"))->record);
    EXPECT_EQ(b->colourSource.find("Geo3DML map"), std::string::npos) << b->colourSource;
}

// Map styles beyond the delivered sample: a rule without a filter colours every feature of
// its layer's class, a field filter selects by a field's text, a later rule wins over an
// earlier one, DiffuseColor and PBR BaseColor are read, a filter other than
// PropertyIsEqualTo and a rule matching nothing are warnings, a sidecar still wins.
TEST(Geo3dmlVolumes, MapStylesColourTheFeaturesTheySelect) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_g3d_styles_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    fs::copy_file(kDataDir / "model_Volume_2.xml", dir / "v2.xml", fs::copy_options::overwrite_existing);
    const std::string rule =
        R"(<se:Rule>%FILTER%<GeoSurfaceSymbolizer><Front>%MAT%</Front></GeoSurfaceSymbolizer></se:Rule>)";
    auto ruleWith = [&](const std::string& filter, const std::string& material) {
        std::string r = rule;
        r.replace(r.find("%FILTER%"), 8, filter);
        r.replace(r.find("%MAT%"), 5, material);
        return r;
    };
    auto eq = [](const std::string& prop, const std::string& lit) {
        return "<ogc:Filter><ogc:PropertyIsEqualTo><ogc:PropertyName>" + prop + "</ogc:PropertyName><ogc:Literal>" +
               lit + "</ogc:Literal></ogc:PropertyIsEqualTo></ogc:Filter>";
    };
    const std::string rules =
        ruleWith("", "<Material><DiffuseColor>0.2 0.4 0.6</DiffuseColor></Material>") +  // every feature
        ruleWith(eq("stratigraphic_name", u8s(u8"蓟县组")),
                 "<PBRMaterial><BaseColor>1 0 0 1</BaseColor></PBRMaterial>") +
        ruleWith("<ogc:Filter><ogc:Or/></ogc:Filter>", "<Material><DiffuseColor>0 0 0</DiffuseColor></Material>") +
        ruleWith(eq("gml:id", "no-such-feature"), "<Material><DiffuseColor>1 1 1</DiffuseColor></Material>");
    std::ofstream(dir / "map.xml")
        << R"(<Geo3DMap xmlns="https://www.iheg.cgs.gov.cn/Standard/geo3dml" xmlns:gml="http://www.opengis.net/gml/3.2" )"
        << R"(xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:ogc="http://www.opengis.net/ogc" xmlns:se="http://www.opengis.net/se">)"
        << "<Name>styles</Name><Layers><Layer><Geo3DLayer><gml:name>L</gml:name>"
        << R"(<FeatureClass xlink:href="#4c654ddd-b574-4bbc-81e9-7b5b7be8bd7d"/>)"
        << "<Styles><Style><Geo3DStyle><FeatureStyle><se:FeatureTypeStyle>" << rules
        << "</se:FeatureTypeStyle></FeatureStyle></Geo3DStyle></Style></Styles></Geo3DLayer></Layer></Layers></"
           "Geo3DMap>";
    std::ofstream(dir / "p.xml") << R"(<Geo3DProject xmlns="http://www.iheg.cgs.gov.cn/Standard/geo3dml" )"
                                 << R"(xmlns:xi="http://www.w3.org/2001/XInclude"><Name>p</Name>)"
                                 << R"(<Models><Model><xi:include href="v2.xml"/></Model></Models>)"
                                 << R"(<Maps><Map><xi:include href="map.xml"/></Map></Maps></Geo3DProject>)";
    auto m = loadModel((dir / "p.xml").string());
    ASSERT_TRUE(m) << m.error().message;
    std::size_t blue = 0;
    for (const Part& p : m->bodies) {
        const AttributeRecord* r = m->attributes.find(p.record);
        ASSERT_TRUE(r) << p.name;
        if (p.name == u8s(u8"地层A")) {  // its stratigraphic_name is 蓟县组: the later rule wins
            EXPECT_EQ(formatColour(r->colour), "#ff0000");
            EXPECT_NE(r->colourSource.find("BaseColor"), std::string::npos) << r->colourSource;
        } else if (formatColour(r->colour) == "#336699") {
            ++blue;
            EXPECT_NE(r->colourSource.find("DiffuseColor"), std::string::npos) << r->colourSource;
        }
    }
    EXPECT_GE(blue, 1u) << "the rule without a filter colours the class's other features";
    const std::string& w = m->notes.at("geo3dml_warnings");
    EXPECT_NE(w.find("rule 3: its filter <ogc:Or> is not read"), std::string::npos) << w;
    EXPECT_NE(w.find("rule 4: matches no feature (gml:id = 'no-such-feature')"), std::string::npos) << w;
    // A sidecar still wins over the map.
    const RecordId aId = bodyNamed(m.value(), u8s(u8"地层A"))->record;
    std::ofstream(dir / "p.attributes.json") << R"({"records": [{"id": )" << aId << R"(, "colour": "#123456"}]})";
    auto withSidecar = loadModel((dir / "p.xml").string());
    ASSERT_TRUE(withSidecar) << withSidecar.error().message;
    const AttributeRecord* a = withSidecar->attributes.find(bodyNamed(withSidecar.value(), u8s(u8"地层A"))->record);
    EXPECT_EQ(formatColour(a->colour), "#123456");
    fs::remove_all(dir);
}

// Includes outside the project's folder are refused (never read), missing ones are warnings.
TEST(Geo3dmlVolumes, IncludesOutsideTheFolderAreRefused) {
    const fs::path root = fs::temp_directory_path() / ("geoslice_g3d_" + std::to_string(::getpid()));
    const fs::path dir = root / "project";
    fs::create_directories(dir / "sub");
    fs::copy_file(kDataDir / "model_Volume_1.xml", dir / "sub" / "v1.xml");
    fs::copy_file(kDataDir / "model_Volume_2.xml", root / "outside.xml");
    fs::create_symlink(root / "outside.xml", dir / "link.xml");
    std::string includes;
    for (const char* href : {"sub/v1.xml", "../outside.xml", "sub/../../outside.xml", "/etc/passwd",
                             "http://example.com/m.xml", "link.xml", "gone.xml"})
        includes += std::string("<Model><xi:include href=\"") + href + "\"/></Model>";
    std::ofstream(dir / "p.xml") << "<Geo3DProject xmlns=\"http://www.iheg.cgs.gov.cn/Standard/geo3dml\" "
                                    "xmlns:xi=\"http://www.w3.org/2001/XInclude\"><Name>p</Name><Models>"
                                 << includes << "</Models></Geo3DProject>";
    auto m = loadModel((dir / "p.xml").string());
    ASSERT_TRUE(m) << m.error().message;
    EXPECT_EQ(m->bodies.size(), 3u);  // sub/v1.xml only
    const std::string& w = m->notes.at("geo3dml_warnings");
    for (const char* refused :
         {"'../outside.xml' refused", "'sub/../../outside.xml' refused", "'/etc/passwd' refused",
          "'http://example.com/m.xml' refused", "'link.xml' refused: it leads outside", "'gone.xml' is missing"})
        EXPECT_NE(w.find(refused), std::string::npos) << refused << " in " << w;
    fs::remove_all(root);
}

}  // namespace
}  // namespace geoslice
