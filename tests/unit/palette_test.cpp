// The default palette (model/style/palette.hpp): distinct in normal vision and under
// protanopia and deuteranopia (CIEDE2000 computed here, independently of
// scripts/make_palette.py; Machado, Oliveira & Fernandes 2009 matrices, severity 1.0, in
// linear RGB), stable by unit name, and never used where a file or sidecar gives a colour.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "model/io/loaders.hpp"
#include "model/style/palette.hpp"

using namespace geoslice;

namespace {

using Lab = std::array<double, 3>;
using Mat = std::array<std::array<double, 3>, 3>;

constexpr Mat kIdentity = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
constexpr Mat kProtan = {
    {{0.152286, 1.052583, -0.204868}, {0.114503, 0.786281, 0.099216}, {-0.003882, -0.048116, 1.051998}}};
constexpr Mat kDeutan = {
    {{0.367322, 0.860646, -0.227968}, {0.280085, 0.672501, 0.047413}, {-0.011820, 0.042940, 0.968881}}};

double linear(std::uint8_t c) {
    const double v = c / 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

Lab labOf(Rgba8 c, const Mat& m) {
    const double in[3] = {linear(c.r), linear(c.g), linear(c.b)};
    double rgb[3];
    for (int i = 0; i < 3; ++i) rgb[i] = std::clamp(m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2], 0.0, 1.0);
    const double x = 0.4124564 * rgb[0] + 0.3575761 * rgb[1] + 0.1804375 * rgb[2];
    const double y = 0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2];
    const double z = 0.0193339 * rgb[0] + 0.1191920 * rgb[1] + 0.9503041 * rgb[2];
    auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
    const double fx = f(x / 0.95047), fy = f(y), fz = f(z / 1.08883);
    return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

// CIEDE2000 (Sharma, Wu & Dalal 2005).
double deltaE2000(const Lab& p, const Lab& q) {
    const double kPi = 3.14159265358979323846;
    auto deg = [&](double r) { return r * 180.0 / kPi; };
    auto rad = [&](double d) { return d * kPi / 180.0; };
    const double c1 = std::hypot(p[1], p[2]), c2 = std::hypot(q[1], q[2]), cm = (c1 + c2) / 2.0;
    const double g = 0.5 * (1.0 - std::sqrt(std::pow(cm, 7) / (std::pow(cm, 7) + std::pow(25.0, 7))));
    const double a1 = (1 + g) * p[1], a2 = (1 + g) * q[1];
    const double c1p = std::hypot(a1, p[2]), c2p = std::hypot(a2, q[2]);
    auto hue = [&](double b, double a) {
        double h = deg(std::atan2(b, a));
        return h < 0 ? h + 360.0 : h;
    };
    const double h1 = c1p == 0 ? 0 : hue(p[2], a1), h2 = c2p == 0 ? 0 : hue(q[2], a2);
    double dh = 0;
    if (c1p * c2p != 0) {
        dh = h2 - h1;
        if (dh > 180) dh -= 360;
        if (dh < -180) dh += 360;
    }
    const double dL = q[0] - p[0], dC = c2p - c1p, dH = 2 * std::sqrt(c1p * c2p) * std::sin(rad(dh / 2));
    const double lm = (p[0] + q[0]) / 2, cpm = (c1p + c2p) / 2;
    double hm = h1 + h2;
    if (c1p * c2p != 0)
        hm = std::fabs(h1 - h2) <= 180 ? (h1 + h2) / 2 : (h1 + h2 < 360 ? (h1 + h2 + 360) / 2 : (h1 + h2 - 360) / 2);
    const double t = 1 - 0.17 * std::cos(rad(hm - 30)) + 0.24 * std::cos(rad(2 * hm)) +
                     0.32 * std::cos(rad(3 * hm + 6)) - 0.20 * std::cos(rad(4 * hm - 63));
    const double dTheta = 30 * std::exp(-std::pow((hm - 275) / 25, 2));
    const double rc = 2 * std::sqrt(std::pow(cpm, 7) / (std::pow(cpm, 7) + std::pow(25.0, 7)));
    const double sl = 1 + 0.015 * std::pow(lm - 50, 2) / std::sqrt(20 + std::pow(lm - 50, 2));
    const double sc = 1 + 0.045 * cpm, sh = 1 + 0.015 * cpm * t;
    const double rt = -std::sin(rad(2 * dTheta)) * rc;
    return std::sqrt(std::pow(dL / sl, 2) + std::pow(dC / sc, 2) + std::pow(dH / sh, 2) + rt * (dC / sc) * (dH / sh));
}

// The smallest CIEDE2000 between two of `colours` in normal, protan and deutan vision.
std::array<double, 3> minDelta(const std::vector<Rgba8>& colours) {
    std::array<double, 3> worst = {1e9, 1e9, 1e9};
    const Mat* views[3] = {&kIdentity, &kProtan, &kDeutan};
    for (int v = 0; v < 3; ++v)
        for (std::size_t i = 0; i < colours.size(); ++i)
            for (std::size_t j = 0; j < i; ++j)
                worst[v] = std::min(worst[v], deltaE2000(labOf(colours[i], *views[v]), labOf(colours[j], *views[v])));
    return worst;
}

Model modelOf(const std::vector<std::string>& bodies, const std::vector<std::string>& surfaces = {}) {
    Model m;
    for (const std::string& n : bodies) {
        Part p;
        p.name = n;
        AttributeRecord r;
        r.name = n;
        p.record = m.attributes.add(r);
        m.bodies.push_back(p);
    }
    for (const std::string& n : surfaces) {
        Part p;
        p.name = n;
        p.kind = PartKind::Surface;
        AttributeRecord r;
        r.name = n;
        p.record = m.attributes.add(r);
        m.surfaces.push_back(p);
    }
    applyDefaultColours(m);
    return m;
}

Rgba8 colourOf(const Model& m, const std::string& name) { return m.attributes.findByName(name)->colour; }

}  // namespace

