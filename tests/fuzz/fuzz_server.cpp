// libFuzzer target for the whole server in process: the bytes are what one client sends on
// one connection (one or more pipelined requests, any bytes at all). They go through the
// real path, the listening socket, the transport (Beast's parser, the framing checks), the
// router and the handlers, to the answer bytes. The server runs in this process on a
// loopback port with a small demo model and no GL, so anything that ends a handler thread
// ends the fuzzer and is found. Invariants checked on every input:
//   - an answer (or a closed connection) within 20 s: no hang;
//   - no 500: bad input is a 4xx or 501 naming the problem, never an internal error;
//   - every problem+json body in the answer is valid JSON (so UTF-8);
//   - the server still answers /healthz after the input.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "server/config.hpp"
#include "server/http_server.hpp"

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
        c.headerTimeoutMs = 2000;
        c.bodyTimeoutMs = 2000;
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

// Sends `bytes`, half-closes, reads until the server closes; false on a 20 s timeout.
bool exchange(int port, std::string_view bytes, std::string& reply) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) std::abort();
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) std::abort();  // the server is gone
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;  // the server closed early (it refused the request): fine
        sent += std::size_t(n);
    }
    shutdown(fd, SHUT_WR);
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    char buf[1 << 14];
    bool done = false;
    while (!done) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now()).count();
        if (left <= 0) break;
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, int(left)) <= 0) break;
        const ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n <= 0) {
            done = true;
        } else if (reply.size() < (8u << 20)) {
            reply.append(buf, std::size_t(n));
        }
    }
    close(fd);
    return done;
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
        if (head.find("application/problem+json") != std::string_view::npos &&
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    SectionServer& s = server();
    std::string reply;
    if (!exchange(s.port(), std::string_view(reinterpret_cast<const char*>(data), size), reply)) {
        std::fprintf(stderr, "fuzz_server: no end to the answer within 20 s\n");
        __builtin_trap();
    }
    checkAnswers(reply);
    std::string health;
    if (!exchange(s.port(), "GET /healthz HTTP/1.1\r\nHost: f\r\nConnection: close\r\n\r\n", health) ||
        health.rfind("HTTP/1.1 200", 0) != 0) {
        std::fprintf(stderr, "fuzz_server: /healthz failed after the input\n");
        __builtin_trap();
    }
    return 0;
}
