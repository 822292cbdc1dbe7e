// The real server (a child process) against the requests an outside campaign used to end
// it or smuggle past it: bytes that are not UTF-8 in every part of a request (they ended the
// process: the problem document could not be written), Transfer-Encoding and Host framing
// (RFC 9112 3.2, 5.2, 6.1), wrong methods and OPTIONS. Every answer must be a 4xx/501
// problem whose body is JSON (and so UTF-8), and the server must still be running after.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/raw_http.hpp"
#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

using nlohmann::json;

class HostileProtocol : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        server_ = ServeProcess::start({"--gl", "none", "--demo-triangles", "4000", "--workers", "1"}).release();
        ASSERT_NE(server_, nullptr);
        ASSERT_TRUE(server_->waitReady()) << server_->log();
    }
    static void TearDownTestSuite() {
        delete server_;
        server_ = nullptr;
    }
    static RawExchange send(const std::string& bytes, bool halfClose = false) {
        return rawExchange(server_->port(), bytes, 5000, halfClose);
    }
    static std::string get(const std::string& target, const std::string& extraHeaders = "") {
        return "GET " + target + " HTTP/1.1\r\nHost: t\r\n" + extraHeaders + "Connection: close\r\n\r\n";
    }
    // One answer with `status`, a problem+json body that parses as JSON (nlohmann's parser
    // refuses text that is not UTF-8) and whose detail holds `detail`.
    static void expectProblem(const RawExchange& x, int status, const std::string& detail, const std::string& what) {
        ASSERT_TRUE(x.connected) << what;
        const auto codes = statusCodes(x.reply);
        ASSERT_FALSE(codes.empty()) << what << ": no answer; server log:\n" << server_->log();
        EXPECT_EQ(codes[0], status) << what << "\n" << x.reply;
        EXPECT_NE(x.reply.find("application/problem+json"), std::string::npos) << what;
        const std::string body = firstBody(x.reply);
        json j = json::parse(body, nullptr, false);
        ASSERT_FALSE(j.is_discarded()) << what << ": the body is not JSON: " << body;
        EXPECT_EQ(j.value("status", 0), status) << what;
        EXPECT_NE(j.value("detail", std::string()).find(detail), std::string::npos)
            << what << ": detail " << j.value("detail", std::string());
        EXPECT_TRUE(server_->running()) << what << ": the server ended; log:\n" << server_->log();
    }
    static ServeProcess* server_;
};
ServeProcess* HostileProtocol::server_ = nullptr;

TEST_F(HostileProtocol, PathsThatAreNotUtf8Are400AndNameTheProblem) {
    // The twelve requests that ended the process, as an outside campaign sent them.
    const std::vector<std::string> targets = {"/%ff",
                                              "/web/%ff",
                                              "/v1/models/%ff",
                                              "/v1/models/%c3%28",
                                              "/v1/models/%c0%af",
                                              "/v1/models/%ed%a0%80",
                                              "/v1/sections/%ff",
                                              "/v1/sections/%ff/tiles/0/0/0.png",
                                              "/v1/models/demo/section.%ff",
                                              "/..%c0%af..%c0%afetc/passwd",
                                              "/%f4%90%80%80",
                                              "/a%00b%ff"};
    for (const auto& t : targets) expectProblem(send(get(t)), 400, "not valid UTF-8", t);
    expectProblem(send("FOO /%ff HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n"), 400, "not valid UTF-8", "FOO");
    expectProblem(send(get("/v1/models/\xff")), 400, "not valid UTF-8", "a raw 0xff in the request line");
    // The bytes are shown escaped.
    const auto x = send(get("/v1/models/%ff"));
    EXPECT_NE(firstBody(x.reply).find("\\\\xFF"), std::string::npos) << x.reply;
}

TEST_F(HostileProtocol, ParametersAndHeadersThatAreNotUtf8Are400NamingThem) {
    const std::string section = "/v1/models/demo/section.png?";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {section + "plane=%ff", "parameter 'plane'"},
        {section + "plane=0,1,0,-3388846&size=%ff", "parameter 'size'"},
        {section + "%ff=1", "query parameter name"},
        {"/v1/models/demo/query?plane=0,1,0,-3388846&px=%ff&py=1", "parameter 'px'"},
        {"/v1/models/demo/section.pdf?plane=0,1,0,-3388846&date=%ff", "parameter 'date'"},
        {"/v1/models/demo/section.pdf?plane=0,1,0,-3388846&paper=%c0%af", "parameter 'paper'"},
        {"/v1/models/demo?x=%ed%a0%80", "parameter 'x'"},
    };
    for (const auto& [target, named] : cases) expectProblem(send(get(target)), 400, named, target);
    expectProblem(send("POST /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\nContent-Type: \xff\r\n"
                       "Content-Length: 2\r\nConnection: close\r\n\r\n{}"),
                  400, "header 'Content-Type'", "Content-Type 0xff");
    expectProblem(send(get("/v1/models/demo", "If-None-Match: \"\xc0\xaf\"\r\n")), 400, "header 'If-None-Match'",
                  "If-None-Match");
    // A POST body that is not UTF-8 is refused by the JSON parser, naming the body.
    const std::string body = "{\"plane\": \"0,1,0,\xff\"}";
    const auto x = send(
        "POST /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
        "Content-Length: " +
        std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body);
    const auto codes = statusCodes(x.reply);
    ASSERT_FALSE(codes.empty());
    EXPECT_EQ(codes[0], 400) << x.reply;
    EXPECT_FALSE(json::parse(firstBody(x.reply), nullptr, false).is_discarded()) << x.reply;
    EXPECT_TRUE(server_->running());
}

