// Geo3DML loader tests. Samples: tests/data/geo3dml (WuZixing/Geo3DML examples/data, MIT).
// Expected counts and coordinates are read from the XML here with pugixml, independently of
// the loader. Coordinates compare exactly: both sides parse the same decimal text to the
// nearest double.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include "model/io/loaders.hpp"

// t/m^3: a density given in kg/m^3, times 0.001: one rounding of 2650 * 0.001.
constexpr double kDensityTol = 1e-12;

namespace geoslice {
namespace {

const std::string kDataDir = std::string(GEOSLICE_TEST_DATA_DIR) + "/geo3dml/";

std::string readSample(const std::string& name) {
    std::ifstream in(kDataDir + name, std::ios::binary);
    EXPECT_TRUE(in.good()) << "cannot open " << kDataDir + name;
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// UTF-8 literal as std::string (C++20 u8"" literals are char8_t).
std::string u8s(const char8_t* s) { return std::string(reinterpret_cast<const char*>(s)); }

std::string_view localName(const char* q) {
    std::string_view s(q);
    const auto colon = s.rfind(':');
    return colon == std::string_view::npos ? s : s.substr(colon + 1);
}

pugi::xml_node child(pugi::xml_node n, std::string_view local) {
    for (pugi::xml_node c : n.children())
        if (c.type() == pugi::node_element && localName(c.name()) == local) return c;
    return {};
}

// One GeoTin as the test reads it: its feature's gml:name, positions and triangles.
struct ExpectedTin {
    std::string featureName;
    std::vector<std::array<double, 3>> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;  // positions of the vertices
};

std::vector<ExpectedTin> expectedTins(const std::string& xml) {
    pugi::xml_document doc;
    EXPECT_TRUE(doc.load_string(xml.c_str()));
    std::vector<ExpectedTin> out;
    for (const pugi::xpath_node& x : doc.select_nodes("//*[local-name()='GeoTin']")) {
        ExpectedTin tin;
        pugi::xml_node feature = x.node();
        while (feature && localName(feature.name()) != "GeoFeature") feature = feature.parent();
        tin.featureName = child(feature, "name").text().get();
        for (pugi::xml_node v : child(x.node(), "Vertices").children()) {
            std::array<double, 3> p{};
            std::istringstream ss(v.text().get());
            ss >> p[0] >> p[1] >> p[2];
            tin.positions.push_back(p);
        }
        for (pugi::xml_node t : child(x.node(), "Triangles").children()) {
            std::array<std::uint32_t, 3> tri{};
            std::istringstream ss(child(t, "VertexList").text().get());
            ss >> tri[0] >> tri[1] >> tri[2];
            tin.triangles.push_back(tri);
        }
        out.push_back(std::move(tin));
    }
    return out;
}

// Triangles as sorted vertex triples, sorted: equal whatever orientation validation chose.
std::vector<std::array<std::uint32_t, 3>> canonical(std::vector<std::array<std::uint32_t, 3>> tris) {
    for (auto& t : tris) std::sort(t.begin(), t.end());
    std::sort(tris.begin(), tris.end());
    return tris;
}

std::vector<std::array<std::uint32_t, 3>> trianglesOf(const Mesh& m) {
    std::vector<std::array<std::uint32_t, 3>> tris;
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
        tris.push_back({m.indices[t], m.indices[t + 1], m.indices[t + 2]});
    return tris;
}

// A minimal Geo3DModel with one feature. `shape` is the geometry inside Geometry/Shape.
std::string modelXml(const std::string& shape, const std::string& metadata = "", const std::string& fields = "",
                     const std::string& className = "地层", const std::string& featureName = "T1") {
    return R"(<?xml version="1.0" encoding="UTF-8"?>
<geo3dml:Geo3DModel xmlns:geo3dml="https://www.iheg.cgs.gov.cn/Standard/geo3dml"
  xmlns="https://www.iheg.cgs.gov.cn/Standard/geo3dml" xmlns:gml="http://www.opengis.net/gml/3.2"
  xmlns:swe="http://www.opengis.net/swe/2.0">
  <Name>测试模型</Name>
  <Type>3DModel</Type>
  <Metadata>)" +
           metadata + R"(</Metadata>
  <FeatureClasses><FeatureClass><GeoFeatureClass gml:id="fc1"><gml:name>)" +
           className +
           R"(</gml:name>
    <Features><Feature><GeoFeature gml:id="f1"><gml:name>)" +
           featureName + R"(</gml:name>
      <Fields>)" +
           fields + R"(</Fields>
      <Geometry><Shape>)" +
           shape + R"(</Shape></Geometry>
    </GeoFeature></Feature></Features>
  </GeoFeatureClass></FeatureClass></FeatureClasses>
