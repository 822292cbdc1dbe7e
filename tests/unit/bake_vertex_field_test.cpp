// Spatially varying attributes from a per-vertex property (issue 4, section 5): a GOCAD TSurf
// with a PVRTX "grade" column, baked with grade classes. For random points on the surface the id
// fetched through UV is the record of the class of the grade interpolated barycentrically from
// the triangle's vertices, except near a class boundary (tolerance derived below); parts
// without the property and no-data vertices keep the part's record; bad options are errors.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "bake/bake.hpp"
#include "bake/package.hpp"
#include "model/io/loaders.hpp"
#include "tests/common/run_command.hpp"

using namespace geoslice;
namespace fs = std::filesystem;

namespace {

constexpr double kNoData = -99999.0;

// A 240 m x 240 m height field (n x n cells, two triangles each), z = 12 sin(x/60) cos(y/50),
// with PVRTX grade = 1 + 0.03 x + 0.02 y + 0.5 sin(x/30) (about 1 to 13). Vertex `noDataVertex`
// (or none when < 0) carries the no-data value.
std::string gradeSurface(const std::string& name, int n, int noDataVertex) {
    std::ostringstream s;
    s.precision(17);
    s << "GOCAD TSurf 1\nHEADER {\nname:" << name << "\n}\nPROPERTIES grade\nNO_DATA_VALUES " << kNoData
      << "\nESIZES 1\nTFACE\n";
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            const double px = 240.0 * x / n, py = 240.0 * y / n;
            const int id = y * (n + 1) + x;
            const double g = id == noDataVertex ? kNoData : 1.0 + 0.03 * px + 0.02 * py + 0.5 * std::sin(px / 30.0);
            s << "PVRTX " << id + 1 << " " << px << " " << py << " " << 12.0 * std::sin(px / 60.0) * std::cos(py / 50.0)
              << " " << g << "\n";
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const int a = y * (n + 1) + x + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
            s << "TRGL " << a << " " << b << " " << c << "\nTRGL " << a << " " << c << " " << d << "\n";
        }
    s << "END\n";
    return s.str();
}

// A plain sheet beside it (no properties): VRTX only.
std::string plainSurface() {
    return "GOCAD TSurf 1\nHEADER {\nname:plain\n}\nTFACE\nVRTX 1 300 0 0\nVRTX 2 400 0 0\nVRTX 3 300 100 0\n"
           "VRTX 4 400 100 0\nTRGL 1 2 3\nTRGL 2 4 3\nEND\n";
}

const Part* partNamed(const Model& m, const std::string& name) {
    for (const auto& p : m.surfaces)
        if (p.name == name) return &p;
    for (const auto& p : m.bodies)
        if (p.name == name) return &p;
    return nullptr;
}

// Squared distance from p to the closed triangle t (2D).
double distance2(const glm::dvec2 t[3], const glm::dvec2& p) {
    const double area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
    const double s0 = (t[1].x - p.x) * (t[2].y - p.y) - (t[2].x - p.x) * (t[1].y - p.y);
    const double s1 = (t[2].x - p.x) * (t[0].y - p.y) - (t[0].x - p.x) * (t[2].y - p.y);
    const double s2 = (t[0].x - p.x) * (t[1].y - p.y) - (t[1].x - p.x) * (t[0].y - p.y);
    if (area != 0.0 && s0 * area >= 0 && s1 * area >= 0 && s2 * area >= 0) return 0.0;
    double best = std::numeric_limits<double>::infinity();
    for (int e = 0; e < 3; ++e) {
        const glm::dvec2 a = t[e], d = t[(e + 1) % 3] - a;
        const double len2 = glm::dot(d, d);
        const double u = len2 > 0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
        const glm::dvec2 q = a + u * d;
        best = std::min(best, glm::dot(p - q, p - q));
    }
    return best;
}

}  // namespace

