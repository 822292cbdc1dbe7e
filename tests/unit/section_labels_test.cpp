// Unit labels (section/fill/labels.hpp) and lithology patterns (section/fill/patterns.hpp):
// the pattern table, the unit codes, the pole of inaccessibility against closed forms, label
// placement on the synthetic mine at many planes (every placed box inside its polygon --
// checked against the engine's own ID buffer, an independent fill -- and no two boxes
// overlapping), the section SVG parsed back, section images decorated through cairo, and
// print sheets whose PDF text (poppler's pdftotext) holds the unit codes.
#include <gtest/gtest.h>

#include <pugixml.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "print/cairo_output.hpp"
#include "print/pattern_cairo.hpp"
#include "print/section_sheet.hpp"
#include "print/svg_output.hpp"
#include "section/cut/contours.hpp"
#include "section/fill/labels.hpp"
#include "section/fill/patterns.hpp"
#include "section/fill/raster.hpp"
#include "section/fill/vector_export.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/synthetic_model.hpp"

using namespace geoslice;

namespace {

// Output units: a pole found to a precision of 1e-3 on shapes of size ~10: the precision.
constexpr double kPoleTol = 1e-3;

TEST(LithologyPatterns, NamesChineseNamesAndCodesPickTheirPattern) {
    const std::map<std::string, Lithology> table = {
        {"sandstone", Lithology::Sandstone},
        {"Quartz Sandstone", Lithology::Sandstone},
        {"砂岩", Lithology::Sandstone},
        {"SST", Lithology::Sandstone},
        {"limestone", Lithology::Limestone},
        {"灰岩", Lithology::Limestone},
        {"石灰岩", Lithology::Limestone},
        {"LST", Lithology::Limestone},
        {"mudstone", Lithology::Mudstone},
        {"泥岩", Lithology::Mudstone},
        {"shale", Lithology::Shale},
        {"页岩", Lithology::Shale},
        {"siltstone", Lithology::Siltstone},
        {"粉砂岩", Lithology::Siltstone},  // ends with 砂岩: the longer name wins
        {"conglomerate", Lithology::Conglomerate},
        {"砾岩", Lithology::Conglomerate},
        {"granite", Lithology::Granite},
        {"花岗岩", Lithology::Granite},
        {"basalt", Lithology::Basalt},
        {"玄武岩", Lithology::Basalt},
        {"dolomite", Lithology::Dolomite},
        {"白云岩", Lithology::Dolomite},
        {"coal", Lithology::Coal},
        {"煤", Lithology::Coal},
        {"clay", Lithology::Clay},
        {"黏土", Lithology::Clay},
        {"breccia", Lithology::Breccia},
        {"tuff", Lithology::Tuff},
        {"mica schist", Lithology::Schist},
        {"diorite", Lithology::Diorite},
        // the head noun (the name that ends last) wins in both languages
        {"sandy mudstone", Lithology::Mudstone},
        {"砂质泥岩", Lithology::Mudstone},
        {"泥质砂岩", Lithology::Sandstone},
        {"siltstone and feldspathic sandstone", Lithology::Sandstone},
        {"coal-bearing mudstone and shale", Lithology::Shale},
        {"marl and oolitic limestone", Lithology::Limestone},
        {"dolomite with gypsum", Lithology::Dolomite},
        // codes are whole words only
        {"glass", Lithology::None},
        {"", Lithology::None},
        {"orebody", Lithology::None},
    };
    for (const auto& [text, want] : table) EXPECT_EQ(matchLithology(text), want) << "\"" << text << "\"";
    for (Lithology l : allLithologies()) {
        EXPECT_EQ(matchLithology(lithologyName(l)), l) << lithologyName(l);
        const PatternTile& t = patternTile(l);
        EXPECT_GT(t.width, 0.0);
        EXPECT_TRUE(t.solid || !t.polylines.empty() || !t.circles.empty() || !t.dots.empty()) << lithologyName(l);
    }
}

TEST(LithologyPatterns, LithologyColumnsAndUnitCodes) {
    AttributeRecord r;
    r.name = "Xujiahe Formation";
    EXPECT_EQ(recordLithology(&r), Lithology::None);
    r.extra["岩性"] = "石英砂岩";
    EXPECT_EQ(recordLithology(&r), Lithology::Sandstone);
    r.extra = nlohmann::ordered_json::object();
    r.extra["Rock"] = "granite";
    EXPECT_EQ(recordLithology(&r), Lithology::Granite);
    r.lithology = "shale";  // the lithology field comes first
    EXPECT_EQ(recordLithology(&r), Lithology::Shale);
    EXPECT_EQ(recordLithology(nullptr), Lithology::None);

    EXPECT_EQ(unitCode(&r, "part"), "Xujiahe Formation");
    r.age = "Late Triassic (T3x)";
    EXPECT_EQ(unitCode(&r, "part"), "T3x");
    r.extra["Symbol"] = "T₃x";
    EXPECT_EQ(unitCode(&r, "part"), "T₃x");
    r.extra["code"] = "T3x-2";
    EXPECT_EQ(unitCode(&r, "part"), "T3x-2");  // code before symbol
    EXPECT_EQ(unitCode(nullptr, "part"), "part");
}

TEST(UnitLabels, PoleOfInaccessibilityMatchesClosedForms) {
    // A 10 x 4 rectangle: the pole lies on its mid-line, 2 from the long sides.
    double d = 0.0;
    glm::dvec2 p = poleOfInaccessibility({{{0, 0}, {10, 0}, {10, 4}, {0, 4}}}, kPoleTol, &d);
    EXPECT_NEAR(d, 2.0, kPoleTol);
    EXPECT_NEAR(p.y, 2.0, kPoleTol);
    EXPECT_GE(p.x, 2.0 - kPoleTol);
    EXPECT_LE(p.x, 8.0 + kPoleTol);
    // A 10 x 10 square with a 2 x 2 hole in the middle: the pole lies on a diagonal, at
    // (t, t) where the distance t to the outer sides equals the distance sqrt2 (4 - t) to the
    // hole's corner (4, 4): t = 4 sqrt2 / (1 + sqrt2).
    const double t = 4.0 * std::sqrt(2.0) / (1.0 + std::sqrt(2.0));
    p = poleOfInaccessibility({{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{4, 4}, {4, 6}, {6, 6}, {6, 4}}}, kPoleTol, &d);
    EXPECT_NEAR(d, t, kPoleTol);
    // An L shape with arms 2 wide: the pole is inside, at least 1 from the rings.
    p = poleOfInaccessibility({{{0, 0}, {10, 0}, {10, 2}, {2, 2}, {2, 10}, {0, 10}}}, kPoleTol, &d);
    EXPECT_GE(d, 1.0 - kPoleTol);
    EXPECT_TRUE(pointInRing(p, {{0, 0}, {10, 0}, {10, 2}, {2, 2}, {2, 10}, {0, 10}}));
}

TEST(UnitLabels, BoxInsidePolygonAndGreedyPlacement) {
    const std::vector<Ring> square = {{{0, 0}, {10, 0}, {10, 10}, {0, 10}}};
    EXPECT_TRUE(boxInsidePolygon({1, 1, 9, 9}, square));
    EXPECT_FALSE(boxInsidePolygon({-1, 1, 9, 9}, square));
    EXPECT_FALSE(boxInsidePolygon({11, 1, 12, 2}, square));
    const std::vector<Ring> holed = {square[0], {{4, 4}, {4, 6}, {6, 6}, {6, 4}}};
    EXPECT_FALSE(boxInsidePolygon({3, 3, 7, 7}, holed));          // the hole inside the box
    EXPECT_FALSE(boxInsidePolygon({4.5, 4.5, 5.5, 5.5}, holed));  // inside the hole
    EXPECT_TRUE(boxInsidePolygon({0.5, 0.5, 3.5, 3.5}, holed));

    // Two candidates over the same square: the first (larger: same area, stable) is placed,
    // the second would overlap it and is dropped; a tiny polygon gets none.
    std::vector<LabelCandidate> c(3);
    c[0] = {"A", square, 4.0, 2.0, 1, 0};
    c[1] = {"B", square, 4.0, 2.0, 2, 1};
    c[2] = {"C", {{{20, 20}, {21, 20}, {21, 21}, {20, 21}}}, 4.0, 2.0, 3, 2};
    const auto placed = placeLabels(c, {-100, -100, 100, 100});
    ASSERT_EQ(placed.size(), 1u);
    EXPECT_EQ(placed[0].text, "A");
    EXPECT_NEAR(placed[0].at.x, 5.0, 0.05);
    EXPECT_NEAR(placed[0].at.y, 5.0, 0.05);
    // Outside the view: none.
    EXPECT_TRUE(placeLabels({c[0]}, {6, 6, 100, 100}).empty());
}

struct Mine {
    Model model = test::syntheticModel(20000);
    std::unique_ptr<SectionIndex> index;
    Mine() {
        auto idx = buildSectionIndex(model);
        EXPECT_TRUE(idx.ok());
        if (idx.ok()) index = std::move(idx.value());
    }
};

// Every placed label: its box lies inside the view, the engine's ID buffer holds the label's
// record at every pixel centre inside the box, and no two boxes overlap. Planes: vertical
// sections at many northings and azimuths, and horizontal slices.
TEST(UnitLabels, PlacedBoxesLieInsideTheirUnitsAndNeverOverlap) {
    Mine mine;
    ASSERT_TRUE(mine.index);
    const SectionIndex& idx = *mine.index;
    const glm::dvec3 lo = idx.bounds.min, hi = idx.bounds.max;
    std::vector<Plane> planes;
    for (int k = 1; k <= 12; ++k) {
        const double y = lo.y + (hi.y - lo.y) * k / 13.0;
        planes.push_back(Plane{{0.0, 1.0, 0.0}, -y});
        const double a = 0.25 * k;  // azimuths through the centre
        const glm::dvec3 n{std::cos(a), std::sin(a), 0.0};
        planes.push_back(Plane{n, -glm::dot(n, 0.5 * (lo + hi) + glm::dvec3(0.0, 0.0, 0.0))});
    }
    for (int k = 1; k <= 6; ++k) planes.push_back(Plane{{0.0, 0.0, -1.0}, lo.z + (hi.z - lo.z) * k / 7.0});
    std::size_t total = 0, sections = 0;
    for (const Plane& plane : planes) {
        auto s = computeSection(idx, plane);
        if (!s.ok() || s->bodies.empty()) continue;
        ++sections;
        const int w = 900, h = 500;
        const FrameRect rect = fitFrame(s.value(), w, h);
        auto image = rasterizeSection(idx, s.value(), rect, w, h);
        ASSERT_TRUE(image.ok());
        const double sx = w / (rect.u1 - rect.u0), sy = h / (rect.v1 - rect.v0);
        LabelStyle style;
        style.size = 12.0;
        style.textWidth = print::labelTextWidth;
        const LabelBox view{0, 0, double(w), double(h)};
        const auto labels = sectionLabels(
            idx, s->bodies, [&](const glm::dvec2& p) { return glm::dvec2((p.x - rect.u0) * sx, (rect.v1 - p.y) * sy); },
            view, style);
        for (std::size_t i = 0; i < labels.size(); ++i) {
            const PlacedLabel& l = labels[i];
            EXPECT_GE(l.box.x0, 0.0);
            EXPECT_GE(l.box.y0, 0.0);
            EXPECT_LE(l.box.x1, double(w));
            EXPECT_LE(l.box.y1, double(h));
            // the text fits its box: the measured width plus padding
            EXPECT_GE(l.box.x1 - l.box.x0, print::labelTextWidth(l.text, style.size));
            std::size_t pixels = 0;
            for (int j = int(std::ceil(l.box.y0 - 0.5)); j + 0.5 <= l.box.y1; ++j)
                for (int x = int(std::ceil(l.box.x0 - 0.5)); x + 0.5 <= l.box.x1; ++x) {
                    ++pixels;
                    ASSERT_EQ(image->ids[std::size_t(j) * w + std::size_t(x)], l.record)
                        << "label " << l.text << " pixel " << x << "," << j;
                }
            EXPECT_GT(pixels, 20u);
            for (std::size_t k = 0; k < i; ++k) EXPECT_FALSE(l.box.overlaps(labels[k].box)) << l.text;
        }
        total += labels.size();
    }
    EXPECT_GE(sections, 25u);
    EXPECT_GT(total, 5 * sections);  // most sections show most of their seven strata labelled
}

// The section SVG: patterns as <pattern> elements for the lithologies shown, a pattern
// path per body with a known lithology, labels (labels=on) as <text> on non-overlapping boxes.
TEST(UnitLabels, SectionSvgCarriesPatternsAndLabels) {
    Mine mine;
    const SectionIndex& idx = *mine.index;
    const double y = 0.5 * (idx.bounds.min.y + idx.bounds.max.y);
    auto s = computeSection(idx, Plane{{0.0, 1.0, 0.0}, -y});
    ASSERT_TRUE(s.ok());
    const FrameRect rect = fitFrame(s.value(), 1200, 600);
    SvgOverlays overlays;
    overlays.labels = true;
    auto svg = toSvg(idx, vectorSource(s.value()), rect, 1200, 600, {}, overlays);
    ASSERT_TRUE(svg.ok());
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(svg->c_str()));
    const pugi::xml_node root = doc.child("svg");
    std::set<std::string> defined, used;
    for (pugi::xml_node p : root.child("defs").children("pattern")) defined.insert(p.attribute("id").value());
    std::vector<LabelBox> boxes;
    std::set<std::string> texts;
    for (pugi::xml_node n : root.children()) {
        if (std::string(n.attribute("class").value()) == "lith") {
            const std::string fill = n.attribute("fill").value();
            used.insert(fill.substr(5, fill.size() - 6));  // url(#...)
            const RecordId r = RecordId(n.attribute("data-record").as_uint());
            EXPECT_EQ(lithologyName(recordLithology(mine.model.attributes.find(r))),
                      n.attribute("data-lithology").value());
        }
        if (std::string(n.attribute("class").value()) == "unit-label") {
            const pugi::xml_node r = n.child("rect");
            const LabelBox b{r.attribute("x").as_double(), r.attribute("y").as_double(),
                             r.attribute("x").as_double() + r.attribute("width").as_double(),
                             r.attribute("y").as_double() + r.attribute("height").as_double()};
            for (const LabelBox& o : boxes) EXPECT_FALSE(b.overlaps(o));
            boxes.push_back(b);
            texts.insert(n.child("text").text().get());
        }
    }
    EXPECT_EQ(defined, used);
    for (const char* p : {"lith-sandstone", "lith-limestone", "lith-dolomite", "lith-mudstone", "lith-shale"})
        EXPECT_TRUE(defined.count(p)) << p;
    for (const char* code : {"T3x", "J2s", "P2m", "J1z"}) EXPECT_TRUE(texts.count(code)) << code;
    // Default: patterns on, labels off (the plain SVG stays an overlay of the image).
    auto plain = toSvg(idx, vectorSource(s.value()), rect, 1200, 600);
    ASSERT_TRUE(plain.ok());
    EXPECT_EQ(plain->find("<text"), std::string::npos);
    EXPECT_NE(plain->find("<pattern"), std::string::npos);
    SvgOverlays none;
    none.patterns = false;
    auto bare = toSvg(idx, vectorSource(s.value()), rect, 1200, 600, {}, none);
    EXPECT_EQ(bare->find("<pattern"), std::string::npos);
}

