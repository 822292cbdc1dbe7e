// print/: paper, round scales, ticks and their page positions, the fitted map frame, end
// names, text wrapping, and whole sheets as SVG (XML with text as <text>), as PDF
// (opened by poppler's pdftoppm and compared with a golden rendering; text extracted by
// pdftotext) and as a raster.
#include <gtest/gtest.h>

#include <pugixml.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "image/image_encode.hpp"
#include "model/blocks/block_model.hpp"
#include "model/io/loaders.hpp"
#include "model/mesh/validate.hpp"
#include "print/axes.hpp"
#include "print/cairo_output.hpp"
#include "print/grid_convergence.hpp"
#include "print/map_frame.hpp"
#include "print/map_scale.hpp"
#include "print/paper.hpp"
#include "print/round_numbers.hpp"
#include "print/section_ends.hpp"
#include "print/section_sheet.hpp"
#include "print/sheet_date.hpp"
#include "print/svg_output.hpp"
#include "print/text_metrics.hpp"
#include "section/blocks/block_section.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/index/section_index.hpp"
#include "tests/common/golden.hpp"
#include "tests/common/synthetic_model.hpp"
#include "view/exaggeration.hpp"

namespace geoslice::print {
namespace {

// Millimetres on the page: positions of a few hundred mm from round scales: rounding only.
constexpr double kPageMmTol = 1e-9;
// Degrees: the first-order convergence (lon - lon0) sin(lat) (Snyder 1987, eq. 8-4) against
// the sheet's: the formula's neglected terms and the sheet's 0.001-degree step.
constexpr double kConvergenceDeg = 1e-3;
// Pixels: a pixel-aligned box's corners and width in pixels at 100 dpi: rounding only.
constexpr double kPixelAlignTolPx = 1e-6;

TEST(PrintPaper, SizesOrientationsAndErrors) {
    auto a4 = paperSize("a4", Orientation::Landscape);
    ASSERT_TRUE(a4.ok());
    EXPECT_EQ(a4->widthMm, 297.0);
    EXPECT_EQ(a4->heightMm, 210.0);
    auto a3 = paperSize("A3", Orientation::Portrait);
    ASSERT_TRUE(a3.ok());
    EXPECT_EQ(a3->widthMm, 297.0);
    EXPECT_EQ(a3->heightMm, 420.0);
    auto bad = paperSize("B7", Orientation::Landscape);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("'B7' is not a paper size"), std::string::npos);
    EXPECT_FALSE(parseOrientation("sideways").ok());
    EXPECT_TRUE(parseOrientation("Portrait").ok());
}

TEST(PrintScale, RoundScalesAndTheirText) {
    EXPECT_EQ(roundScaleAtLeast(4300.0), 5000.0);
    EXPECT_EQ(roundScaleAtLeast(5000.0), 5000.0);
    EXPECT_EQ(roundScaleAtLeast(5000.0000001), 5000.0);  // within the relative 1e-9
    EXPECT_EQ(roundScaleAtLeast(22641.0), 25000.0);
    EXPECT_EQ(roundScaleAtLeast(25714.0), 30000.0);
    EXPECT_EQ(roundScaleAtLeast(0.2), 1.0);
    EXPECT_EQ(formatScale(5000.0), "1:5,000");
    EXPECT_EQ(formatScale(2500.0), "1:2,500");
    EXPECT_EQ(formatScale(500.0), "1:500");
    EXPECT_EQ(formatScale(1250000.0), "1:1,250,000");
    EXPECT_FALSE(checkScale(0.0).ok());
    EXPECT_FALSE(checkScale(NAN).ok());
    EXPECT_FALSE(checkScale(2e8).ok());
    EXPECT_TRUE(checkScale(5000.0).ok());
}

TEST(PrintRoundNumbers, GroupingStepsAndDecimals) {
    EXPECT_EQ(formatGrouped(35502000.0, 0), "35,502,000");
    EXPECT_EQ(formatGrouped(1200.0, 0), "1200");
    EXPECT_EQ(formatGrouped(-0.0, 0), "0");
    EXPECT_EQ(formatGrouped(-12.5, 1), "-12.5");
    EXPECT_EQ(formatGrouped(-3388000.0, 0), "-3,388,000");
    EXPECT_EQ(niceAtMost125(130.0), 100.0);
    EXPECT_EQ(niceAtMost125(4999.0), 2000.0);
    EXPECT_EQ(decimalsFor(50.0), 0);
    EXPECT_EQ(decimalsFor(0.5), 1);
    EXPECT_EQ(decimalsFor(0.02), 2);
    EXPECT_EQ(tickStep(5.0, 10.0), 50.0);  // 5 m per mm, ticks >= 10 mm apart
    EXPECT_EQ(tickStep(6.0, 10.0), 100.0);
}

// A known frame: 1:5,000 (0.2 mm per metre), u 0..1000 m and v -200..600 m in a box at
// (50, 40) mm. Every tick is a round multiple of its step, its label is that number, and
// it lies where the scale puts it. Tolerance 1e-9 mm: double arithmetic on a few terms.
TEST(PrintTicks, RoundLabelsAtTheirPagePositions) {
    MapFrame f;
    f.shown = {0.0, -200.0, 1000.0, 600.0};
    f.scale = 5000.0;
    f.box = {50.0, 40.0, 200.0, 160.0};
    const auto h = horizontalTicks(f, {"Distance (m)", 0.0});
    ASSERT_EQ(h.size(), 21u);  // 0, 50, ..., 1000: 50 m = 10 mm, wider than "1000" plus a gap
    for (std::size_t i = 0; i < h.size(); ++i) {
        EXPECT_EQ(h[i].tick.value, 50.0 * double(i));
        EXPECT_EQ(h[i].tick.label, std::to_string(50 * i));
        EXPECT_NEAR(h[i].pageMm, 50.0 + 0.2 * 50.0 * double(i), kPageMmTol);
    }
    const auto v = verticalTicks(f, {"Elevation (m)", 0.0});
    ASSERT_EQ(v.size(), 17u);  // -200, -150, ..., 600
    for (const PlacedTick& t : v) {
        EXPECT_EQ(std::fmod(t.tick.value, 50.0), 0.0);
        EXPECT_EQ(t.tick.label, std::to_string(int(t.tick.value)));
        EXPECT_NEAR(t.pageMm, 40.0 + (600.0 - t.tick.value) * 0.2, kPageMmTol);  // y down from the top (600 m)
    }
    // Distances from an end at u = 123.4: labels count from there, positions stay on the frame.
    const auto d = horizontalTicks(f, {"Distance (m)", 123.4});
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.front().tick.label, "-100");
    for (const PlacedTick& t : d) EXPECT_NEAR(t.pageMm, 50.0 + (t.tick.value + 123.4) * 0.2, kPageMmTol);
    // Coordinates: big numbers grouped, and ticks spread until labels do not touch.
    MapFrame g = f;
    g.shown = {35502000.0, 3387000.0, 35508000.0, 3391000.0};
    g.scale = 30000.0;
    const auto e = horizontalTicks(g, {"Easting (m)", 0.0});
    ASSERT_GE(e.size(), 2u);
    for (std::size_t i = 1; i < e.size(); ++i)
        EXPECT_GE(e[i].pageMm - e[i - 1].pageMm, textWidthMm(e[i].tick.label, kTickLabelPt) + 3.0 - 1e-9);
    EXPECT_EQ(e.front().tick.label.find(','), 2u) << e.front().tick.label;  // "35,50x,000"
}