TEST(BakeVertexField, PvrtxGradeFetchesTheClassOfTheInterpolatedValue) {
    const int n = 24;
    const int noDataVertex = 12 * (n + 1) + 12;  // the centre vertex: its 6 triangles have no grade
    auto loaded = parseTsurf(gradeSurface("graded", n, noDataVertex) + plainSurface(), "graded.ts");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    const Model& m = loaded.value();
    const Part* graded = partNamed(m, "graded");
    const Part* plain = partNamed(m, "plain");
    ASSERT_NE(graded, nullptr);
    ASSERT_NE(plain, nullptr);
    ASSERT_EQ(graded->mesh.propertyNames, std::vector<std::string>{"grade"});
    ASSERT_TRUE(plain->mesh.propertyNames.empty());
    ASSERT_TRUE(std::isnan(graded->mesh.propertyValues[std::size_t(noDataVertex)]));

    bake::BakeOptions o;
    o.pack.width = o.pack.height = 512;
    o.field.vertexProperty = "grade";
    o.field.breaks = {4.0, 7.0, 10.0};
    o.field.unit = "g/t Au";
    auto baked = bake::bakeModel(m, o);
    ASSERT_TRUE(baked.ok()) << baked.error().message;
    ASSERT_EQ(baked->pages, 1u);

    // Class records: 4 classes of the graded part's record only, found by (parent, class).
    ASSERT_EQ(baked->fieldRecords.size(), 4u);
    std::map<int, RecordId> classId;
    for (const auto& r : baked->fieldRecords) {
        EXPECT_EQ(r.extra["parent"].get<RecordId>(), graded->record);
        EXPECT_EQ(r.extra["field"].get<std::string>(), "grade");
        EXPECT_EQ(r.gradeUnit, "g/t Au");
        classId[r.extra["class"].get<int>()] = r.id;
        EXPECT_EQ(m.attributes.find(r.id), nullptr) << "class record ids are new ids";
    }
    ASSERT_EQ(classId.size(), 4u);
    EXPECT_NE(baked->fieldRecords[1].name.find("grade 4 - 7"), std::string::npos) << baked->fieldRecords[1].name;

    const bake::BakedPart* gp = nullptr;
    const bake::BakedPart* pp = nullptr;
    for (const auto& p : baked->parts) (p.name == "graded" ? gp : pp) = &p;
    ASSERT_NE(gp, nullptr);
    ASSERT_NE(pp, nullptr);
    const Mesh& mesh = graded->mesh;
    const double W = baked->width, H = baked->height;
    auto texelUv = [&](const bake::BakedPart& p, std::uint32_t corner) {
        const glm::vec2 uv = p.uvs[p.indices[corner]];
        return glm::dvec2(double(uv.x) * W, double(uv.y) * H);
    };
    auto vertexGrade = [&](std::size_t t, int e) {
        return double(mesh.propertyValues[mesh.indices[3 * t + std::size_t(e)]]);
    };

    // Tolerance. The fetched texel's centre lies within sqrt(2)/2 texel of the sample (in UV);
    // the point the bake maps it to (its nearest point on the chart) lies no farther from the
    // centre than the sample, so within sqrt(2) texels of the sample. The grade is linear in
    // UV on each triangle, so it differs from the sample's by at most L x sqrt(2), L the largest
    // grade gradient per texel over the triangles; samples whose grade is within 2 L of a break
    // (2 rather than sqrt(2): float32 UVs, and the path around a concave chart corner) are
    // skipped. Likewise samples within 2 texels of a no-data triangle.
    const std::size_t triangles = mesh.triangleCount();
    std::vector<bool> noData(triangles);
    double L = 0.0;
    for (std::size_t t = 0; t < triangles; ++t) {
        glm::dvec2 q[3];
        double g[3];
        for (int e = 0; e < 3; ++e) {
            q[e] = texelUv(*gp, std::uint32_t(3 * t + std::size_t(e)));
            g[e] = vertexGrade(t, e);
            noData[t] = noData[t] || std::isnan(g[e]);
        }
        if (noData[t]) continue;
        const glm::dvec2 a = q[1] - q[0], b = q[2] - q[0];
        const double det = a.x * b.y - a.y * b.x;
        ASSERT_NE(det, 0.0);
        const glm::dvec2 grad((g[1] - g[0]) * b.y - (g[2] - g[0]) * a.y, (g[2] - g[0]) * a.x - (g[1] - g[0]) * b.x);
        L = std::max(L, glm::length(grad / det));
    }
    EXPECT_EQ(std::count(noData.begin(), noData.end(), true), 6);
    ASSERT_GT(L, 0.0);
    const double guardValue = 2.0 * L, guardTexels = 2.0;

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t checked = 0, checkedNoData = 0, wrong = 0;
    std::map<RecordId, std::size_t> seen;
    const int samples = 40000;
    for (int i = 0; i < samples; ++i) {
        const std::size_t t = std::size_t(rng() % triangles);
        double r1 = unit(rng), r2 = unit(rng);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const double b[3] = {1.0 - r1 - r2, r1, r2};
        glm::dvec2 uv(0.0);
        for (int e = 0; e < 3; ++e) uv += b[e] * texelUv(*gp, std::uint32_t(3 * t + std::size_t(e)));
        // Distance (texels) to the no-data triangles.
        double nearNoData = std::numeric_limits<double>::infinity();
        for (std::size_t u = 0; u < triangles; ++u)
            if (noData[u]) {
                glm::dvec2 q[3];
                for (int e = 0; e < 3; ++e) q[e] = texelUv(*gp, std::uint32_t(3 * u + std::size_t(e)));
                nearNoData = std::min(nearNoData, std::sqrt(distance2(q, uv)));
            }
        RecordId expect;
        if (noData[t]) {
            // Inside a no-data triangle: the part's record, unless near its border.
            bool deep = true;
            glm::dvec2 q[3];
            for (int e = 0; e < 3; ++e) q[e] = texelUv(*gp, std::uint32_t(3 * t + std::size_t(e)));
            for (int e = 0; e < 3 && deep; ++e) {
                // Distance to the edge e, e+1 in texels.
                const glm::dvec2 a = q[e], d = q[(e + 1) % 3] - a;
                const double dist = std::abs(d.x * (uv.y - a.y) - d.y * (uv.x - a.x)) / glm::length(d);
                // Edges shared by two no-data triangles are interior to the no-data region.
                const std::uint32_t va = mesh.indices[3 * t + std::size_t(e)],
                                    vb = mesh.indices[3 * t + std::size_t((e + 1) % 3)];
                const bool interior = int(va) == noDataVertex || int(vb) == noDataVertex;
                if (!interior && dist < guardTexels) deep = false;
            }
            if (!deep) continue;
            expect = graded->record;
            ++checkedNoData;
        } else {
            if (nearNoData < guardTexels) continue;
            double g = 0.0;
            for (int e = 0; e < 3; ++e) g += b[e] * vertexGrade(t, e);
            bool nearBreak = false;
            for (double br : o.field.breaks) nearBreak = nearBreak || std::abs(g - br) < guardValue;
            if (nearBreak) continue;
            const int k = g < 4.0 ? 0 : g < 7.0 ? 1 : g < 10.0 ? 2 : 3;
            expect = classId[k];
        }
        ++checked;
        const RecordId got = bake::fetchId(baked->texels.data(), baked->width, baked->height, baked->pages,
                                           glm::dvec2(uv.x / W, uv.y / H));
        ++seen[got];
        if (got != expect && ++wrong < 5)
            ADD_FAILURE() << "triangle " << t << " uv " << uv.x << "," << uv.y << ": " << got << " not " << expect;
    }
    std::printf("vertex field: %zu of %d samples checked (%zu in no-data triangles), L = %.4g grade/texel\n", checked,
                samples, checkedNoData, L);
    EXPECT_EQ(wrong, 0u);
    EXPECT_GT(checked, std::size_t(samples) * 8 / 10);
    EXPECT_GT(checkedNoData, 0u);
    for (const auto& [k, id] : classId) EXPECT_GT(seen[id], 100u) << "class " << k;

    // The plain part (no property) keeps its record everywhere.
    for (int i = 0; i < 2000; ++i) {
        const std::size_t t = std::size_t(rng() % (pp->indices.size() / 3));
        double r1 = unit(rng), r2 = unit(rng);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const glm::vec2 uv = float(1 - r1 - r2) * pp->uvs[pp->indices[3 * t]] +
                             float(r1) * pp->uvs[pp->indices[3 * t + 1]] + float(r2) * pp->uvs[pp->indices[3 * t + 2]];
        ASSERT_EQ(bake::fetchId(baked->texels.data(), baked->width, baked->height, baked->pages, glm::dvec2(uv)),
                  plain->record);
    }

    // The class records reach the package's attribute table.
    const fs::path dir = fs::temp_directory_path() / ("geoslice_bake_vfield_" + std::to_string(::getpid()));
    ASSERT_TRUE(bake::writePackage(m, baked.value(), dir.string()).ok());
    auto pkg = bake::loadPackage(dir.string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    ASSERT_NE(pkg->attributes.find(classId[2]), nullptr);
    EXPECT_EQ(pkg->attributes.find(classId[2])->extra["min"], 7.0);
    EXPECT_EQ(pkg->attributes.find(classId[2])->extra["max"], 10.0);
    fs::remove_all(dir);
}

TEST(BakeVertexField, ErrorsNameTheProblem) {
    auto loaded = parseTsurf(gradeSurface("graded", 4, -1) + plainSurface(), "graded.ts");
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    Model m = std::move(loaded).value();
    bake::BakeOptions o;
    o.pack.width = o.pack.height = 64;
    o.field.breaks = {5.0};

    // Unknown property: the message lists the known ones.
    o.field.vertexProperty = "Au_ppm";
    auto r = bake::bakeModel(m, o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument);
    EXPECT_NE(r.error().message.find("\"Au_ppm\""), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("known: \"grade\""), std::string::npos) << r.error().message;

    // Breaks not increasing, or not finite.
    o.field.vertexProperty = "grade";
    o.field.breaks = {5.0, 5.0};
    r = bake::bakeModel(m, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("increasing"), std::string::npos) << r.error().message;
    o.field.breaks = {std::nan("")};
    EXPECT_FALSE(bake::bakeModel(m, o).ok());

    // Both sources.
    bake::BlockModel blocks;
    blocks.name = "g";
    blocks.centres = {{0, 0, 0}};
    blocks.sizes = {{1, 1, 1}};
    blocks.values = {1.0};
    o.field.breaks = {5.0};
    o.field.blocks = &blocks;
    r = bake::bakeModel(m, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("not both"), std::string::npos) << r.error().message;
    o.field.blocks = nullptr;

    // Values inconsistent with the names: an error, not a read past the end.
    Model broken = m;
    for (auto& p : broken.surfaces)
        if (!p.mesh.propertyValues.empty()) p.mesh.propertyValues.pop_back();
    r = bake::bakeModel(broken, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("per-vertex property values"), std::string::npos) << r.error().message;

    // A model without properties says so.
    Model bare = m;
    for (auto& p : bare.surfaces) p.mesh.propertyNames.clear(), p.mesh.propertyValues.clear();
    r = bake::bakeModel(bare, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("no per-vertex properties"), std::string::npos) << r.error().message;

    // A field bake cannot be re-baked part by part.
    auto ok = bake::bakeModel(m, o);
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    EXPECT_EQ(bake::rebakePart(m, 0, ok.value(), o).error().code, ErrorCode::Unsupported);
}

TEST(BakeVertexField, CliBakesAVertexField) {
    const fs::path dir = fs::temp_directory_path() / ("geoslice_bake_vfield_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string model = (dir / "graded.ts").string();
    {
        std::ofstream f(model);
        f << gradeSurface("graded", 8, -1) << plainSurface();
    }
    auto r =
        test::runGeoslice("bake " + model + " --vertex-field grade --breaks 4,7,10 --field-unit g/t --size 256 --out " +
                          (dir / "pkg").string());
    ASSERT_EQ(r.exitCode, 0) << r.out;
    auto pkg = bake::loadPackage((dir / "pkg").string());
    ASSERT_TRUE(pkg.ok()) << pkg.error().message;
    std::size_t classes = 0;
    for (const auto& [id, rec] : pkg->attributes.records())
        if (rec.extra.contains("field") && rec.extra["field"] == "grade") ++classes;
    EXPECT_EQ(classes, 4u);
    // Unknown name, and both sources: exit 1 with the reason on stderr.
    const std::string errFile = (dir / "err.txt").string();
    auto bad = test::runCommand(std::string(GEOSLICE_BINARY) + " bake " + model + " --vertex-field Au --out " +
                                (dir / "pkg2").string() + " 2>" + errFile);
    EXPECT_EQ(bad.exitCode, 1);
    {
        std::ifstream err(errFile);
        const std::string msg((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
        EXPECT_NE(msg.find("known: \"grade\""), std::string::npos) << msg;
    }
    {
        std::ofstream csv(dir / "blocks.csv");
        csv << "x,y,z,dx,dy,dz,g\n0,0,0,10,10,10,1\n";
    }
    bad = test::runCommand(std::string(GEOSLICE_BINARY) + " bake " + model + " --vertex-field grade --field " +
                           (dir / "blocks.csv").string() + " --out " + (dir / "pkg3").string() + " 2>" + errFile);
    EXPECT_EQ(bad.exitCode, 1);
    {
        std::ifstream err(errFile);
        const std::string msg((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
        EXPECT_NE(msg.find("exclude each other"), std::string::npos) << msg;
    }
    fs::remove_all(dir);
}
