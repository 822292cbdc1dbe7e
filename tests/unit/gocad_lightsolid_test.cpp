// GOCAD LightTSolid as RINGMesh and OpenGeode write it: SHAREDVRTX vertices, regions named by
// "# CTETRA" comment lines or seeded by MODEL_REGION lines, no TVOLUME. The files in
// tests/data/ringmesh are RINGMesh's real geomodel3d.so rewritten in that layout by
// make_lightsolid.py (Python, following OpenGeode's lso_output.cpp); each must give the
// regions of the original (its TVOLUMEs): same names, same tetrahedra volumes, and bodies
// whose enclosed volume is their tetrahedra's to 1e-9 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "model/io/loaders.hpp"

using namespace geoslice;

namespace {

const std::string kDir = std::string(GEOSLICE_TEST_DATA_DIR) + "/ringmesh/";

// Region name -> tetrahedra volume (record extra) and enclosed volume of the body.
std::map<std::string, std::pair<double, double>> regionVolumes(const Model& m) {
    std::map<std::string, std::pair<double, double>> out;
    for (const Part& p : m.bodies) {
        const AttributeRecord* r = m.attributes.find(p.record);
        EXPECT_NE(r, nullptr);
        if (!r) continue;
        out[p.name] = {r->extra.value("tetrahedra_volume_m3", 0.0), p.report.signedVolume};
    }
    return out;
}

}  // namespace

TEST(GocadLightTsolid, SharedVerticesAndRegionCommentsOrSeedsGiveTheOriginalRegions) {
    auto original = loadModel(kDir + "geomodel3d.so");
    ASSERT_TRUE(original.ok()) << original.error().message;
    const auto expected = regionVolumes(original.value());
    ASSERT_EQ(expected.size(), 4u);
    for (const char* file : {"lightsolid_ctetra.so", "lightsolid_model_region.so"}) {
        SCOPED_TRACE(file);
        auto m = loadModel(kDir + file);
        ASSERT_TRUE(m.ok()) << m.error().message;
        EXPECT_FALSE(m->validation.hasErrors());
        const auto got = regionVolumes(m.value());
        ASSERT_EQ(got.size(), expected.size());
        double total = 0.0;
        for (const auto& [name, v] : expected) {
            auto it = got.find(name);
            ASSERT_NE(it, got.end()) << name;
            EXPECT_NEAR(it->second.first, v.first, 1e-9 * v.first) << name << ": tetrahedra volume";
            EXPECT_NEAR(it->second.second, it->second.first, 1e-9 * it->second.first) << name << ": shell vs cells";
            total += it->second.first;
        }
        EXPECT_GT(total, 0.0);
        EXPECT_EQ(m->surfaces.size(), original->surfaces.size());
    }
}

TEST(GocadLightTsolid, ErrorsNameTheLine) {
    const std::string head =
        "GOCAD LightTSolid 1\nHEADER {\nname:t\n}\nVRTX 1 0 0 0\nVRTX 2 1 0 0\nVRTX 3 0 1 0\nVRTX 4 0 0 1\n";
    // A SHAREDVRTX of a vertex not defined before it.
    auto r = parseGocad(head + "SHAREDVRTX 5 9\nTETRA 1 2 3 5\nEND\n", "bad_shared.so");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("bad_shared.so: line 9"), std::string::npos) << r.error().message;
    // A MODEL_REGION seeded on a TFACE that has no triangle.
    r = parseGocad(head + "TETRA 1 2 3 4\nMODEL\nSURFACE s\nTFACE 1\nTRGL 1 2 3\nMODEL_REGION a +7\nEND\n",
                   "bad_seed.so");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("MODEL_REGION a refers to TFACE 7"), std::string::npos) << r.error().message;
    // One tetrahedron; TRGL 1 2 4 has normal (2-1)x(4-1) = (0,-1,0), and vertex 3 = (0,1,0)
    // lies on its - side: MODEL_REGION a -1 seeds it, a +1 seeds nothing.
    r = parseGocad(head + "TETRA 1 2 3 4\nMODEL\nSURFACE s\nTFACE 1\nTRGL 1 2 4\nMODEL_REGION a -1\nEND\n",
                   "one_tet.so");
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->bodies.size(), 1u);
    EXPECT_EQ(r->bodies[0].name, "a");
    EXPECT_NEAR(r->bodies[0].report.signedVolume, 1.0 / 6.0, 1e-12);
    r = parseGocad(head + "TETRA 1 2 3 4\nMODEL\nSURFACE s\nTFACE 1\nTRGL 1 2 4\nMODEL_REGION a +1\nEND\n",
                   "wrong_side.so");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("no tetrahedron lies on the + side"), std::string::npos) << r.error().message;
}