TEST(PrintFrame, AutoFitPicksARoundScaleAndAGivenScaleMustFit) {
    FitRequest r;
    r.extent = {0.0, 0.0, 6000.0, 2700.0};
    r.area = {0.0, 0.0, 265.0, 200.0};
    r.areaName = "A3 landscape";
    auto f = fitMapFrame(r);
    ASSERT_TRUE(f.ok());
    EXPECT_EQ(f->scale, 25000.0);  // 6000 m into 265 mm needs 1:22,642
    EXPECT_LE(f->box.width, 265.0);
    EXPECT_LE(f->box.height, 200.0);
    EXPECT_NEAR(f->box.width, 6000.0 * 1000.0 / 25000.0, kPageMmTol);
    r.exaggeration = 2.0;
    f = fitMapFrame(r);
    ASSERT_TRUE(f.ok());
    EXPECT_EQ(f->scale, 30000.0);  // 5400 m (2700 m x 2) into 200 mm needs 1:27,000
    r.scale = 5000.0;
    f = fitMapFrame(r);
    ASSERT_FALSE(f.ok());
    EXPECT_EQ(f.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(f.error().message.find("scale: at 1:5,000"), std::string::npos) << f.error().message;
    EXPECT_NE(f.error().message.find("largest round scale that fits is 1:30,000"), std::string::npos)
        << f.error().message;
}

TEST(PrintEnds, CompassPointsAndLetters) {
    EXPECT_EQ(compassPoint(azimuthDeg({1.0, 0.0})), "E");
    EXPECT_EQ(compassPoint(azimuthDeg({-1.0, 0.0})), "W");
    EXPECT_EQ(compassPoint(azimuthDeg({1.0, 1.0})), "NE");
    EXPECT_EQ(compassPoint(359.0), "N");
    EXPECT_EQ(compassPoint(200.0), "S");
    EXPECT_EQ(vertexLetter(0), "A");
    EXPECT_EQ(vertexLetter(25), "Z");
    EXPECT_EQ(vertexLetter(26), "AA");
}

TEST(PrintText, FitAndWrapStayWithinTheirWidth) {
    const std::string longText = "EPSG:4523 CGCS2000 / 3-degree Gauss-Kruger zone 35 and more words to wrap";
    const std::string cut = fitText(longText, 30.0, 7.0);
    EXPECT_LE(textWidthMm(cut, 7.0), 30.0);
    EXPECT_NE(cut.find("\u2026"), std::string::npos);
    for (const std::string& line : wrapText(longText, 40.0, 7.0, 3)) EXPECT_LE(textWidthMm(line, 7.0), 40.0) << line;
    const auto coords = wrapText("line=35502500,3388000,35504500,3389000,35506500,3388500", 40.0, 7.0, 3);
    EXPECT_GE(coords.size(), 2u);
    EXPECT_EQ(coords[0].back(), ',');  // broken after a comma
    EXPECT_TRUE(isCalendarDate("2024-02-29"));
    EXPECT_FALSE(isCalendarDate("2023-02-29"));
    EXPECT_FALSE(isCalendarDate("2026-13-01"));
    EXPECT_FALSE(isCalendarDate("26-01-01"));
}

// A small synthetic mine with a CRS, its index, and the E-W section through its centre.
struct Fixture {
    Model model = test::syntheticModel(20000, OreVariant::Nested, 1, "EPSG:4523");
    std::unique_ptr<SectionIndex> index;
    Section section;
    Fixture() {
        auto idx = buildSectionIndex(model);
        EXPECT_TRUE(idx.ok());
        index = std::move(idx.value());
        const double cy = 0.5 * (index->bounds.min.y + index->bounds.max.y);
        auto s = computeSection(*index, Plane{{0.0, 1.0, 0.0}, -std::round(cy)});
        EXPECT_TRUE(s.ok());
        section = std::move(s.value());
    }
    SheetInfo info() const {
        SheetInfo i;
        i.model = "synthetic";
        i.version = "0123456789abcdef";
        i.crs = "EPSG:4523 CGCS2000 / 3-degree Gauss-Kruger zone 35";
        i.date = "2026-11-24";
        i.definition = "plane=0,1,0,-y&vx=2";
        return i;
    }
    SheetOptions options(const char* paper = "A4") const {
        SheetOptions o;
        o.paper = paperSize(paper, Orientation::Landscape).value();
        o.exaggeration = 2.0;
        return o;
    }
};

std::vector<std::string> texts(const Sheet& sheet) {
    std::vector<std::string> out;
    for (const SheetItem& item : sheet.items)
        if (const auto* t = std::get_if<TextItem>(&item)) out.push_back(t->text);
    return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(PrintSheet, SectionSheetHasItsSurrounds) {
    Fixture fx;
    auto sheet = sectionSheet(*fx.index, fx.section, fx.options(), fx.info());
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    const auto t = texts(sheet.value());
    EXPECT_TRUE(contains(t, "Geological section W\u2013E"));
    EXPECT_TRUE(contains(t, "W"));
    EXPECT_TRUE(contains(t, "E"));
    EXPECT_TRUE(contains(t, "Legend"));
    EXPECT_TRUE(contains(t, "Elevation (m)"));
    EXPECT_TRUE(contains(t, "Distance from W (m)"));
    EXPECT_TRUE(contains(t, "0"));
    EXPECT_TRUE(contains(t, "2026-11-24"));
    bool scale = false, vx = false;
    for (const std::string& s : t) {
        scale |= s.rfind("Scale 1:", 0) == 0;
        vx |= s.find("vertical exaggeration \u00d72") != std::string::npos;
    }
    EXPECT_TRUE(scale);
    EXPECT_TRUE(vx);
    // Every record the section cuts has a legend row with its name.
    for (const BodySection& b : fx.section.bodies) {
        const AttributeRecord* r = fx.model.attributes.find(b.record);
        ASSERT_NE(r, nullptr);
        EXPECT_TRUE(contains(t, r->name)) << r->name;
    }
    // A scale that does not fit names the parameter.
    SheetOptions big = fx.options();
    big.scale = 500.0;
    auto refused = sectionSheet(*fx.index, fx.section, big, fx.info());
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().message.rfind("scale: at 1:500", 0), 0u) << refused.error().message;
    // A horizontal plane seen from below is refused; the slice seen from above has a north arrow.
    const double z = 0.5 * (fx.index->bounds.min.z + fx.index->bounds.max.z);
    auto below = computeSection(*fx.index, Plane{{0.0, 0.0, 1.0}, -z});
    ASSERT_TRUE(below.ok());
    EXPECT_EQ(sectionSheet(*fx.index, below.value(), fx.options(), fx.info()).error().code, ErrorCode::Unsupported);
    auto slice = computeSection(*fx.index, horizontalPlane(z));
    ASSERT_TRUE(slice.ok());
    auto plan = sectionSheet(*fx.index, slice.value(), fx.options(), fx.info());
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    EXPECT_TRUE(contains(texts(plan.value()), "N"));
    EXPECT_TRUE(contains(texts(plan.value()), "Northing (m)"));
    // True north from grid north: Transverse Mercator convergence is about (lon - lon0) sin(lat)
    // (Snyder, "Map Projections: A Working Manual", 1987, eq. 8-4 to first order): 0.03 degrees
    // west at 105.05 E, 30.6 N in zone 35 (central meridian 105 E). Tolerance 1e-3 degrees:
    // the first-order formula's neglected terms and the 0.001-degree step.
    const glm::dvec2 centre{0.5 * (fx.index->bounds.min.x + fx.index->bounds.max.x),
                            0.5 * (fx.index->bounds.min.y + fx.index->bounds.max.y)};
    auto ll = fx.model.crs.toLonLat(centre.x, centre.y);
    ASSERT_TRUE(ll.ok());
    auto tn = trueNorthDeg(fx.model.crs, centre);
    ASSERT_TRUE(tn.has_value());
    const double expected = -(ll.value().x - 105.0) * std::sin(ll.value().y * std::numbers::pi / 180.0);
    EXPECT_NEAR(*tn, expected, kConvergenceDeg);
    EXPECT_FALSE(trueNorthDeg(Crs::local(), centre).has_value());
    bool stated = false;
    for (const std::string& s : texts(plan.value())) stated |= s.rfind("true north ", 0) == 0;
    EXPECT_TRUE(stated);
}

// Vertical exaggeration on an inclined plane: images and tiles stretch the plane's v axis
// by vStretch(n) = sqrt(nz^2 + k^2 (1 - nz^2)) (view/exaggeration.hpp), the picture of the
// display space where only elevation is scaled; a sheet that stretched v by the raw factor
// k would draw a different picture of the same plane. The sheet follows the images: its
// down-dip stretch is vStretch, not k, and its scale row says both.
TEST(PrintSheet, InclinedPlaneIsStretchedAsImagesStretchIt) {
    Fixture fx;
    const double dip = 40.0 * std::numbers::pi / 180.0;  // normal 40 degrees from vertical
    const glm::dvec3 n{0.0, std::sin(dip), std::cos(dip)};
    const double cy = 0.5 * (fx.index->bounds.min.y + fx.index->bounds.max.y);
    const double cz = 0.5 * (fx.index->bounds.min.z + fx.index->bounds.max.z);
    auto section = computeSection(*fx.index, Plane{n, -(n.y * cy + n.z * cz)});
    ASSERT_TRUE(section.ok()) << section.error().message;
    SheetOptions o = fx.options("A3");
    o.exaggeration = 3.0;
    auto sheet = sectionSheet(*fx.index, section.value(), o, fx.info());
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    const double stretch = VerticalExaggeration{3.0, 0.0}.vStretch(n);
    ASSERT_GT(std::abs(stretch - 3.0), 0.5);  // the two pictures differ visibly here
    // The title block wraps the scale row: its lines joined again by spaces.
    std::string all;
    for (const std::string& t : texts(sheet.value())) all += t + " ";
    const std::size_t at = all.find("along strike");
    ASSERT_NE(at, std::string::npos) << "no along-strike scale on an inclined sheet";
    const std::size_t start = all.rfind("1:", at);
    const std::string scaleRow = all.substr(start, all.find(')', at) + 1 - start);
    EXPECT_NE(scaleRow.find("VE \u00d73"), std::string::npos) << scaleRow;
    EXPECT_NE(scaleRow.find("down-dip \u00d7" + formatGrouped(stretch, 3)), std::string::npos)
        << scaleRow << " (vStretch " << stretch << ")";
    // The two scales' ratio is the stretch: "Scale 1:H along strike, 1:V down dip".
    auto number = [&](std::size_t from) {
        std::string digits;
        for (std::size_t i = scaleRow.find("1:", from) + 2; i < scaleRow.size(); ++i) {
            if (std::isdigit(static_cast<unsigned char>(scaleRow[i])) || scaleRow[i] == '.')
                digits += scaleRow[i];
            else if (scaleRow[i] != ',')  // 1:12,500.000
                break;
        }
        return std::atof(digits.c_str());
    };
    const double h = number(0), v = number(scaleRow.find("along strike"));
    ASSERT_GT(h, 0.0);
    ASSERT_GT(v, 0.0);
    EXPECT_NEAR(h / v, stretch, 0.01 * stretch) << scaleRow;
}

TEST(PrintSheet, PolylineSheetNamesItsVerticesAndMarksBends) {
    Fixture fx;
    const Aabb& b = fx.index->bounds;
    const std::vector<glm::dvec2> pts{{b.min.x + 100.0, b.min.y + 500.0},
                                      {0.5 * (b.min.x + b.max.x), b.max.y - 500.0},
                                      {b.max.x - 100.0, b.min.y + 800.0}};
    auto line = computePolylineSection(*fx.index, pts);
    ASSERT_TRUE(line.ok());
    auto sheet = sectionSheet(*fx.index, line.value(), fx.options(), fx.info());
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    const auto t = texts(sheet.value());
    EXPECT_TRUE(contains(t, "Geological section A\u2013B\u2013C"));
    for (const char* s : {"A", "B", "C", "Distance along the section from A (m)"}) EXPECT_TRUE(contains(t, s)) << s;
    std::size_t dashed = 0;
    for (const SheetItem& item : sheet.value().items)
        if (const auto* p = std::get_if<PathItem>(&item)) dashed += p->dashMm > 0.0;
    EXPECT_EQ(dashed, 1u);  // the bend at B
}

std::string tempPath(const std::string& name) { return testing::TempDir() + "geoslice_print_" + name; }

std::string runText(const std::string& command) {
    std::string out;
    FILE* p = popen(command.c_str(), "r");
    if (!p) return out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    pclose(p);
    return out;
}

TEST(PrintSvg, ParsesAsXmlAndKeepsTextAsText) {
    Fixture fx;
    auto sheet = sectionSheet(*fx.index, fx.section, fx.options(), fx.info());
    ASSERT_TRUE(sheet.ok());
    auto svg = renderSvg(sheet.value());
    ASSERT_TRUE(svg.ok()) << svg.error().message;
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed = doc.load_string(svg->c_str());
    ASSERT_TRUE(parsed) << parsed.description();
    const pugi::xml_node root = doc.child("svg");
    EXPECT_STREQ(root.attribute("width").value(), "297mm");
    EXPECT_STREQ(root.attribute("viewBox").value(), "0 0 297 210");
    std::set<std::string> textContent;
    std::size_t textCount = 0, paths = 0;
    for (pugi::xml_node n : root.children()) {
        if (std::string(n.name()) == "text") {
            ++textCount;
            textContent.insert(n.text().get());
        }
        paths += std::string(n.name()) == "path";
        EXPECT_NE(std::string(n.name()), "use");  // no glyphs drawn as shapes
        EXPECT_NE(std::string(n.name()), "image");
    }
    EXPECT_EQ(textCount, texts(sheet.value()).size());
    EXPECT_TRUE(textContent.count("Legend"));
    EXPECT_TRUE(textContent.count("Geological section W\u2013E"));
    EXPECT_GE(paths, fx.section.bodies.size());
}

// Compares a rendering with the golden case tests/data/goldens/<name>/ (request.json: the
// sheet, the raster dpi and the tolerance of output "page" with its reason: a pixel fails when
// an RGB channel differs by more than 64 of 255, at most 0.5 % may fail; anti-aliasing and
// glyph rasterisation depend on the poppler, cairo and FreeType builds) by the shared
// comparator (tests/common/golden.hpp); UPDATE_GOLDENS=1 rewrites it.
void expectGolden(const DecodedImage& actual, const std::string& name) {
    const nlohmann::json request = test::goldenRequest(name);
    EXPECT_EQ(request.value("runner", ""), "print");
    EXPECT_EQ(request.value("rasterDpi", 0), 40) << "the dpi pdftoppm is run with here";
    test::compareGolden(name, "page", actual.rgba.data(), actual.width, actual.height,
                        test::goldenTolerance(request, "page"), tempPath("golden_failures"));
}

// The PDF: opened by poppler (pdftoppm), its rendering compared with a golden image, and
// its text extracted (pdftotext) -- text stays text.
TEST(PrintPdf, OpensInPopplerAndMatchesItsGolden) {
    Fixture fx;
    // The golden predates unit labels and lithology patterns (print_labels_test.cpp tests them).
    SheetOptions o = fx.options();
    o.labels = o.patterns = false;
    auto sheet = sectionSheet(*fx.index, fx.section, o, fx.info());
    ASSERT_TRUE(sheet.ok());
    auto pdf = renderPdf(sheet.value());
    ASSERT_TRUE(pdf.ok()) << pdf.error().message;
    ASSERT_EQ(pdf->rfind("%PDF-", 0), 0u);
    auto again = renderPdf(sheet.value());
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(pdf.value(), again.value()) << "the same sheet must give the same bytes (dated metadata)";
    const std::string path = tempPath("sheet.pdf");
    {
        std::ofstream f(path, std::ios::binary);
        f << pdf.value();
    }
    const std::string base = tempPath("sheet");
    ASSERT_EQ(std::system(("pdftoppm -r 40 -png -singlefile '" + path + "' '" + base + "'").c_str()), 0)
        << "pdftoppm (poppler-utils) could not open the PDF";
    auto actual = readPngRgba(base + ".png");
    ASSERT_TRUE(actual.ok()) << actual.error().message;
    EXPECT_EQ(actual->width, 468);  // 297 mm at 40 dpi
    EXPECT_EQ(actual->height, 331);

    expectGolden(actual.value(), "print_section_a4");

    const std::string text = runText("pdftotext -layout '" + path + "' -");
    for (const char* s : {"Geological section W", "Legend", "Elevation (m)", "2026-11-24", "Scale 1:"})
        EXPECT_NE(text.find(s), std::string::npos) << s << " not found in the PDF's text:\n" << text;
}

// Chinese unit names (a Geo3DML model's records, "雾迷山组"): set in WenQuanYi Micro Hei, whose glyphs
// the PDF embeds, so the names print instead of empty boxes; pdftotext reads them back.
// A block model over the fixture's orebodies: a 16 x 16 x 8 grid over the model's bounds,
// grade = 0.25 i + 0.1 k g/t Au, clipped by the bodies whose record is an orebody; classes
// < 1, 1 - 2, 2 - 3, >= 3 on viridis.
struct BlockFixture : Fixture {
    BlockModel blocks;
    SheetBlocks sheetBlocks() {
        const Aabb& b = index->bounds;
        blocks.source = "test grid";
        blocks.origin = b.min;
        blocks.dims = {16, 16, 8};
        for (int a = 0; a < 3; ++a)
            blocks.size[std::size_t(a)] = (b.max[a] - b.min[a]) / double(blocks.dims[std::size_t(a)]);
        BlockProperty grade{"grade", "g/t Au", std::vector<double>(blocks.cellCount())};
        for (std::size_t c = 0; c < blocks.cellCount(); ++c) {
            const auto ijk = blocks.ijk(c);
            grade.values[c] = 0.25 * double(ijk[0]) + 0.1 * double(ijk[2]);
        }
        blocks.properties.push_back(std::move(grade));
        for (const Part& p : model.bodies)
            if (const AttributeRecord* r = model.attributes.find(p.record); r && r->kind == "orebody")
                blocks.clipBodies.push_back(p.name);
        EXPECT_FALSE(blocks.clipBodies.empty());
        EXPECT_TRUE(resolveBlockClip(model, blocks).ok());
        auto classes = makePropertyClasses(0, "viridis", {1.0, 2.0, 3.0});
        EXPECT_TRUE(classes.ok());
        return SheetBlocks{&blocks, classes.value(), blockClipRecords(model, blocks)};
    }
};

TEST(PrintSheet, BlockColouredSheetShowsItsRamp) {
    BlockFixture fx;
    SheetOptions o = fx.options();
    o.labels = o.patterns = false;  // the golden predates labels and patterns (print_labels_test.cpp)
    o.blocks = fx.sheetBlocks();
    const PropertyClasses& classes = o.blocks->classes;
    // Vector: one path per piece with a value, in its class colour; the ramp in the legend.
    auto sheet = sectionSheet(*fx.index, fx.section, o, fx.info());
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    const auto t = texts(sheet.value());
    EXPECT_TRUE(contains(t, "grade (g/t Au), viridis classes"));
    for (const char* label : {"< 1", "1 - 2", "2 - 3", ">= 3"}) EXPECT_TRUE(contains(t, label)) << label;
    auto pieces = blockPieces(fx.blocks, fx.section);
    ASSERT_TRUE(pieces.ok());
    std::map<int, std::size_t> expected, got;  // class -> pieces
    for (const BlockPiece& p : pieces.value()) ++expected[classes.classOf(fx.blocks.properties[0].values[p.cell])];
    ASSERT_GE(expected.size(), 2u) << "the section should show several classes";
    for (const SheetItem& item : sheet->items)
        if (const auto* p = std::get_if<PathItem>(&item); p && p->title.rfind("grade ", 0) == 0) {
            ASSERT_TRUE(p->fill);
            for (std::size_t k = 0; k < classes.colours.size(); ++k)
                if (p->title == "grade " + classes.label(k)) {
                    EXPECT_EQ(p->fill->r, classes.colours[k].r);
                    EXPECT_EQ(p->fill->g, classes.colours[k].g);
                    EXPECT_EQ(p->fill->b, classes.colours[k].b);
                    ++got[int(k)];
                }
        }
    EXPECT_EQ(got, expected);
    // The title block names the colouring (its value wraps over lines).
    std::string all;
    for (const std::string& s : t) all += s + " ";
    EXPECT_NE(all.find("block property grade"), std::string::npos) << all;
    EXPECT_NE(all.find("test grid"), std::string::npos) << all;
    // Polyline sheets are coloured too.
    const Aabb& b = fx.index->bounds;
    auto line = computePolylineSection(*fx.index, {{b.min.x + 100.0, 0.5 * (b.min.y + b.max.y)},
                                                   {0.5 * (b.min.x + b.max.x), b.max.y - 500.0},
                                                   {b.max.x - 100.0, 0.5 * (b.min.y + b.max.y)}});
    ASSERT_TRUE(line.ok());
    auto lineSheet = sectionSheet(*fx.index, line.value(), o, fx.info());
    ASSERT_TRUE(lineSheet.ok()) << lineSheet.error().message;
    auto linePieces = blockPieces(fx.blocks, line.value(), fx.index->origin);
    ASSERT_TRUE(linePieces.ok());
    std::size_t linePaths = 0;
    for (const SheetItem& item : lineSheet->items)
        if (const auto* p = std::get_if<PathItem>(&item); p && p->title.rfind("grade ", 0) == 0) ++linePaths;
    EXPECT_EQ(linePaths, linePieces->size());
    EXPECT_GT(linePaths, 0u);
    // Raster: the map box's pixels take the class colours (the profile images' rule).
    SheetOptions ro = o;
    ro.rasterGeometry = true;
    ro.dpi = 60.0;
    auto raster = sectionSheet(*fx.index, fx.section, ro, fx.info());
    ASSERT_TRUE(raster.ok()) << raster.error().message;
    std::map<int, std::size_t> classPixels;
    for (const SheetItem& item : raster->items)
        if (const auto* im = std::get_if<ImageItem>(&item))
            for (std::size_t i = 0; i < im->rgba.size(); i += 4)
                for (std::size_t k = 0; k < classes.colours.size(); ++k)
                    if (im->rgba[i] == classes.colours[k].r && im->rgba[i + 1] == classes.colours[k].g &&
                        im->rgba[i + 2] == classes.colours[k].b && im->rgba[i + 3] == 255)
                        ++classPixels[int(k)];
    for (const auto& [k, n] : expected) EXPECT_GT(classPixels[k], 0u) << "class " << k;
    // The PDF: poppler opens it; its rendering matches a golden (the tolerance of the plain
    // sheet's golden above); the ramp's text is text.
    auto pdf = renderPdf(sheet.value());
    ASSERT_TRUE(pdf.ok()) << pdf.error().message;
    const std::string path = tempPath("blocks.pdf"), base = tempPath("blocks");
    {
        std::ofstream f(path, std::ios::binary);
        f << pdf.value();
    }
    ASSERT_EQ(std::system(("pdftoppm -r 40 -png -singlefile '" + path + "' '" + base + "'").c_str()), 0);
    auto actual = readPngRgba(base + ".png");
    ASSERT_TRUE(actual.ok()) << actual.error().message;
    expectGolden(actual.value(), "print_section_blocks_a4");
    // pdftotext drops the spaces of short labels ("2-3"): compare without spaces.
    std::string text = runText("pdftotext -layout '" + path + "' -");
    std::erase(text, ' ');
    for (const char* s : {"grade(g/tAu),viridisclasses", ">=3", "2-3", "<1"})
        EXPECT_NE(text.find(s), std::string::npos) << s << " not found in the PDF's text:\n" << text;
}

TEST(PrintPdf, ChineseUnitNamesGetACjkFont) {
    EXPECT_STREQ(fontFamilyFor("Maokou Formation (P2m)"), kFontFamily);
    EXPECT_STREQ(fontFamilyFor("\u5730\u5c42C"), kCjkFontFamily);
    auto model = loadModel(std::string(GEOSLICE_TEST_DATA_DIR) + "/geo3dml/model_Volume_1.xml");
    ASSERT_TRUE(model.ok()) << model.error().message;
    validate(model.value());
    auto index = buildSectionIndex(model.value());
    ASSERT_TRUE(index.ok());
    auto section = computeSection(*index.value(), Plane{{1.0, 0.0, 0.0}, -100.0});
    ASSERT_TRUE(section.ok()) << section.error().message;
    SheetOptions o;
    o.paper = paperSize("A4", Orientation::Landscape).value();
    SheetInfo info;
    info.model = "model_Volume_1";
    info.date = "2026-11-24";
    auto sheet = sectionSheet(*index.value(), section.value(), o, info);
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    auto pdf = renderPdf(sheet.value());
    ASSERT_TRUE(pdf.ok());
    const std::string path = tempPath("cjk.pdf");
    {
        std::ofstream f(path, std::ios::binary);
        f << pdf.value();
    }
    EXPECT_NE(runText("pdffonts '" + path + "'").find("WenQuanYi"), std::string::npos);
    const std::string text = runText("pdftotext '" + path + "' -");
    for (const BodySection& b : section.value().bodies) {
        const AttributeRecord* r = model.value().attributes.find(b.record);
        ASSERT_NE(r, nullptr);
        EXPECT_STREQ(fontFamilyFor(r->name), kCjkFontFamily) << r->name;  // e.g. 雾迷山组
        EXPECT_NE(text.find(r->name), std::string::npos) << r->name << " not in\n" << text;
    }
}

// decorate=1: the section is the engine's raster, pixel-aligned in the map box of a sheet
// drawn at the asked resolution.
TEST(PrintRaster, DecoratedSheetAtItsResolution) {
    Fixture fx;
    SheetOptions o = fx.options("A5");
    o.rasterGeometry = true;
    o.dpi = 100.0;
    o.labels = o.patterns = false;  // nothing over the raster but the surrounds (section_labels_test.cpp)
    auto sheet = sectionSheet(*fx.index, fx.section, o, fx.info());
    ASSERT_TRUE(sheet.ok()) << sheet.error().message;
    const ImageItem* image = nullptr;
    for (const SheetItem& item : sheet.value().items)
        if (const auto* im = std::get_if<ImageItem>(&item)) image = im;
    ASSERT_NE(image, nullptr);
    // Pixel aligned: the box's corners land on whole pixels and the image has one pixel per pixel.
    const double ppmm = 100.0 / 25.4;
    EXPECT_NEAR(image->box.x * ppmm, std::round(image->box.x * ppmm), kPixelAlignTolPx);
    EXPECT_NEAR(image->box.width * ppmm, double(image->width), kPixelAlignTolPx);
    auto raster = renderRaster(sheet.value(), 100.0);
    ASSERT_TRUE(raster.ok()) << raster.error().message;
    EXPECT_EQ(raster->width, sheetPixels(210.0, 100.0));
    EXPECT_EQ(raster->height, sheetPixels(148.0, 100.0));
    // The section image shows in the sheet unchanged where it is opaque, except under the
    // grid lines, ticks and outline drawn over it: at least 90 % of its opaque pixels.
    const int ox = int(std::lround(image->box.x * ppmm)), oy = int(std::lround(image->box.y * ppmm));
    std::size_t opaque = 0, same = 0;
    for (int y = 0; y < image->height; ++y)
        for (int x = 0; x < image->width; ++x) {
            const std::uint8_t* src = &image->rgba[(std::size_t(y) * std::size_t(image->width) + std::size_t(x)) * 4];
            if (src[3] != 255) continue;
            ++opaque;
            const std::uint8_t* dst =
                &raster->rgba[(std::size_t(oy + y) * std::size_t(raster->width) + std::size_t(ox + x)) * 4];
            same += std::abs(dst[0] - src[0]) <= 1 && std::abs(dst[1] - src[1]) <= 1 && std::abs(dst[2] - src[2]) <= 1;
        }
    ASSERT_GT(opaque, 1000u);
    EXPECT_GE(double(same), 0.9 * double(opaque)) << same << " of " << opaque;
    EXPECT_FALSE(renderSvg(sheet.value()).ok());  // raster items never go into an SVG
}

}  // namespace
}  // namespace geoslice::print
