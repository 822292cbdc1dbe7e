// Unit labels and lithology patterns over HTTP: section.png?labels=1&patterns=1 differs from
// the plain image only where units are (the ID buffer, and so pixel queries, unchanged);
// section.svg carries <pattern>s, and labels on request; section.pdf has the codes by default;
// a bad labels/patterns value is a 400 naming the parameter.
#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include "server/http_server.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {
namespace {

using nlohmann::json;

const std::string kSection = "/v1/models/demo/section.";
const std::string kView = "plane=0,1,0,-3388846&size=600x300";

class Labels : public InProcessServer {
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

TEST_F(Labels, ImagesSvgAndParameters) {
    auto plain = get(kSection + "png?" + kView);
    auto decorated = get(kSection + "png?" + kView + "&labels=1&patterns=1");
    ASSERT_TRUE(plain && decorated);
    ASSERT_EQ(plain->status, 200);
    ASSERT_EQ(decorated->status, 200) << decorated->body;
    EXPECT_NE(plain->body, decorated->body);
    EXPECT_NE(plain->get_header_value("ETag"), decorated->get_header_value("ETag"));
    // The same pixel answers the same record with and without decorations.
    const json a = json::parse(get("/v1/models/demo/query?" + kView + "&px=300&py=150")->body);
    const json b = json::parse(get("/v1/models/demo/query?" + kView + "&labels=1&patterns=1&px=300&py=150")->body);
    ASSERT_TRUE(a.contains("record")) << a;
    EXPECT_EQ(a["record"], b["record"]);

    auto svg = get(kSection + "svg?" + kView + "&labels=1");
    ASSERT_TRUE(svg);
    ASSERT_EQ(svg->status, 200);
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_string(svg->body.c_str()));
    EXPECT_TRUE(doc.child("svg").child("defs").child("pattern"));
    EXPECT_TRUE(doc.child("svg").find_child_by_attribute("g", "class", "unit-label"));
    auto bare = get(kSection + "svg?" + kView + "&patterns=0");
    ASSERT_TRUE(bare);
    EXPECT_EQ(bare->body.find("<pattern"), std::string::npos);

    for (const char* bad : {"labels=2", "patterns=maybe"}) {
        auto r = get(kSection + "png?" + kView + "&" + bad);
        ASSERT_TRUE(r);
        EXPECT_EQ(r->status, 400) << bad;
        EXPECT_NE(r->body.find(std::string(bad).substr(0, std::string(bad).find('='))), std::string::npos);
    }
}

}  // namespace
}  // namespace geoslice::server
