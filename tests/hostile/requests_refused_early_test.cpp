// Requests that were accepted and then failed later (or were silently ignored): 'coords' on a
// request without a 'line' (it gives the units of 'line' only), and a section colouring by a
// block property defined on a model without a block model (was 201, then every tile a 400).
// Each must be a 400 at once whose detail names the parameter. The demo model has no block
// model (api::makeDemoModel: the synthetic mine, no blocks sidecar).
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

using nlohmann::json;

class RefusedEarly : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = ServeProcess::start({"--gl", "none", "--demo-triangles", "20000", "--workers", "2"}).release();
        ASSERT_NE(server_, nullptr);
        ASSERT_TRUE(server_->waitReady()) << server_->log();
    }
    static void TearDownTestSuite() {
        delete server_;
        server_ = nullptr;
    }
    // The status, and the problem detail (or the body when it is not a problem).
    static std::pair<int, std::string> send(const std::string& method, const std::string& path,
                                            const std::string& body = "") {
        auto cl = server_->client(30);
        auto r = method == "GET" ? cl.Get(path.c_str()) : cl.Post(path.c_str(), body, "application/json");
        if (!r) return {0, "no answer"};
        const json j = json::parse(r->body, nullptr, false);
        if (r->status >= 400 && j.is_object() && j.contains("detail")) return {r->status, j["detail"]};
        return {r->status, r->body};
    }
    static ServeProcess* server_;
};
ServeProcess* RefusedEarly::server_ = nullptr;

// The demo model's east-west section through its centre (northing 3388846 m).
const std::string kPlane = "plane=0,1,0,-3388846";

TEST_F(RefusedEarly, CoordsWithoutALineIsA400NamingIt) {
    const std::string view = "&size=64x32";
    for (const std::string& path : {"/v1/models/demo/section.png?" + kPlane + "&coords=lonlat" + view,
                                    "/v1/models/demo/section.png?elevation=500&coords=world" + view,
                                    "/v1/models/demo/query?" + kPlane + "&coords=4326&px=10&py=10" + view,
                                    "/v1/models/demo/section.geojson?" + kPlane + "&coords=lonlat" + view}) {
        const auto [status, detail] = send("GET", path);
        EXPECT_EQ(status, 400) << path << ": " << detail;
        EXPECT_NE(detail.find("parameter 'coords'"), std::string::npos) << path << ": " << detail;
    }
    for (const auto& [path, body] : std::vector<std::pair<std::string, std::string>>{
             {"/v1/models/demo/sections", R"({"plane":[0,1,0,-3388846],"coords":"lonlat"})"},
             {"/v1/models/demo/sections", R"({"elevation":500,"coords":"bogus"})"},
             {"/v1/models/demo/query", R"({"view":{"plane":"0,1,0,-3388846","coords":"world","size":"64x32"},)"
                                       R"("pixels":[[1,1]]})"}}) {
        const auto [status, detail] = send("POST", path, body);
        EXPECT_EQ(status, 400) << path << " " << body << ": " << detail;
        EXPECT_NE(detail.find("parameter 'coords'"), std::string::npos) << path << " " << body << ": " << detail;
    }
    // Routes without a section take no 'coords' at all.
    for (const std::string path :
         {"/v1/models/demo/borehole?x=35504794&y=3388846&coords=lonlat", "/v1/models/demo/legend.png?coords=lonlat"}) {
        const auto [status, detail] = send("GET", path);
        EXPECT_EQ(status, 400) << path << ": " << detail;
        EXPECT_NE(detail.find("coords"), std::string::npos) << path << ": " << detail;
    }
    // With a line it is what it says: degrees.
    const auto [status, detail] =
        send("GET", "/v1/models/demo/section.png?line=105.04,30.61,105.06,30.63&coords=lonlat" + view);
    EXPECT_EQ(status, 200) << detail;
}

TEST_F(RefusedEarly, SectionColouredByABlockPropertyWithoutABlockModelIsA400) {
    const auto [status, detail] =
        send("POST", "/v1/models/demo/sections", R"({"plane":[0,1,0,-3388846],"colour":"grade"})");
    EXPECT_EQ(status, 400) << detail;  // was 201, and then every tile 400
    EXPECT_NE(detail.find("parameter 'colour'"), std::string::npos) << detail;
    EXPECT_NE(detail.find("no block model"), std::string::npos) << detail;
    // Without the colouring the section is defined, and its tiles draw.
    const auto [okStatus, body] = send("POST", "/v1/models/demo/sections", R"({"plane":[0,1,0,-3388846]})");
    ASSERT_EQ(okStatus, 201) << body;
    const json j = json::parse(body, nullptr, false);
    ASSERT_TRUE(j.is_object() && j.contains("sid")) << body;
    const auto [tileStatus, tileBody] = send("GET", "/v1/sections/" + j["sid"].get<std::string>() + "/tiles/0/0/0.png");
    EXPECT_EQ(tileStatus, 200) << tileBody;
}

}  // namespace
}  // namespace geoslice::test
