// Print sheets over HTTP (api/sheet.hpp): section.pdf, section.svg?layout=print and
// section.png?decorate=1 on the demo model, and bad sheet parameters answered 400 with the
// parameter named.
#include <gtest/gtest.h>
#include <httplib.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "server/http_server.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
namespace {

using nlohmann::json;

const std::string kBase = "/v1/models/demo/section.";
const std::string kPlane = "plane=0,1,0,-3388846";

class Sheets : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        ServerConfig c = loopbackConfig();
        c.demoTriangles = 20000;
        c.cacheMiB = 64;
        c.deadlineMs = 20000;
        startServer(c);
    }
    static void TearDownTestSuite() { stopServer(); }
};

void expectProblem(const httplib::Result& r, const std::string& parameter, const std::string& needle = "") {
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json j = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(j.is_object()) << r->body;
    const std::string detail = j.value("detail", "");
    EXPECT_NE(detail.find("parameter '" + parameter + "'"), std::string::npos) << detail;
    EXPECT_NE(detail.find(needle), std::string::npos) << detail;
}

// PDFs answer one byte range (RFC 9110 14): 206 with Content-Range and exactly those bytes,
// a suffix range, 416 past the end, and the whole body when If-Range names another ETag.
TEST_F(Sheets, PdfByteRanges) {
    const std::string path = kBase + "pdf?" + kPlane + "&paper=A4&date=2026-11-24";
    auto whole = get(path);
    ASSERT_TRUE(whole);
    ASSERT_EQ(whole->status, 200) << whole->body;
    EXPECT_EQ(whole->get_header_value("Accept-Ranges"), "bytes");
    const std::string& body = whole->body;
    const std::string total = std::to_string(body.size());
    const std::string etag = whole->get_header_value("ETag");
    httplib::Client c("127.0.0.1", server_->port());
    auto ranged = [&](const httplib::Headers& h) { return c.Get(path.c_str(), h); };
    auto r = ranged({{"Range", "bytes=0-99"}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 206);
    EXPECT_EQ(r->get_header_value("Content-Range"), "bytes 0-99/" + total);
    EXPECT_EQ(r->body, body.substr(0, 100));
    r = ranged({{"Range", "bytes=-10"}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 206);
    EXPECT_EQ(r->body, body.substr(body.size() - 10));
    r = ranged({{"Range", "bytes=100-"}, {"If-Range", etag}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 206);
    EXPECT_EQ(r->body, body.substr(100));
    r = ranged({{"Range", "bytes=" + total + "-"}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 416);
    EXPECT_EQ(r->get_header_value("Content-Range"), "bytes */" + total);
    r = ranged({{"Range", "bytes=0-99"}, {"If-Range", "\"someone-elses\""}});
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body, body);
    r = ranged({{"Range", "bytes=0-1,5-9"}});  // several ranges: the whole body, as RFC 9110 14.2 allows
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body, body);
}

// decorate and layout are booleans/choices as documented: their "off" values give the plain
// image or SVG, not an "unknown parameter" 400.
TEST_F(Sheets, UndecoratedIsThePlainAnswer) {
    auto plain = get(kBase + "png?" + kPlane + "&size=64x32");
    ASSERT_TRUE(plain);
    ASSERT_EQ(plain->status, 200);
    for (const char* off : {"decorate=0", "decorate=false"}) {
        auto r = get(kBase + "png?" + kPlane + "&size=64x32&" + off);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 200) << off << " " << r->body;
        EXPECT_EQ(r->body, plain->body) << off;
    }
    auto svg = get(kBase + "svg?" + kPlane + "&size=64x32&layout=plain&decorate=0");
    ASSERT_TRUE(svg);
    EXPECT_EQ(svg->status, 200) << svg->body;
    auto geo = get(kBase + "geojson?" + kPlane + "&decorate=1");
    ASSERT_TRUE(geo);
    EXPECT_EQ(geo->status, 400);  // GeoJSON has no decorated form
}

TEST_F(Sheets, PdfSvgAndDecoratedImages) {
    auto pdf = get(kBase + "pdf?" + kPlane + "&paper=A4&vx=2&date=2026-11-24");
    ASSERT_TRUE(pdf);
    ASSERT_EQ(pdf->status, 200) << pdf->body;
    EXPECT_EQ(pdf->get_header_value("Content-Type"), "application/pdf");
    EXPECT_EQ(pdf->body.rfind("%PDF-", 0), 0u);
    const std::string etag = pdf->get_header_value("ETag");
    EXPECT_FALSE(etag.empty());
    {
        httplib::Client c("127.0.0.1", server_->port());
        auto again = c.Get((kBase + "pdf?" + kPlane + "&paper=A4&vx=2&date=2026-11-24").c_str(),
                           httplib::Headers{{"If-None-Match", etag}});
        ASSERT_TRUE(again);
        EXPECT_EQ(again->status, 304);
    }

    auto svg = get(kBase + "svg?layout=print&line=35502500,3388000,35504500,3389000,35506500,3388500&paper=A3");
    ASSERT_TRUE(svg);
    ASSERT_EQ(svg->status, 200) << svg->body;
    EXPECT_EQ(svg->get_header_value("Content-Type"), "image/svg+xml");
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(svg->body.c_str()));
    std::size_t texts = 0;
    bool title = false;
    for (pugi::xml_node n : doc.child("svg").children("text")) {
        ++texts;
        title |= std::string(n.text().get()) == "Geological section A\u2013B\u2013C";
    }
    EXPECT_GT(texts, 30u);
    EXPECT_TRUE(title);

    // The plain SVG (no layout) is unchanged: the section alone in pixel space (holes=0: the
    // demo's drillholes would add their ids as text).
    auto plain = get(kBase + "svg?" + kPlane + "&size=256x128&holes=0");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->status, 200);
    EXPECT_EQ(plain->body.find("<text"), std::string::npos);

    auto png = get(kBase + "png?" + kPlane + "&decorate=1&paper=A5&dpi=50");
    ASSERT_TRUE(png);
    ASSERT_EQ(png->status, 200) << png->body;
    EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
    ASSERT_GT(png->body.size(), 24u);
    auto be32 = [&](std::size_t at) {
        return (std::uint32_t(std::uint8_t(png->body[at])) << 24) |
               (std::uint32_t(std::uint8_t(png->body[at + 1])) << 16) |
               (std::uint32_t(std::uint8_t(png->body[at + 2])) << 8) | std::uint32_t(std::uint8_t(png->body[at + 3]));
    };
    EXPECT_EQ(be32(16), 413u);  // A5 landscape, 210 x 148 mm at 50 dpi
    EXPECT_EQ(be32(20), 291u);
    auto jpg = get(kBase + "jpg?elevation=300&decorate=true&paper=A5&dpi=60&orientation=portrait");
    ASSERT_TRUE(jpg);
    EXPECT_EQ(jpg->status, 200) << jpg->body;
    EXPECT_EQ(jpg->get_header_value("Content-Type"), "image/jpeg");
}