// Images: patterns change only pixels of units with a lithology; labels only pixels inside
// their boxes; the text is drawn (the box holds pixels of the ink colour).
TEST(UnitLabels, ImageDecorationsStayInsideTheirUnitsAndBoxes) {
    Mine mine;
    const SectionIndex& idx = *mine.index;
    auto s = computeSection(idx, Plane{{0.0, 1.0, 0.0}, -0.5 * (idx.bounds.min.y + idx.bounds.max.y)});
    ASSERT_TRUE(s.ok());
    const int w = 800, h = 400;
    const FrameRect rect = fitFrame(s.value(), w, h);
    auto image = rasterizeSection(idx, s.value(), rect, w, h);
    ASSERT_TRUE(image.ok());
    std::vector<std::uint8_t> patterned = image->rgba;
    print::decorateSectionImage(idx, s->bodies, rect, w, h, patterned.data(), image->ids.data(), {false, true});
    std::size_t changed = 0;
    for (std::size_t i = 0; i < image->ids.size(); ++i) {
        const bool differs = std::memcmp(&patterned[4 * i], &image->rgba[4 * i], 4) != 0;
        if (!differs) continue;
        ++changed;
        ASSERT_NE(recordLithology(mine.model.attributes.find(image->ids[i])), Lithology::None) << "pixel " << i;
    }
    EXPECT_GT(changed, image->ids.size() / 50);

    std::vector<std::uint8_t> labelled = image->rgba;
    print::decorateSectionImage(idx, s->bodies, rect, w, h, labelled.data(), image->ids.data(), {true, false});
    const double sx = w / (rect.u1 - rect.u0), sy = h / (rect.v1 - rect.v0);
    LabelStyle style;
    style.size = 12.0;
    style.textWidth = print::labelTextWidth;
    const auto labels = sectionLabels(
        idx, s->bodies, [&](const glm::dvec2& p) { return glm::dvec2((p.x - rect.u0) * sx, (rect.v1 - p.y) * sy); },
        {0, 0, double(w), double(h)}, style);
    ASSERT_FALSE(labels.empty());
    std::vector<std::size_t> inked(labels.size(), 0);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::size_t k = std::size_t(j) * w + std::size_t(i);
            if (std::memcmp(&labelled[4 * k], &image->rgba[4 * k], 4) == 0) continue;
            bool inBox = false;
            for (std::size_t n = 0; n < labels.size(); ++n) {
                const LabelBox& b = labels[n].box;
                if (i + 1 > b.x0 && i < b.x1 && j + 1 > b.y0 && j < b.y1) {  // the pixel touches the box
                    inBox = true;
                    ++inked[n];
                }
            }
            ASSERT_TRUE(inBox) << "pixel " << i << "," << j << " changed outside every label box";
        }
    for (std::size_t n = 0; n < labels.size(); ++n) EXPECT_GT(inked[n], 10u) << labels[n].text;
}