TEST(Palette, KnownCiede2000Pair) {
    // Sharma et al. 2005, table 1, pair 1: 2.0425.
    EXPECT_NEAR(deltaE2000({50.0, 2.6772, -79.7751}, {50.0, 0.0, -82.7485}), 2.0425, 1e-4);
    // Pair 17: 27.1492.
    EXPECT_NEAR(deltaE2000({50.0, 2.5, 0.0}, {73.0, 25.0, -18.0}), 27.1492, 1e-4);
}

TEST(Palette, FillsDistinctInNormalAndColourBlindVision) {
    std::vector<Rgba8> fills(fillPalette(), fillPalette() + kFillPaletteSize);
    const auto worst = minDelta(fills);
    std::printf("palette: %zu fills, min CIEDE2000 normal %.2f, protanopia %.2f, deuteranopia %.2f\n", fills.size(),
                worst[0], worst[1], worst[2]);
    EXPECT_GE(worst[0], 9.0);
    EXPECT_GE(worst[1], 8.0);
    EXPECT_GE(worst[2], 8.0);
    // Lines stand out from every fill in every view.
    double lineWorst = 1e9;
    for (const Rgba8 line : {kFaultLineColour, kSurfaceLineColour})
        for (const Rgba8 f : fills)
            for (const Mat* v : {&kIdentity, &kProtan, &kDeutan})
                lineWorst = std::min(lineWorst, deltaE2000(labOf(line, *v), labOf(f, *v)));
    std::printf("palette: min CIEDE2000 between a line colour and a fill, all views: %.2f\n", lineWorst);
    EXPECT_GE(lineWorst, 20.0);
}

TEST(Palette, UnitsOfOneModelDifferUpToThePaletteSize) {
    // 16 units named as a stratigraphic column might be, in a scrambled order.
    const std::vector<std::string> names = {
        "Quaternary cover", "Upper sandstone", "Lower sandstone", "Shale A",    "Shale B", "Limestone",    "Dolomite",
        "Granite",          "Diorite dyke",    "Ore zone 1",      "Ore zone 2", "Basalt",  "Conglomerate", "Marl",
        "Siltstone",        "Basement"};
    for (std::size_t n : {2u, 5u, 8u, 12u, 16u}) {
        const Model m = modelOf(std::vector<std::string>(names.begin(), names.begin() + std::ptrdiff_t(n)));
        std::vector<Rgba8> used;
        for (const auto& [id, r] : m.attributes.records()) {
            used.push_back(r.colour);
            EXPECT_EQ(r.colourSource, "palette");
        }
        const auto worst = minDelta(used);
        std::printf("palette: %zu units of one model: min CIEDE2000 normal %.2f, protan %.2f, deutan %.2f\n", n,
                    worst[0], worst[1], worst[2]);
        EXPECT_GE(std::min({worst[0], worst[1], worst[2]}), 8.0) << n << " units";
    }
    // More units than entries: still deterministic, and the 17th differs from all others.
    std::vector<std::string> many = names;
    many.push_back("Extra unit");
    const Model m = modelOf(many);
    std::set<std::array<int, 3>> distinct;
    for (const auto& [id, r] : m.attributes.records()) distinct.insert({r.colour.r, r.colour.g, r.colour.b});
    EXPECT_EQ(distinct.size(), many.size());
}