TEST_F(Sheets, BadSheetParametersAreNamed) {
    const std::string pdf = kBase + "pdf?" + kPlane;
    expectProblem(get(pdf + "&paper=B7"), "paper", "not a paper size");
    expectProblem(get(pdf + "&orientation=sideways"), "orientation", "landscape or portrait");
    expectProblem(get(pdf + "&scale=0"), "scale", "scale denominator");
    expectProblem(get(pdf + "&scale=abc"), "scale");
    expectProblem(get(pdf + "&scale=nan"), "scale");
    expectProblem(get(pdf + "&scale=500&paper=A4"), "scale", "largest round scale that fits");
    expectProblem(get(pdf + "&dpi=300"), "dpi", "decorated images");
    expectProblem(get(pdf + "&size=100x100"), "size");
    expectProblem(get(pdf + "&bg=%23ff0000"), "bg");
    expectProblem(get(pdf + "&date=2026-02-30"), "date");
    expectProblem(get(pdf + "&view=perspective"), "view");
    expectProblem(get(kBase + "png?" + kPlane + "&decorate=1&dpi=1000"), "dpi", "50..600");
    expectProblem(get(kBase + "png?" + kPlane + "&decorate=1&paper=A0&dpi=600"), "dpi", "pixels");
    expectProblem(get(kBase + "png?" + kPlane + "&decorate=maybe"), "decorate");
    expectProblem(get(kBase + "svg?" + kPlane + "&layout=fancy"), "layout");
    expectProblem(get(kBase + "svg?" + kPlane + "&decorate=1"), "decorate");
    auto unknown = get(pdf + "&papr=A4");
    ASSERT_TRUE(unknown);
    EXPECT_EQ(unknown->status, 400);
    EXPECT_NE(unknown->body.find("papr"), std::string::npos);
}

}  // namespace
}  // namespace geoslice::server
