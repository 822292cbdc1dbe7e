// Pixel-query cases as data (tests/data/queries/<case>/, README there): every case through
// every path that answers a pixel query, each held to the case's expected.json by the one
// comparator (tests/common/query_case.hpp):
//   Http  GET /query per pixel (no image cached: the exact oracle at the pixel centre, or the
//         perspective ray); for a profile or tile view then the image (section.png, which
//         caches its ID buffer) and POST /query of all pixels, answered from that ID buffer;
//         for a tile case, first the grid of POST /sections must give the derived tile frame
//   Cli   `geoslice query MODEL --<param>=<value>... --pixel px,py ...` (the same answers
//         without a server)
// The server serves tests/data/queries/models/ (read only: no bake directory).
#include <gtest/gtest.h>

#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/common/query_case.hpp"
#include "tests/common/run_command.hpp"
#include "tests/server/query_models_server.hpp"

namespace geoslice::server {
namespace {

using test::QueryCase;

// Percent-encodes a query-string value (RFC 3986 unreserved characters and ',' stay).
std::string encodeValue(const std::string& v) {
    std::string out;
    for (unsigned char ch : v) {
        if (std::isalnum(ch) || ch == '-' || ch == '_' || ch == '.' || ch == '~' || ch == ',') {
            out += char(ch);
        } else {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", ch);
            out += buf;
        }
    }
    return out;
}

std::string queryString(const std::map<std::string, std::string>& params) {
    std::string q;
    for (const auto& [k, v] : params) q += (q.empty() ? "" : "&") + k + "=" + encodeValue(v);
    return q;
}

class QueryCases : public QueryModelsServer, public ::testing::WithParamInterface<std::string> {};

TEST_P(QueryCases, Http) {
    const QueryCase c = test::loadQueryCase(GetParam());
    const std::string model = c.request["model"];
    const auto view = c.view();
    const auto& pixels = c.request["pixels"];
    if (c.tile()) {
        // The server's tile grid must give the tile frame derived from the documented rule.
        nlohmann::json def = nlohmann::json::object();
        for (const auto& [k, v] : c.request["view"].items()) def[k] = v;
        auto r = client().Post(("/v1/models/" + model + "/sections").c_str(), def.dump(), "application/json");
        ASSERT_TRUE(r);
        ASSERT_EQ(r->status, 201) << r->body;
        const auto grid = nlohmann::json::parse(r->body)["grid"];
        const auto& t = c.request["tile"];
        const double s = grid["size0"].get<double>() / double(1 << t["z"].get<int>());
        const double k = grid["exaggeration"];
        const double u0 = grid["origin"]["u"].get<double>() + t["x"].get<double>() * s;
        const double v1 = grid["origin"]["v"].get<double>() - t["y"].get<double>() * s / k;
        const double got[4] = {u0, u0 + s, v1 - s / k, v1};
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(got[i], c.expected["tileFrame"][i].get<double>(), c.tolerance("section_m"))
                << c.name << ": tile frame [" << i << "] from the server's grid " << grid.dump() << " ("
                << c.reason("section_m") << ")";
    }
    const std::string q = queryString(view);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        const std::string path =
            "/v1/models/" + model + "/query?" + q + "&px=" + pixels[i][0].dump() + "&py=" + pixels[i][1].dump();
        const auto answer = getJson(path);
        test::expectAnswer(c, "GET /query", i, answer);
        EXPECT_EQ(answer.value("source", ""), "ray") << path;
    }
    if (c.perspective()) return;  // no GL in this server: the ray path is the answer
    auto image = get("/v1/models/" + model + "/section.png?" + q);
    ASSERT_TRUE(image);
    ASSERT_EQ(image->status, 200) << image->body;
    nlohmann::json body;
    body["view"] = view;
    body["pixels"] = pixels;
    auto r = client().Post(("/v1/models/" + model + "/query").c_str(), body.dump(), "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const auto results = nlohmann::json::parse(r->body, nullptr, false)["results"];
    ASSERT_EQ(results.size(), pixels.size()) << r->body;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        test::expectAnswer(c, "POST /query after the image", i, results[i]);
        EXPECT_EQ(results[i].value("source", ""), "id-buffer") << c.name << " pixel " << i;
    }
}

TEST_P(QueryCases, Cli) {
    const QueryCase c = test::loadQueryCase(GetParam());
    std::string args = "query '" + c.modelPath() + "'";
    for (const auto& [k, v] : c.view()) args += " '--" + k + "=" + v + "'";
    for (const auto& p : c.request["pixels"]) args += " --pixel " + p[0].dump() + "," + p[1].dump();
    const auto r = test::runGeoslice(args);
    ASSERT_EQ(r.exitCode, 0) << "geoslice " << args;
    const auto results = nlohmann::json::parse(r.out, nullptr, false)["results"];
    ASSERT_EQ(results.size(), c.request["pixels"].size()) << r.out;
    for (std::size_t i = 0; i < results.size(); ++i) test::expectAnswer(c, "geoslice query", i, results[i]);
}

INSTANTIATE_TEST_SUITE_P(Case, QueryCases, ::testing::ValuesIn(test::queryCases()),
                         [](const ::testing::TestParamInfo<std::string>& c) { return c.param; });

// The comparator can fail: answers known to be wrong by a little more than each tolerance,
// or in a field, are each reported (a comparator that passes everything would pass here).
TEST(QueryCaseComparator, ReportsEveryWrongField) {
    const QueryCase c = test::loadQueryCase("profile_ns_frame");
    const nlohmann::json& want = c.expected["pixels"][0];  // the orebody, with a block cell
    ASSERT_EQ(want["body"], "orebody");
    nlohmann::json right;
    right["hit"] = true;
    right["record"] = want["record"];
    right["body"] = want["body"];
    right["block"] = want["block"];
    right["world"] = {{"x", want["world"][0]}, {"y", want["world"][1]}, {"z", want["world"][2]}};
    right["world"]["geodetic"] = {{"lon", want["lonlat"][0]}, {"lat", want["lonlat"][1]}};
    right["section"] = want["section"];
    EXPECT_TRUE(test::compareAnswer(c, want, right).empty());
    auto wrong = [&](auto change) {
        nlohmann::json a = right;
        change(a);
        return test::compareAnswer(c, want, a).size();
    };
    const double worldTol = c.tolerance("world_m"), degTol = c.tolerance("lonlat_deg");
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["hit"] = false; }), 1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["record"]["lithology"] = "granite gneiss"; }), 1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["body"] = "sandstone"; }), 1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["block"]["cell"][2] = 0; }), 1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["block"]["properties"]["grade"] = 7.25; }), 1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["block"] = nullptr; }), 1u);
    EXPECT_EQ(wrong([&](nlohmann::json& a) { a["world"]["x"] = a["world"]["x"].get<double>() + 2 * worldTol; }), 1u);
    EXPECT_EQ(wrong([&](nlohmann::json& a) {
                  a["world"]["geodetic"]["lat"] = a["world"]["geodetic"]["lat"].get<double>() + 2 * degTol;
              }),
              1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["world"]["geodetic"] = nullptr; }), 2u);
    EXPECT_EQ(wrong([&](nlohmann::json& a) { a["section"]["v"] = a["section"]["v"].get<double>() - 2 * worldTol; }),
              1u);
    EXPECT_EQ(wrong([](nlohmann::json& a) { a["world"] = nullptr; }), 1u);
}

}  // namespace
}  // namespace geoslice::server