TEST(Palette, StableByNameAcrossModelsAndOrders) {
    const Model a = modelOf({"Granite", "Upper Sandstone", "Shale"});
    const Model b = modelOf({"shale", "upper_sandstone", "granite"});  // other order, other spelling
    EXPECT_EQ(colourOf(a, "Granite"), colourOf(b, "granite"));
    EXPECT_EQ(colourOf(a, "Upper Sandstone"), colourOf(b, "upper_sandstone"));
    EXPECT_EQ(colourOf(a, "Shale"), colourOf(b, "shale"));
    // A unit alone takes the entry its name hashes to, in any model.
    for (const char* n : {"Granite", "Xujiahe Formation",
                          "\xe5\x9c\xb0\xe5\xb1\x82"
                          "C"}) {
        const Model one = modelOf({n});
        EXPECT_EQ(colourOf(one, n), fillColourOf(unitNameHash(n) % kFillPaletteSize)) << n;
    }
    EXPECT_EQ(normaliseUnitName("  Upper_Sandstone (T3) "), "upper sandstone t3");
    // Idempotent: running it again changes nothing.
    Model c = modelOf({"Granite", "Shale"});
    const Rgba8 before = colourOf(c, "Shale");
    applyDefaultColours(c);
    EXPECT_EQ(colourOf(c, "Shale"), before);
}

TEST(Palette, FaultsAndSurfacesGetDarkLines) {
    const Model m = modelOf({"Granite"}, {"F1_model3_fault", "H1b_horizon"});
    EXPECT_EQ(colourOf(m, "F1_model3_fault"), kFaultLineColour);
    EXPECT_EQ(colourOf(m, "H1b_horizon"), kSurfaceLineColour);
}

TEST(Palette, FileColoursAndSidecarsWin) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "geoslice_palette_test";
    std::filesystem::create_directories(dir);
    // Two GOCAD TSurfs: one with *solid*color (0..1 floats), one with none.
    const std::string ts =
        "GOCAD TSurf 1\nHEADER {\nname:Coloured\n*solid*color:0.2 0.4 0.6 1\n}\nVRTX 1 0 0 0\nVRTX 2 1 0 0\n"
        "VRTX 3 0 1 0\nTRGL 1 2 3\nEND\n"
        "GOCAD TSurf 1\nHEADER {\nname:Plain fault\n}\nGEOLOGICAL_TYPE fault\nVRTX 1 0 0 1\nVRTX 2 1 0 1\n"
        "VRTX 3 0 1 1\nTRGL 1 2 3\nEND\n";
    { std::ofstream(dir / "two.ts") << ts; }
    auto m = loadModel((dir / "two.ts").string());
    ASSERT_TRUE(m.ok()) << m.error().message;
    const AttributeRecord* c = m->attributes.findByName("Coloured");
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->colour, (Rgba8{51, 102, 153, 255}));
    EXPECT_EQ(c->colourSource, "file (GOCAD *solid*color)");
    EXPECT_EQ(c->nameSource, "file (GOCAD name:)");
    const AttributeRecord* f = m->attributes.findByName("Plain fault");
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->colour, kFaultLineColour);
    EXPECT_EQ(f->colourSource, "palette");
    // A sidecar colour wins over the file's; a sidecar row without one keeps the file's.
    { std::ofstream(dir / "two.attributes.csv") << "id,name,colour\n7,Coloured,\n8,Plain fault,#ff0000\n"; }
    m = loadModel((dir / "two.ts").string());
    ASSERT_TRUE(m.ok()) << m.error().message;
    auto partRecord = [&](const std::string& name) -> const AttributeRecord* {
        for (const auto* list : {&m->bodies, &m->surfaces})
            for (const Part& p : *list)
                if (p.name == name) return m->attributes.find(p.record);
        return nullptr;
    };
    c = partRecord("Coloured");
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->colour, (Rgba8{51, 102, 153, 255}));
    EXPECT_EQ(c->colourSource, "file (GOCAD *solid*color)");
    EXPECT_EQ(c->nameSource, "sidecar");
    f = partRecord("Plain fault");
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->colour, (Rgba8{255, 0, 0, 255}));
    EXPECT_EQ(f->colourSource, "sidecar");
    // colour_source survives the attribute table's JSON (baked packages keep it).
    auto back = AttributeTable::fromJson(m->attributes.toJson(), "roundtrip");
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(back->find(7)->colourSource, "file (GOCAD *solid*color)");
    std::filesystem::remove_all(dir);
}