std::string runText(const std::string& command) {
    std::string out;
    FILE* p = popen(command.c_str(), "r");
    if (!p) return out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
    return out;
}

// Print sheets: the PDF's text (pdftotext) holds the unit codes as words of their own (the
// legend writes them in brackets); legend swatches carry the patterns; the SVG sheet defines them.
TEST(UnitLabels, PrintSheetShowsCodesAndPatterns) {
    Mine mine;
    const SectionIndex& idx = *mine.index;
    auto s = computeSection(idx, Plane{{0.0, 1.0, 0.0}, -0.5 * (idx.bounds.min.y + idx.bounds.max.y)});
    ASSERT_TRUE(s.ok());
    print::SheetOptions o;
    o.paper = print::paperSize("A3", print::Orientation::Landscape).value();
    print::SheetInfo info;
    info.model = "synthetic";
    info.date = "2026-11-28";
    auto sheet = print::sectionSheet(idx, s.value(), o, info);
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    std::size_t patternedSwatches = 0, patternedBodies = 0;
    for (const print::SheetItem& item : sheet->items)
        if (const auto* p = std::get_if<print::PathItem>(&item); p && p->pattern != Lithology::None)
            (p->clip ? patternedBodies : patternedSwatches)++;
    EXPECT_GE(patternedSwatches, 7u);  // the seven strata and the orebody in the legend
    EXPECT_GE(patternedBodies, s->bodies.size() - 2);

    auto pdf = print::renderPdf(sheet.value());
    ASSERT_TRUE(pdf.ok());
    const std::string path = testing::TempDir() + "geoslice_labels_sheet.pdf";
    std::ofstream(path, std::ios::binary) << pdf.value();
    const std::string text = runText("pdftotext -layout " + path + " -");
    ASSERT_FALSE(text.empty()) << "pdftotext (poppler-utils) missing?";
    for (const char* code : {"T3x", "J2s", "P2m", "J1z", "T1j"}) {
        const std::regex word(std::string("(^|[^(A-Za-z0-9])") + code + "($|[^)A-Za-z0-9])");
        EXPECT_TRUE(std::regex_search(text, word)) << code << " not found as a word of its own";
    }
    auto svg = print::renderSvg(sheet.value());
    ASSERT_TRUE(svg.ok());
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(svg->c_str()));
    EXPECT_TRUE(doc.child("svg").child("defs").find_child_by_attribute("pattern", "id", "lith-sandstone"));

    o.labels = o.patterns = false;
    auto plain = print::sectionSheet(idx, s.value(), o, info);
    ASSERT_TRUE(plain.ok());
    for (const print::SheetItem& item : plain->items)
        if (const auto* p = std::get_if<print::PathItem>(&item)) {
            EXPECT_EQ(p->pattern, Lithology::None);
        }
    EXPECT_LT(plain->items.size(), sheet->items.size());
}

}  // namespace
