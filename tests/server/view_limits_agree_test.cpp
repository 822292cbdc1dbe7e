// One set of image and camera limits (view/view_limits.hpp, issue 14 item 1): what HTTP
// refuses, the CLI's render, section and query refuse too, with the same reason; only the
// name differs (HTTP "parameter 'fov'", the CLI "--fov"). The CLI took any field of view in
// (0, 179) degrees while HTTP took 1..170. Values at the limits are accepted by both.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/common/run_command.hpp"
#include "tests/server/query_models_server.hpp"
#include "view/view_limits.hpp"

namespace geoslice::server {
namespace {

// tests/data/queries/models/layers.obj: boxes in EPSG:4523 around (35500500, 3390300, 50).
const std::string kPlane = "0,1,0,-3390310";
const std::string kEye = "35500500,3389300,300", kTarget = "35500500,3390300,50";

struct Limit {
    std::string what;      // for messages
    std::string http;      // the view's query string
    std::string httpName;  // how HTTP names the parameter
    std::string cli;       // flags of `geoslice render` / `section` (the model and --out are added)
    std::string cliName;   // how the CLI names the flag
    std::string reason;    // a piece of the reason both must give
};

// `geoslice query MODEL --pixel 0,0` with each HTTP parameter of `query` as a '--name=value' flag.
std::string queryArgs(const std::string& model, const std::string& query) {
    std::string args = "query '" + model + "' --pixel 0,0";
    for (std::size_t at = 0; at < query.size();) {
        const std::size_t amp = std::min(query.find('&', at), query.size());
        args += " '--" + query.substr(at, amp - at) + "'";
        at = amp + 1;
    }
    return args;
}

class ViewLimitsAgree : public QueryModelsServer {
protected:
    // The HTTP problem's detail for GET section.png?<query> (400 expected).
    static std::string httpRefusal(const std::string& query) {
        auto r = get("/v1/models/layers/section.png?" + query);
        EXPECT_TRUE(r) << query;
        if (!r) return "";
        EXPECT_EQ(r->status, 400) << query << "\n" << r->body;
        const auto j = nlohmann::json::parse(r->body, nullptr, false);
        return j.is_object() ? j.value("detail", "") : "";
    }
    // stdout + stderr of `geoslice <args>`, which must exit non-zero.
    static std::string cliRefusal(const std::string& args) {
        const auto r = test::runCommand(std::string(GEOSLICE_BINARY) + " " + args + " 2>&1");
        EXPECT_NE(r.exitCode, 0) << "geoslice " << args << " accepted it:\n" << r.out;
        return r.out;
    }
    // HTTP's detail minus its parameter name: the reason the CLI must give after its own name.
    static void expectSameReason(const Limit& l, const std::string& detail, const std::string& cliOut,
                                 const std::string& command) {
        const auto at = detail.find(l.httpName);
        ASSERT_NE(at, std::string::npos) << l.what << ": HTTP detail '" << detail << "' does not name " << l.httpName;
        const std::string reason = detail.substr(at + l.httpName.size());
        EXPECT_NE(reason.find(l.reason), std::string::npos) << l.what << ": '" << detail << "'";
        EXPECT_NE(cliOut.find(l.cliName + reason), std::string::npos)
            << l.what << ": HTTP says '" << detail << "', geoslice " << command << " says '" << cliOut << "'";
    }
};

const std::vector<Limit>& limits() {
    static const std::vector<Limit> all = [] {
        const std::string persp = "plane=" + kPlane + "&view=perspective&eye=" + kEye + "&target=" + kTarget;
        const std::string cam = "--plane " + kPlane + " --eye " + kEye + " --target " + kTarget;
        const std::string fov = "1.." + limitNumber(kMaxFovDeg) + " degrees";
        const std::string vx = limitNumber(kMinExaggeration) + ".." + limitNumber(kMaxExaggeration);
        return std::vector<Limit>{
            {"fov above 170", persp + "&fov=175", "parameter 'fov'", cam + " --fov 175", "--fov",
             "175 is outside " + fov},
            {"fov 178 (the CLI's old range)", persp + "&fov=178", "parameter 'fov'", cam + " --fov 178", "--fov",
             "178 is outside " + fov},
            {"fov below 1", persp + "&fov=0.5", "parameter 'fov'", cam + " --fov 0.5", "--fov",
             "0.5 is outside " + fov},
            {"eye on the target", "plane=" + kPlane + "&view=perspective&eye=" + kTarget + "&target=" + kTarget,
             "parameters 'eye' and 'target'", "--plane " + kPlane + " --eye " + kTarget + " --target " + kTarget,
             "--eye and --target", "coincide"},
            {"width 0", "plane=" + kPlane + "&size=0x10", "parameter 'size'", "--plane " + kPlane + " --size 0x10",
             "--size", "width outside 1..8192"},
            {"height above 8192", "plane=" + kPlane + "&size=100x8193", "parameter 'size'",
             "--plane " + kPlane + " --size 100x8193", "--size", "height outside 1..8192"},
        };
    }();
    return all;
}

TEST_F(ViewLimitsAgree, RenderRefusesWhatHttpRefusesWithTheSameReason) {
    const std::string model = test::queryCaseDir() + "/models/layers.obj";
    const std::string out = (freshTempDir("view_limits") / "x.png").string();
    for (const Limit& l : limits()) {
        const std::string args = "render '" + model + "' " + l.cli + " --out '" + out + "'";
        expectSameReason(l, httpRefusal(l.http), cliRefusal(args), "render");
    }
}

TEST_F(ViewLimitsAgree, SectionAndQueryRefuseWhatHttpRefusesWithTheSameReason) {
    const std::string model = test::queryCaseDir() + "/models/layers.obj";
    const std::string out = (freshTempDir("view_limits") / "x.png").string();
    for (const Limit& l : limits()) {
        if (l.cliName != "--size") continue;  // `section` draws profiles: no camera
        expectSameReason(l, httpRefusal(l.http),
                         cliRefusal("section '" + model + "' " + l.cli + " --out '" + out + "'"), "section");
    }
    // Exaggeration: `section --vx` and `render --exaggeration` against HTTP vx=.
    for (const char* k : {"200", "0.05"}) {
        const std::string reason = std::string(k) + " is outside 0.1..100";
        const Limit section{"vx " + std::string(k),  "plane=" + kPlane + "&vx=" + k,
                            "parameter 'vx'",        "",
                            "--exaggeration (--vx)", reason};
        expectSameReason(
            section, httpRefusal(section.http),
            cliRefusal("section '" + model + "' --plane " + kPlane + " --vx " + k + " --out '" + out + "'"), "section");
        const Limit render{"vx " + std::string(k), section.http, "parameter 'vx'", "", "--exaggeration", reason};
        expectSameReason(
            render, httpRefusal(render.http),
            cliRefusal("render '" + model + "' --plane " + kPlane + " --exaggeration " + k + " --out '" + out + "'"),
            "render");
    }
    // `geoslice query` reads the view with HTTP's own parser: the same message, names and all.
    for (const Limit& l : limits()) {
        const std::string detail = httpRefusal(l.http);
        const std::string cliOut = cliRefusal(queryArgs(model, l.http));
        EXPECT_NE(cliOut.find(detail), std::string::npos) << l.what << ": HTTP '" << detail << "', query '" << cliOut;
    }
}

// The limits themselves are accepted by both: fov 1 and 170, vx 0.1 and 100, 8192 pixels a side.
TEST_F(ViewLimitsAgree, ValuesAtTheLimitsAreAccepted) {
    const std::string model = test::queryCaseDir() + "/models/layers.obj";
    const std::string persp = "plane=" + kPlane + "&view=perspective&eye=" + kEye + "&target=" + kTarget;
    for (const std::string& q : {persp + "&fov=1", persp + "&fov=170", "plane=" + kPlane + "&vx=0.1",
                                 "plane=" + kPlane + "&vx=100", "plane=" + kPlane + "&size=8192x16"}) {
        getJson("/v1/models/layers/query?" + q + "&px=0&py=0");
        const std::string args = queryArgs(model, q);
        const auto r = test::runGeoslice(args);
        EXPECT_EQ(r.exitCode, 0) << "geoslice " << args;
    }
}

}  // namespace
}  // namespace geoslice::server