</geo3dml:Geo3DModel>
)";
}

// A GeoTin from "x y z" vertex texts and "a b c" triangle texts (IndexNo = position unless given).
std::string geoTin(const std::vector<std::string>& vertices, const std::vector<std::string>& triangles,
                   const std::string& tinAttributes = "", const std::vector<std::string>& indexNos = {}) {
    std::string s = "<GeoTin gml:id=\"tin1\"" + tinAttributes + "><Vertices>";
    for (std::size_t i = 0; i < vertices.size(); ++i)
        s += "<Vertex gml:srsDimension=\"3\" IndexNo=\"" + (indexNos.empty() ? std::to_string(i) : indexNos[i]) +
             "\">" + vertices[i] + "</Vertex>";
    s += "</Vertices><Triangles>";
    for (std::size_t i = 0; i < triangles.size(); ++i)
        s += "<Triangle IndexNo=\"" + std::to_string(i) + "\"><VertexList>" + triangles[i] + "</VertexList></Triangle>";
    return s + "</Triangles></GeoTin>";
}

// A closed tetrahedron, counter-clockwise seen from outside, corner at (x0, y0, z0), 100 m edges.
std::string tetraTin(double x0 = 0.0, double y0 = 0.0, double z0 = 0.0, const std::string& tinAttributes = "") {
    const auto p = [&](double dx, double dy, double dz) {
        std::ostringstream ss;
        ss.precision(17);
        ss << x0 + dx << ' ' << y0 + dy << ' ' << z0 + dz;
        return ss.str();
    };
    return geoTin({p(0, 0, 0), p(100, 0, 0), p(0, 100, 0), p(0, 0, 100)}, {"0 2 1", "0 1 3", "0 3 2", "1 2 3"},
                  tinAttributes);
}

const std::string kSrs4526 =
    "<SpatialReferenceSystem><CoordinateReferenceSystem><Identifier>EPSG</Identifier>"
    "<Parameter>4526</Parameter></CoordinateReferenceSystem></SpatialReferenceSystem>";

std::string textField(const std::string& name, const std::string& value) {
    return "<Field Name=\"" + name + "\"><swe:Text><swe:value>" + value + "</swe:value></swe:Text></Field>";
}

std::string quantityField(const std::string& name, const std::string& value, const std::string& uom) {
    return "<Field Name=\"" + name + "\"><swe:Quantity><swe:uom code=\"" + uom + "\"/><swe:value>" + value +
           "</swe:value></swe:Quantity></Field>";
}

// An expected failure: the code, the source name and each fragment in the message.
void expectError(const Result<Model>& r, ErrorCode code, const std::string& source,
                 const std::vector<std::string>& fragments) {
    ASSERT_FALSE(r.ok()) << "expected an error mentioning " << (fragments.empty() ? "" : fragments[0]);
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(source), std::string::npos) << r.error().message;
    for (const std::string& f : fragments)
        EXPECT_NE(r.error().message.find(f), std::string::npos) << "missing '" << f << "' in: " << r.error().message;
}