TEST_F(HostileProtocol, TransferEncodingOtherThanALoneChunkedIs501AndNothingIsSmuggled) {
    // Each probe hides a second request in what the server would read as a body; it must not
    // be answered (only one status line comes back) and the connection must close.
    const std::string hidden = "GET /v1/models/demo HTTP/1.1\r\nHost: t\r\n\r\n";
    for (const std::string te : {"gzip", "identity", "xchunked", "chunked, identity", "gzip, chunked, gzip"}) {
        const std::string probe =
            "POST /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\nContent-Type: "
            "application/json\r\nTransfer-Encoding: " +
            te + "\r\n\r\n" + hidden;
        const auto x = send(probe);
        expectProblem(x, 501, "Transfer-Encoding", te);
        EXPECT_EQ(statusCodes(x.reply).size(), 1u) << te << ": a smuggled request was answered\n" << x.reply;
        EXPECT_TRUE(x.closed) << te << ": the connection stayed open";
    }
    // Two Transfer-Encoding fields, or one beside a Content-Length.
    for (const std::string fields :
         {"Transfer-Encoding: chunked\r\nTransfer-Encoding: chunked\r\n",
          "Transfer-Encoding: gzip\r\nContent-Length: 5\r\n", "Content-Length: 5\r\nTransfer-Encoding: chunked\r\n"}) {
        const auto x =
            send("POST /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\n" + fields + "\r\n0\r\n\r\n" + hidden);
        const auto codes = statusCodes(x.reply);
        ASSERT_EQ(codes.size(), 1u) << fields << "\n" << x.reply;
        EXPECT_TRUE(codes[0] == 400 || codes[0] == 501) << fields << "\n" << x.reply;
        EXPECT_TRUE(x.closed) << fields;
    }
    // chunked on HTTP/1.0: refused and closed.
    const auto old =
        send("POST /v1/models/demo/sections HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n" + hidden);
    expectProblem(old, 400, "HTTP/1.0", "chunked on HTTP/1.0");
    EXPECT_EQ(statusCodes(old.reply).size(), 1u) << old.reply;
    EXPECT_TRUE(old.closed);
    // A lone chunked still works.
    const std::string body = "{\"plane\": \"0,1,0,-3388846\"}";
    char size[16];
    std::snprintf(size, sizeof size, "%zx", body.size());
    const auto ok = send(
        "POST /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
        "Transfer-Encoding: chunked\r\nConnection: close\r\n\r\n" +
        std::string(size) + "\r\n" + body + "\r\n0\r\n\r\n");
    ASSERT_FALSE(statusCodes(ok.reply).empty()) << ok.reply;
    EXPECT_EQ(statusCodes(ok.reply)[0], 201) << ok.reply;
}

TEST_F(HostileProtocol, HostRulesAndFoldedHeadersAre400) {
    expectProblem(send("GET /healthz HTTP/1.1\r\nConnection: close\r\n\r\n"), 400, "Host", "no Host");
    expectProblem(send("GET /healthz HTTP/1.1\r\nHost: a\r\nHost: b\r\nConnection: close\r\n\r\n"), 400, "Host",
                  "two Hosts");
    expectProblem(send("GET /healthz HTTP/1.1\r\nHost: a\r\nX-A: b\r\n c\r\nConnection: close\r\n\r\n"), 400,
                  "obs-fold", "a folded header");
    expectProblem(send("GET /healthz HTTP/1.1\r\nHost: a\r\n\tX-A: b\r\n\r\n"), 400, "obs-fold", "a tab-folded header");
    // HTTP/1.0 needs no Host.
    const auto x = send("GET /healthz HTTP/1.0\r\n\r\n");
    ASSERT_FALSE(statusCodes(x.reply).empty()) << x.reply;
    EXPECT_EQ(statusCodes(x.reply)[0], 200) << x.reply;
}

TEST_F(HostileProtocol, WrongMethodIs405WithAllowAndUnknownOptionsIs404) {
    const auto x = send("POST /v1/models/demo HTTP/1.1\r\nHost: t\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
    expectProblem(x, 405, "not allowed", "POST on a GET route");
    EXPECT_NE(x.reply.find("Allow: GET, HEAD, OPTIONS"), std::string::npos) << x.reply;
    const auto del = send("DELETE /v1/models/demo/sections HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n");
    expectProblem(del, 405, "not allowed", "DELETE on a POST route");
    EXPECT_NE(del.reply.find("Allow: POST, OPTIONS"), std::string::npos) << del.reply;
    expectProblem(send("OPTIONS /nowhere HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n"), 404, "no route",
                  "OPTIONS /nowhere");
    const auto opt = send("OPTIONS /v1/models/demo/query HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n");
    ASSERT_FALSE(statusCodes(opt.reply).empty());
    EXPECT_EQ(statusCodes(opt.reply)[0], 204) << opt.reply;
    EXPECT_NE(opt.reply.find("Allow: GET, HEAD, POST, OPTIONS"), std::string::npos) << opt.reply;
}

}  // namespace
}  // namespace geoslice::test
