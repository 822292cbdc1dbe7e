// libFuzzer target for the whole server in process: the bytes are what one client sends on
// one connection (one or more pipelined requests, any bytes at all). They go through the
// real path, the listening socket, the transport (Beast's parser, the framing checks), the
// router and the handlers, to the answer bytes. The server runs in this process on a
// loopback port with a small demo model and no GL, so anything that ends a handler thread
// ends the fuzzer and is found. Invariants checked on every input:
//   - an answer (or a closed connection) within 60 s: no hang (generous: renders run under ASan on a loaded machine);
//   - no 500: bad input is a 4xx or 501 naming the problem, never an internal error;
//   - every problem+json body in the answer is valid JSON (so UTF-8);
//   - the server still answers /healthz after the input.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>

#include <unistd.h>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "server/config.hpp"
#include "server/http_server.hpp"
#include "tests/common/raw_http.hpp"

namespace {

using geoslice::server::SectionServer;
using geoslice::server::ServerConfig;

SectionServer& server() {
    static SectionServer* s = [] {
        ServerConfig c;
        c.host = "127.0.0.1";
        c.port = 0;
        c.gl = "none";
        c.workers = 1;
        c.httpThreads = 4;
        c.demoTriangles = 4000;
        c.logLevel = "off";
        c.headerTimeoutMs = 3000;  // from accept: above any scheduling delay under ASan on a loaded machine
        c.bodyTimeoutMs = 300;
        c.keepAliveMs = 300;
        c.deadlineMs = 15000;
        c.cacheMiB = 64;
        spdlog::set_level(spdlog::level::off);
        auto* srv = new SectionServer(c);  // lives for the process: the fuzzer never returns
        auto port = srv->start();
        if (!port) {
            std::fprintf(stderr, "fuzz_server: %s\n", port.error().message.c_str());
            std::abort();
        }
        srv->waitUntilLoaded();
        return srv;
    }();
    return *s;
}

constexpr std::string_view kSentinel = "GET /healthz HTTP/1.1\r\nHost: f\r\nConnection: close\r\n\r\n";

// Sends `bytes` and then a last request that asks the server to close (a client that
// half-closes is taken for gone and gets no answer, as with nginx), reads until the server
// closes (tests/common/raw_http.hpp); false on a 60 s timeout. Input that leaves a request
// unfinished swallows the last request and ends at the header or body deadline.
bool exchange(int port, std::string_view bytes, std::string& reply) {
    auto x = geoslice::test::rawExchange(port, std::string(bytes) + std::string(kSentinel), 60000);
    if (!x.connected) std::abort();  // the server is gone
    reply = std::move(x.reply);
    return x.closed;
}

// Every answer's status and, for problem+json, its body must be JSON.
void checkAnswers(std::string_view reply) {
    std::size_t at = 0;
    while ((at = reply.find("HTTP/1.", at)) != std::string_view::npos) {
        const std::size_t headEnd = reply.find("\r\n\r\n", at);
        if (headEnd == std::string_view::npos || at + 12 > reply.size()) return;
        const std::string_view head = reply.substr(at, headEnd - at);
        if (head.substr(9, 3) == "500") {
            std::fprintf(stderr, "fuzz_server: a 500 answer:\n%.*s\n", int(reply.size() > 2000 ? 2000 : reply.size()),
                         reply.data());
            __builtin_trap();
        }
        std::size_t length = 0;
        if (const auto cl = head.find("\r\nContent-Length: "); cl != std::string_view::npos)
            length = std::strtoul(std::string(head.substr(cl + 18, 20)).c_str(), nullptr, 10);
        const std::size_t bodyAt = headEnd + 4;
        // The answer to a HEAD request has the GET answer's Content-Length and no body: the
        // next status line follows at once.
        const bool noBody = reply.substr(bodyAt, 7) == "HTTP/1." || bodyAt == reply.size();
        if (noBody) length = 0;
        if (!noBody && head.find("application/problem+json") != std::string_view::npos &&
            head.find("Content-Encoding") == std::string_view::npos && bodyAt + length <= reply.size()) {
            const auto j = nlohmann::json::parse(reply.substr(bodyAt, length), nullptr, false);
            if (j.is_discarded()) {
                std::fprintf(stderr, "fuzz_server: a problem body that is not JSON\n");
                __builtin_trap();
            }
        }
        at = bodyAt + length;
    }
}

// On a stall, every thread's stack (gdb attached to this process) before the trap, so the
// report says where the server waits, not only that it did.
void dumpThreads() {
    const std::string cmd = "gdb -p " + std::to_string(getpid()) +
                            " -batch -nx -ex 'set pagination off' -ex 'thread apply all bt 25' 2>/dev/null 1>&2";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "fuzz_server: gdb could not print the threads\n");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    SectionServer& s = server();
    std::string reply;
    if (!exchange(s.port(), std::string_view(reinterpret_cast<const char*>(data), size), reply)) {
        std::fprintf(stderr, "fuzz_server: no end to the answer within 60 s; %zu bytes of it: %.300s\n", reply.size(),
                     reply.c_str());
        dumpThreads();
        __builtin_trap();
    }
    checkAnswers(reply);
    std::string health;
    const auto t0 = std::chrono::steady_clock::now();
    const bool closed = exchange(s.port(), "", health);
    if (!closed || health.rfind("HTTP/1.1 200", 0) != 0) {
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0);
        std::fprintf(stderr, "fuzz_server: /healthz failed after the input (%s after %lld ms): %.200s\n",
                     closed ? "closed" : "not closed", static_cast<long long>(ms.count()), health.c_str());
        // Transient or lasting? Ask again, and show the transport's counters.
        for (int i = 0; i < 3; ++i) {
            std::string again;
            const bool c = exchange(s.port(), "", again);
            std::fprintf(stderr, "fuzz_server: retry %d: %s: %.40s\n", i, c ? "closed" : "not closed", again.c_str());
        }
        auto m = geoslice::test::rawExchange(s.port(), "GET /metrics HTTP/1.1\r\nHost: f\r\nConnection: close\r\n\r\n",
                                             60000);
        for (std::size_t at = 0; (at = m.reply.find("\ngeoslice_connection", at)) != std::string::npos;) {
            const std::size_t end = m.reply.find('\n', ++at);
            std::fprintf(stderr, "  %s\n", m.reply.substr(at, end - at).c_str());
            at = end;
        }
        dumpThreads();
        __builtin_trap();
    }
    return 0;
}