TEST(Geo3dmlLoader, Volume2ClosedTinBodyWithCountsFromXml) {
    const std::string xml = readSample("model_Volume_2.xml");
    const std::vector<ExpectedTin> expected = expectedTins(xml);
    ASSERT_EQ(expected.size(), 1u);  // 地层A; the other features are grids and prisms

    Result<Model> r = parseGeo3dml(xml, "model_Volume_2.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Model& m = r.value();
    EXPECT_EQ(m.name, u8s(u8"体数据示例模型-2"));
    EXPECT_TRUE(m.crs.isLocal());    // this sample declares no CRS
    ASSERT_EQ(m.bodies.size(), 4u);  // 地层A (TIN), 地层B and 地层C (truncated grids), 地层D (prisms)
    EXPECT_TRUE(m.surfaces.empty());

    const Part& body = m.bodies[0];
    EXPECT_EQ(body.name, expected[0].featureName);
    EXPECT_EQ(body.name,
              "\xe5\x9c\xb0\xe5\xb1\x82"
              "A");  // 地层A, as bytes
    EXPECT_EQ(body.kind, PartKind::Body);
    EXPECT_TRUE(body.report.closed);
    EXPECT_EQ(body.mesh.vertexCount(), expected[0].positions.size());
    EXPECT_EQ(body.mesh.triangleCount(), expected[0].triangles.size());
    EXPECT_EQ(body.report.triangles, expected[0].triangles.size());
    for (std::size_t i = 0; i < expected[0].positions.size() && i < body.mesh.positions.size(); ++i) {
        EXPECT_EQ(body.mesh.positions[i].x, expected[0].positions[i][0]) << "vertex " << i;
        EXPECT_EQ(body.mesh.positions[i].y, expected[0].positions[i][1]) << "vertex " << i;
        EXPECT_EQ(body.mesh.positions[i].z, expected[0].positions[i][2]) << "vertex " << i;
    }
    EXPECT_EQ(canonical(trianglesOf(body.mesh)), canonical(expected[0].triangles));

    const AttributeRecord* rec = m.attributes.find(body.record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->name, "\xe8\x93\x9f\xe5\x8e\xbf\xe7\xbb\x84");  // 蓟县组, the stratigraphic_name field
    EXPECT_EQ(rec->name, u8s(u8"蓟县组"));
    EXPECT_EQ(rec->lithology, u8s(u8"灰岩"));
    EXPECT_EQ(rec->kind, "stratum");  // feature class 地层
    ASSERT_TRUE(rec->density.has_value());
    EXPECT_DOUBLE_EQ(*rec->density, 2.3);  // t/m3 as written; same decimal on both sides
    EXPECT_EQ(rec->extra.at("stratigraphic_name").get<std::string>(), u8s(u8"蓟县组"));
    EXPECT_EQ(rec->extra.at("lithology").get<std::string>(), u8s(u8"灰岩"));
    EXPECT_DOUBLE_EQ(rec->extra.at("density").get<double>(), 2.3);
    EXPECT_EQ(rec->extra.at("density:uom").get<std::string>(), "t/m3");
    EXPECT_EQ(rec->extra.at("gml:name").get<std::string>(), u8s(u8"地层A"));
    EXPECT_EQ(rec->extra.at("gml:id").get<std::string>(), "64a35c7c-1e87-4ef2-bcfe-2315bae0213a");
    EXPECT_EQ(rec->extra.at("geo3dml:featureClass").get<std::string>(), u8s(u8"地层"));
    // Field order survives (ordered_json), and the UTF-8 survives a JSON round trip.
    const std::string dumped = rec->extra.dump();
    EXPECT_LT(dumped.find("stratigraphic_name"), dumped.find("\"lithology\""));
    EXPECT_NE(dumped.find(u8s(u8"蓟县组")), std::string::npos);
}

struct NonTinCase {
    const char* file;
    std::vector<std::string> fragments;
};

TEST(Geo3dmlLoader, NonTinSamplesAreUnsupportedAndSayWhatTheyHold) {
    const std::vector<NonTinCase> cases = {
        {"map_stratum.xml", {"Geo3DMap"}},
        // From memory (no folder to resolve includes against): nothing is read.
        {"project.xml", {"Geo3DProject", "model_Volume_2.xml", "xi:include"}},
    };
    for (const NonTinCase& c : cases) {
        SCOPED_TRACE(c.file);
        expectError(parseGeo3dml(readSample(c.file), c.file), ErrorCode::Unsupported, c.file, c.fragments);
    }
}

TEST(Geo3dmlLoader, DeclaredEpsg4526IsRecognised) {
    // Plausible CGCS2000 3-degree zone 38 coordinates (false easting 38,500,000 m).
    const std::string xml = modelXml(tetraTin(38500100.0, 4400100.0, 50.0), kSrs4526);
    Result<Model> r = parseGeo3dml(xml, "epsg4526.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->crs.epsg(), 4526);
    EXPECT_TRUE(r->crs.isProjected());
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_TRUE(r->bodies[0].report.closed);
    EXPECT_EQ(r->bodies[0].mesh.positions[0].x, 38500100.0);  // as written: easting first
    EXPECT_FALSE(r->notes.count("crs_warning"));
    EXPECT_FALSE(r->notes.count("axis_order"));
}

TEST(Geo3dmlLoader, Epsg4526OnSampleCoordinatesIsKeptWithAWarning) {
    // The samples declare EPSG:4526 on coordinates of 0..200 m, which cannot be eastings of
    // zone 38; the CRS is kept as declared and the mismatch noted in the model's notes.
    std::string xml = readSample("model_Volume_2.xml");
    const std::string anchor = "<Version>1.0.0</Version>";
    ASSERT_NE(xml.find(anchor), std::string::npos);
    xml.replace(xml.find(anchor), anchor.size(), anchor + kSrs4526);
    Result<Model> r = parseGeo3dml(xml, "volume2_4526.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->crs.epsg(), 4526);
    ASSERT_TRUE(r->notes.count("crs_warning"));
    EXPECT_NE(r->notes.at("crs_warning").find("EPSG:4526"), std::string::npos);
}

TEST(Geo3dmlLoader, NorthingFirstCoordinatesAreSwappedToEastingFirst) {
    // Chinese surveying convention X = northing: the file lists northing, easting, height.
    const std::string xml = modelXml(tetraTin(4400100.0, 38500100.0, 50.0), kSrs4526);
    Result<Model> r = parseGeo3dml(xml, "northing_first.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    const Part& body = r->bodies[0];
    EXPECT_EQ(body.mesh.positions[0].x, 38500100.0);
    EXPECT_EQ(body.mesh.positions[0].y, 4400100.0);
    EXPECT_TRUE(body.report.closed);
    EXPECT_FALSE(body.report.flipped);  // winding was swapped with the axes: still outward
    EXPECT_GT(body.report.signedVolume, 0.0);
    EXPECT_TRUE(r->notes.count("axis_order"));
}

TEST(Geo3dmlLoader, SrsNameForms) {
    for (const std::string srs :
         {"EPSG:4526", "urn:ogc:def:crs:EPSG::4526", "http://www.opengis.net/def/crs/EPSG/0/4526"}) {
        SCOPED_TRACE(srs);
        Result<Model> r =
            parseGeo3dml(modelXml(tetraTin(38500100.0, 4400100.0, 0.0, " srsName=\"" + srs + "\"")), "srsname.xml");
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_EQ(r->crs.epsg(), 4526);
    }
}

TEST(Geo3dmlLoader, UnsupportedCrsStaysLocalAndIsRecorded) {
    // Any EPSG CRS PROJ knows is supported (model/crs/crs.hpp): WGS 84 / UTM zone 50N.
    const auto srsFor = [](const char* code) {
        return std::string(
                   "<SpatialReferenceSystem><CoordinateReferenceSystem><Identifier>EPSG</Identifier>"
                   "<Parameter>") +
               code + "</Parameter></CoordinateReferenceSystem></SpatialReferenceSystem>";
    };
    Result<Model> utm = parseGeo3dml(modelXml(tetraTin(), srsFor("32650")), "utm.xml");
    ASSERT_TRUE(utm.ok()) << utm.error().message;
    EXPECT_EQ(utm->crs.epsg(), 32650);
    // A code that is no CRS (99999) leaves the model local, with the text recorded.
    Result<Model> r = parseGeo3dml(modelXml(tetraTin(), srsFor("99999")), "unknown.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->crs.isLocal());
    EXPECT_EQ(r->notes.at("declared_crs"), "EPSG:99999");
    EXPECT_TRUE(r->notes.count("declared_crs_note"));
}

TEST(Geo3dmlLoader, ChineseFieldNamesMapToRecordFields) {
    const std::string fields = textField("地层名称", "须家河组") + textField("岩性", "石英砂岩") +
                               textField("时代", "晚三叠世") + quantityField("密度", "2650", "kg/m3") +
                               quantityField("品位", "3.5", "g/t") + textField("颜色", "#ff0000") +
                               textField("备注", "  保留空格  ");
    Result<Model> r = parseGeo3dml(modelXml(tetraTin(), "", fields, "矿体", "矿体1"), "fields.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_EQ(r->bodies[0].name, u8s(u8"矿体1"));
    const AttributeRecord* rec = r->attributes.find(r->bodies[0].record);
    ASSERT_NE(rec, nullptr);
    EXPECT_EQ(rec->name, u8s(u8"须家河组"));
    EXPECT_EQ(rec->kind, "orebody");
    EXPECT_EQ(rec->lithology, u8s(u8"石英砂岩"));
    EXPECT_EQ(rec->age, u8s(u8"晚三叠世"));
    ASSERT_TRUE(rec->density.has_value());
    EXPECT_NEAR(*rec->density, 2.65, kDensityTol);  // kg/m3 -> t/m3; 1e-12: one rounding of 2650 * 0.001
    ASSERT_TRUE(rec->grade.has_value());
    EXPECT_DOUBLE_EQ(*rec->grade, 3.5);
    EXPECT_EQ(rec->gradeUnit, "g/t");
    EXPECT_EQ(rec->colour, (Rgba8{255, 0, 0, 255}));
    EXPECT_EQ(rec->extra.at(u8s(u8"备注")).get<std::string>(), u8s(u8"  保留空格  "));  // verbatim
    EXPECT_DOUBLE_EQ(rec->extra.at(u8s(u8"密度")).get<double>(), 2650.0);               // as written
}

TEST(Geo3dmlLoader, FieldTypesAndRepeatedNames) {
    const std::string fields = textField("note", "a") + textField("note", "b") + textField("note", "c") +
                               "<Field Name=\"n\"><swe:Count><swe:value>7</swe:value></swe:Count></Field>"
                               "<Field Name=\"ok\"><swe:Boolean><swe:value>true</swe:value></swe:Boolean></Field>"
                               "<Field Name=\"empty\"><swe:Text/></Field>" +
                               quantityField("odd", "n/a", "m");
    Result<Model> r = parseGeo3dml(modelXml(tetraTin(), "", fields), "types.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const nlohmann::ordered_json& extra = r->attributes.find(r->bodies.at(0).record)->extra;
    EXPECT_EQ(extra.at("note"), "a");
    EXPECT_EQ(extra.at("note#2"), "b");
    EXPECT_EQ(extra.at("note#3"), "c");
    EXPECT_EQ(extra.at("n"), 7);
    EXPECT_EQ(extra.at("ok"), true);
    EXPECT_TRUE(extra.at("empty").is_null());
    EXPECT_EQ(extra.at("odd"), "n/a");  // a Quantity that is not a number stays text
    EXPECT_EQ(extra.at("odd:uom"), "m");
}

TEST(Geo3dmlLoader, ManyFieldsLoadInLinearTime) {
    // ordered_json looks keys up linearly; the loader must not (this would take minutes).
    std::string fields;
    for (int i = 0; i < 50000; ++i) fields += textField("f", std::to_string(i));
    Result<Model> r = parseGeo3dml(modelXml(tetraTin(), "", fields), "many.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    const nlohmann::ordered_json& extra = r->attributes.find(r->bodies.at(0).record)->extra;
    EXPECT_EQ(extra.at("f#50000"), "49999");
}

TEST(Geo3dmlLoader, OpenTinIsASurface) {
    const std::string tin = geoTin({"0 0 0", "100 0 0", "0 100 0", "100 100 5"}, {"0 1 2", "2 1 3"});
    Result<Model> r = parseGeo3dml(modelXml(tin, "", "", "断层", "F1"), "fault.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->bodies.empty());
    ASSERT_EQ(r->surfaces.size(), 1u);
    EXPECT_EQ(r->surfaces[0].kind, PartKind::Surface);
    EXPECT_FALSE(r->surfaces[0].report.closed);
    EXPECT_EQ(r->surfaces[0].mesh.triangleCount(), 2u);
    EXPECT_EQ(r->attributes.find(r->surfaces[0].record)->kind, "fault");
}

TEST(Geo3dmlLoader, IndexNoNeedNotBePositions) {
    const std::string tin = geoTin({"0 0 0", "100 0 0", "0 100 0", "0 0 100"},
                                   {"10 12 11", "10 11 13", "10 13 12", "11 12 13"}, "", {"10", "11", "12", "13"});
    Result<Model> r = parseGeo3dml(modelXml(tin), "indexno.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_EQ(r->bodies[0].mesh.vertexCount(), 4u);
    EXPECT_TRUE(r->bodies[0].report.closed);
}

TEST(Geo3dmlLoader, GmlTriangulatedSurfaceIsWelded) {
    const auto tri = [](const std::string& a, const std::string& b, const std::string& c) {
        return "<gml:Triangle><gml:exterior><gml:LinearRing><gml:posList srsDimension=\"3\" count=\"4\">" + a + " " +
               b + " " + c + " " + a + "</gml:posList></gml:LinearRing></gml:exterior></gml:Triangle>";
    };
    const std::string o = "0 0 0", x = "100 0 0", y = "0 100 0", z = "0 0 100";
    const std::string shape = "<gml:TriangulatedSurface><gml:patches>" + tri(o, y, x) + tri(o, x, z) + tri(o, z, y) +
                              tri(x, y, z) + "</gml:patches></gml:TriangulatedSurface>";
    Result<Model> r = parseGeo3dml(modelXml(shape), "gmltin.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_EQ(r->bodies[0].mesh.vertexCount(), 4u);
    EXPECT_EQ(r->bodies[0].mesh.triangleCount(), 4u);
    EXPECT_TRUE(r->bodies[0].report.closed);
}

TEST(Geo3dmlLoader, ProjectWithInlineModel) {
    const std::string model = modelXml(tetraTin());
    const std::string inner = model.substr(model.find("<geo3dml:Geo3DModel"));
    const std::string xml =
        "<Geo3DProject xmlns=\"https://www.iheg.cgs.gov.cn/Standard/geo3dml\"><Name>示例项目</Name>"
        "<Models><Model>" +
        inner + "</Model></Models></Geo3DProject>";
    Result<Model> r = parseGeo3dml(xml, "project_inline.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->name, u8s(u8"示例项目"));
    EXPECT_EQ(r->bodies.size(), 1u);
}

TEST(Geo3dmlLoader, Gb18030DeclaredFileIsConverted) {
    // 灰岩 in GB18030 is bb d2 d1 d2; the record must hold its UTF-8 form.
    std::string xml = modelXml(tetraTin(), "", textField("lithology", "\xbb\xd2\xd1\xd2"));
    xml.replace(xml.find("UTF-8"), 5, "GB2312");
    const std::string cjk[] = {u8s(u8"测试模型"), u8s(u8"地层")};  // other UTF-8 text in the template
    xml.replace(xml.find(cjk[0]), cjk[0].size(), "test");
    xml.replace(xml.find(cjk[1]), cjk[1].size(), "stratum");
    Result<Model> r = parseGeo3dml(xml, "gb.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->attributes.find(r->bodies.at(0).record)->lithology, u8s(u8"灰岩"));
}

// --- malformed input -------------------------------------------------------------------------

TEST(Geo3dmlLoader, EmptyInput) {
    expectError(parseGeo3dml("", "empty.xml"), ErrorCode::ParseError, "empty.xml", {"empty"});
    expectError(parseGeo3dml(" \n\t", "blank.xml"), ErrorCode::ParseError, "blank.xml", {"empty"});
}

TEST(Geo3dmlLoader, NotXml) {
    expectError(parseGeo3dml("solid cube\nfacet normal 0 0 1\n", "cube.stl"), ErrorCode::ParseError, "cube.stl",
                {"not XML"});
    expectError(parseGeo3dml("<a><b></a>", "mismatch.xml"), ErrorCode::ParseError, "mismatch.xml", {"byte "});
}

TEST(Geo3dmlLoader, TruncatedXml) {
    const std::string xml = readSample("model_Volume_2.xml");
    for (const std::size_t cut : {xml.size() / 3, xml.size() / 2, xml.size() - 30}) {
        SCOPED_TRACE(cut);
        expectError(parseGeo3dml(std::string_view(xml).substr(0, cut), "model_Volume_2.xml"), ErrorCode::ParseError,
                    "model_Volume_2.xml", {"byte ", "not well-formed XML"});
    }
}

TEST(Geo3dmlLoader, WrongRootElement) {
    expectError(parseGeo3dml("<html><body/></html>", "page.html"), ErrorCode::ParseError, "page.html",
                {"root element", "html"});
}

TEST(Geo3dmlLoader, VertexIndexOutOfRange) {
    const std::string tin = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"0 1 2", "0 1 9"});
    expectError(parseGeo3dml(modelXml(tin), "range.xml"), ErrorCode::ParseError, "range.xml",
                {"vertex index 9", "out of range", "Triangle[2]/VertexList", "byte "});
    const std::string mapped = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"5 6 8"}, "", {"5", "6", "7"});
    expectError(parseGeo3dml(modelXml(mapped), "mapped.xml"), ErrorCode::ParseError, "mapped.xml",
                {"vertex index 8", "out of range"});
    const std::string negative = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"0 -1 2"});
    expectError(parseGeo3dml(modelXml(negative), "neg.xml"), ErrorCode::ParseError, "neg.xml", {"negative"});
    const std::string duplicate = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"0 1 2"}, "", {"0", "1", "1"});
    expectError(parseGeo3dml(modelXml(duplicate), "dup.xml"), ErrorCode::ParseError, "dup.xml", {"IndexNo 1"});
}

TEST(Geo3dmlLoader, NanAndInfCoordinates) {
    for (const std::string bad : {"nan", "NaN", "inf", "-Infinity", "1e999"}) {
        SCOPED_TRACE(bad);
        const std::string tin = geoTin({"0 0 0", bad + " 0 0", "0 1 0"}, {"0 1 2"});
        expectError(parseGeo3dml(modelXml(tin), "nan.xml"), ErrorCode::ParseError, "nan.xml",
                    {"NaN or infinite", "Vertex[2]"});
    }
    const std::string word = geoTin({"0 0 0", "one 0 0", "0 1 0"}, {"0 1 2"});
    expectError(parseGeo3dml(modelXml(word), "word.xml"), ErrorCode::ParseError, "word.xml", {"not a number"});
}

TEST(Geo3dmlLoader, CoordinateCountNotMultipleOf3) {
    const std::string tin = geoTin({"0 0 0", "1 0", "0 1 0"}, {"0 1 2"});
    expectError(parseGeo3dml(modelXml(tin), "two.xml"), ErrorCode::ParseError, "two.xml", {"2 coordinates"});
    const std::string four = geoTin({"0 0 0", "1 0 0 7", "0 1 0"}, {"0 1 2"});
    expectError(parseGeo3dml(modelXml(four), "four.xml"), ErrorCode::ParseError, "four.xml", {"4 coordinates"});
    const std::string gml =
        "<gml:TriangulatedSurface><gml:patches><gml:Triangle><gml:exterior><gml:LinearRing>"
        "<gml:posList>0 0 0 1 0 0 0 1 0 0 0</gml:posList></gml:LinearRing></gml:exterior>"
        "</gml:Triangle></gml:patches></gml:TriangulatedSurface>";
    expectError(parseGeo3dml(modelXml(gml), "poslist.xml"), ErrorCode::ParseError, "poslist.xml",
                {"11 numbers", "not a multiple of 3"});
}

TEST(Geo3dmlLoader, TriangleWithTooFewIndices) {
    const std::string tin = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"0 1"});
    expectError(parseGeo3dml(modelXml(tin), "short.xml"), ErrorCode::ParseError, "short.xml", {"2 vertex indices"});
    const std::string none =
        "<GeoTin><Vertices><Vertex>0 0 0</Vertex></Vertices><Triangles><Triangle/></Triangles></GeoTin>";
    expectError(parseGeo3dml(modelXml(none), "nolist.xml"), ErrorCode::ParseError, "nolist.xml", {"VertexList"});
}

TEST(Geo3dmlLoader, HugeDeclaredCountsAreNotTrusted) {
    const std::string gml =
        "<gml:TriangulatedSurface><gml:patches><gml:Triangle><gml:exterior><gml:LinearRing>"
        "<gml:posList count=\"4000000000000\">0 0 0 1 0 0 0 1 0 0 0 0</gml:posList>"
        "</gml:LinearRing></gml:exterior></gml:Triangle></gml:patches></gml:TriangulatedSurface>";
    expectError(parseGeo3dml(modelXml(gml), "count.xml"), ErrorCode::ParseError, "count.xml",
                {"count=4000000000000", "holds 4 positions"});
    const std::string tin =
        "<GeoTin><Vertices><Vertex>0 0 0</Vertex><Vertex>1 0 0</Vertex><Vertex>0 1 0</Vertex>"
        "</Vertices><Triangles><Triangle><VertexList ItemCount=\"999999999999\">0 1 2</VertexList>"
        "</Triangle></Triangles></GeoTin>";
    expectError(parseGeo3dml(modelXml(tin), "itemcount.xml"), ErrorCode::ParseError, "itemcount.xml",
                {"ItemCount=999999999999"});
    // A huge IndexNo is only a key, never a size.
    const std::string big = geoTin({"0 0 0", "1 0 0", "0 1 0"}, {"18446744073 1 2"}, "", {"18446744073", "1", "2"});
    Result<Model> r = parseGeo3dml(modelXml(big), "bigindex.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->surfaces.size(), 1u);
}

TEST(Geo3dmlLoader, InvalidUtf8TextIsAnError) {
    const std::string xml = modelXml(tetraTin(), "", textField("lithology", "\xff\xfe bad"));
    expectError(parseGeo3dml(xml, "latin.xml"), ErrorCode::ParseError, "latin.xml", {"UTF-8"});
}

TEST(Geo3dmlLoader, DeepNestingDoesNotOverflowTheStack) {
    const std::size_t depth = 200000;
    std::string shape;
    shape.reserve(depth * 8);
    for (std::size_t i = 0; i < depth; ++i) shape += "<a>";
    for (std::size_t i = 0; i < depth; ++i) shape += "</a>";
    expectError(parseGeo3dml(modelXml(shape), "deep.xml"), ErrorCode::Unsupported, "deep.xml", {"no TIN triangles"});
}

TEST(Geo3dmlLoader, VolumesThatCannotBeBuiltAreSkippedWithAWarning) {
    // A tetrahedron naming a vertex that is not there, beside a TIN: the TIN loads, the
    // volume is skipped and named in a warning.
    const std::string volume =
        "<GeoTetrahedronVolume><Vertices><Vertex IndexNo=\"0\">0 0 0</Vertex><Vertex IndexNo=\"1\">1 0 0</Vertex>"
        "<Vertex IndexNo=\"2\">0 1 0</Vertex></Vertices><Tetrahedrons><Tetrahedron IndexNo=\"0\">"
        "<VertexList>0 1 2 9</VertexList></Tetrahedron></Tetrahedrons></GeoTetrahedronVolume>";
    std::string xml = modelXml(volume);
    const std::string tinFeature = modelXml(tetraTin(500, 0, 0), "", "", "地层", "T2");
    const auto begin = tinFeature.find("<Feature>"), end = tinFeature.find("</Feature>") + 10;
    xml.insert(xml.find("</Features>"), tinFeature.substr(begin, end - begin));
    Result<Model> r = parseGeo3dml(xml, "broken_volume.xml");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_EQ(r->bodies[0].name, "T2");
    std::size_t warnings = 0;
    for (const auto& issue : r->validation.issues) {
        if (issue.severity != ValidationIssue::Severity::Warning) continue;
        ++warnings;
        EXPECT_EQ(issue.part, "T1");
        EXPECT_NE(issue.message.find("Tetrahedron 0: vertex index 9 is not a Vertex of the volume (it has 3)"),
                  std::string::npos)
            << issue.message;
        EXPECT_NE(issue.message.find("skipped"), std::string::npos) << issue.message;
    }
    EXPECT_EQ(warnings, 1u);
    EXPECT_TRUE(r->notes.count("geo3dml_warnings"));
    // The same volume alone: nothing to load, an error.
    EXPECT_FALSE(parseGeo3dml(modelXml(volume), "broken_volume.xml").ok());
}

}  // namespace
}  // namespace geoslice
