// server/http_transport: the target and Accept-Encoding helpers, gzip, and the protocol
// details a route never sees (HEAD, Expect: 100-continue, early 413, chunked bodies,
// HTTP/1.0, handler exceptions, the cancel token), on a transport with a test handler.
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zlib.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "server/http_transport.hpp"

namespace geoslice::server {
namespace {

using Clock = std::chrono::steady_clock;

TEST(HttpTarget, PathAndQueryArePercentDecoded) {
    std::string path;
    std::multimap<std::string, std::string> params;
    parseTarget("/a%20b/c%2Fd?x=1&y=a+b&z=%23ff&flag&=v&&k=%zz&x=2", path, params);
    EXPECT_EQ(path, "/a b/c/d");
    const std::multimap<std::string, std::string> want = {{"x", "1"}, {"y", "a b"}, {"z", "#ff"}, {"flag", ""},
                                                          {"", "v"},  {"k", "%zz"}, {"x", "2"}};
    EXPECT_EQ(params, want);
    parseTarget("http://example.org:8080/healthz?a=1#frag", path, params);
    EXPECT_EQ(path, "/healthz");
    EXPECT_EQ(params.size(), 1u);
    parseTarget("/p+q%2", path, params);  // '+' is a space only in the query; a cut escape stays
    EXPECT_EQ(path, "/p+q%2");
    EXPECT_TRUE(params.empty());
}

TEST(HttpTarget, AcceptEncodingAndCompressibleTypes) {
    EXPECT_TRUE(acceptsGzip("gzip"));
    EXPECT_TRUE(acceptsGzip("br, gzip;q=0.5"));
    EXPECT_TRUE(acceptsGzip("GZIP"));
    EXPECT_TRUE(acceptsGzip("*"));
    EXPECT_FALSE(acceptsGzip("gzip;q=0"));
    EXPECT_FALSE(acceptsGzip("identity, br"));
    EXPECT_FALSE(acceptsGzip(""));
    EXPECT_TRUE(acceptsGzip(" deflate ;q=1 , gzip ; level=1 ; Q=0.1"));
    EXPECT_TRUE(acceptsGzip(",1,0,*;q;Q"));  // malformed parameters are ignored (found by fuzz_http)
    EXPECT_TRUE(compressibleType("application/json"));
    EXPECT_TRUE(compressibleType("application/problem+json"));
    EXPECT_TRUE(compressibleType("text/html; charset=utf-8"));
    EXPECT_TRUE(compressibleType("image/svg+xml"));
    EXPECT_FALSE(compressibleType("image/png"));
    EXPECT_FALSE(compressibleType("text/event-stream"));
}

TEST(HttpTarget, GzipRoundTrip) {
    std::string text;
    for (int i = 0; i < 2000; ++i) text += "{\"record\":" + std::to_string(i % 17) + "},";
    const std::string z = gzipCompress(text);
    ASSERT_GE(z.size(), 18u);
    EXPECT_EQ(std::uint8_t(z[0]), 0x1f);  // gzip magic (RFC 1952)
    EXPECT_EQ(std::uint8_t(z[1]), 0x8b);
    EXPECT_LT(z.size(), text.size() / 4);
    z_stream s{};
    ASSERT_EQ(inflateInit2(&s, 15 + 16), Z_OK);
    std::string back(text.size() + 16, '\0');
    s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(z.data()));
    s.avail_in = uInt(z.size());
    s.next_out = reinterpret_cast<Bytef*>(back.data());
    s.avail_out = uInt(back.size());
    EXPECT_EQ(inflate(&s, Z_FINISH), Z_STREAM_END);
    back.resize(s.total_out);
    inflateEnd(&s);
    EXPECT_EQ(back, text);
}

// A transport on a free loopback port with a handler that echoes or misbehaves on demand.
class Transport : public ::testing::Test {
protected:
    void SetUp() override {
        TransportConfig c;
        c.host = "127.0.0.1";
        c.port = 0;
        c.handlerThreads = 4;
        c.ioThreads = 2;  // connections on strands across threads (TSan builds check the hand-offs)
        c.maxBodyBytes = 1000;
        transport_ = std::make_unique<HttpTransport>(
            c,
            [this](HttpRequest& req, HttpResponse& res) {
                if (req.path == "/throw") throw std::runtime_error("boom");
                if (req.path == "/wait") {  // until the client goes away (at most 5 s)
                    const auto t0 = Clock::now();
                    while (!req.isCancelled() && Clock::now() - t0 < std::chrono::seconds(5))
                        std::this_thread::sleep_for(std::chrono::milliseconds(5));
                    sawCancel_ = req.isCancelled();
                    res.set_content("late", "text/plain");
                    return;
                }
                if (req.path == "/sleep") std::this_thread::sleep_for(std::chrono::milliseconds(20));
                res.set_content(req.method + " " + req.path + " [" + req.body + "]", "text/plain");
            },
            [](HttpResponse& res, int status, const std::string& detail, const std::string&) {
                res.status = status;
                res.set_content(detail, "text/plain");
            });
        auto port = transport_->listen();
        ASSERT_TRUE(port) << port.error().message;
        port_ = port.value();
        transport_->start();
    }
    void TearDown() override { transport_->stop(1000); }

    int connectFd() const {
        const int fd = socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(std::uint16_t(port_));
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
        return fd;
    }
    static void sendText(int fd, const std::string& s) {
        ASSERT_EQ(send(fd, s.data(), s.size(), MSG_NOSIGNAL), ssize_t(s.size()));
    }
    // Reads until `needle` has arrived, the peer closes, or `ms` pass.
    static std::string readUntil(int fd, const std::string& needle, int ms = 5000) {
        std::string got;
        const auto until = Clock::now() + std::chrono::milliseconds(ms);
        while (got.find(needle) == std::string::npos && Clock::now() < until) {
            pollfd p{fd, POLLIN, 0};
            if (poll(&p, 1, 50) <= 0) continue;
            char buf[4096];
            const ssize_t n = recv(fd, buf, sizeof buf, 0);
            if (n <= 0) break;
            got.append(buf, std::size_t(n));
        }
        return got;
    }
    static bool closedByPeer(int fd, int ms) {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, ms) <= 0) return false;
        char c;
        return recv(fd, &c, 1, 0) == 0;
    }

    std::unique_ptr<HttpTransport> transport_;
    int port_ = 0;
    std::atomic<bool> sawCancel_{false};
};

TEST_F(Transport, HeadHasTheLengthButNoBody) {
    const int fd = connectFd();
    sendText(fd, "HEAD /x HTTP/1.1\r\nHost: h\r\n\r\nGET /y HTTP/1.1\r\nHost: h\r\n\r\n");
    const std::string got = readUntil(fd, "GET /y []");
    // "GET /x []" is 9 bytes: announced for HEAD, not sent; the next answer follows at once.
    EXPECT_NE(got.find("Content-Length: 9\r\n"), std::string::npos) << got;
    EXPECT_EQ(got.find("GET /x"), std::string::npos) << got;
    EXPECT_NE(got.find("GET /y []"), std::string::npos) << got;
    close(fd);
}

TEST_F(Transport, ExpectContinueThenBody) {
    const int fd = connectFd();
    sendText(fd, "POST /p HTTP/1.1\r\nHost: h\r\nContent-Length: 5\r\nExpect: 100-continue\r\n\r\n");
    EXPECT_NE(readUntil(fd, "100 Continue").find("HTTP/1.1 100 Continue"), std::string::npos);
    sendText(fd, "hello");
    EXPECT_NE(readUntil(fd, "[hello]").find("POST /p [hello]"), std::string::npos);
    close(fd);
}

TEST_F(Transport, ChunkedBody) {
    const int fd = connectFd();
    sendText(fd, "POST /c HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n3\r\nabc\r\n2\r\nde\r\n0\r\n\r\n");
    EXPECT_NE(readUntil(fd, "[abcde]").find("POST /c [abcde]"), std::string::npos);
    close(fd);
}

// A Content-Length over the limit is refused as soon as the header is read: no body sent,
// no timeout waited.
TEST_F(Transport, TooLargeBodyRefusedFromItsContentLength) {
    const int fd = connectFd();
    const auto t0 = Clock::now();
    sendText(fd, "POST /big HTTP/1.1\r\nHost: h\r\nContent-Length: 1000000\r\n\r\n");
    const std::string got = readUntil(fd, "limit");
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    EXPECT_EQ(got.rfind("HTTP/1.1 413", 0), 0u) << got;
    EXPECT_NE(got.find("Connection: close"), std::string::npos) << got;
    EXPECT_LT(ms, 1000.0);  // the previous layer waited for its 10 s read timeout
    close(fd);
}

TEST_F(Transport, MalformedRequestIs400AndClosed) {
    const int fd = connectFd();
    sendText(fd, "GET /x HTTP/1.1\r\nHost h\r\n\r\n");
    const std::string got = readUntil(fd, "malformed");
    EXPECT_EQ(got.rfind("HTTP/1.1 400", 0), 0u) << got;
    EXPECT_TRUE(closedByPeer(fd, 3000));
    close(fd);
}

TEST_F(Transport, Http10ClosesAfterTheAnswer) {
    const int fd = connectFd();
    sendText(fd, "GET /old HTTP/1.0\r\n\r\n");
    const std::string got = readUntil(fd, "GET /old []");
    EXPECT_EQ(got.rfind("HTTP/1.0 200", 0), 0u) << got;
    EXPECT_TRUE(closedByPeer(fd, 3000));
    close(fd);
}

TEST_F(Transport, HandlerExceptionIs500) {
    const int fd = connectFd();
    sendText(fd, "GET /throw HTTP/1.1\r\nHost: h\r\n\r\n");
    // The transport's last catch answers a prepared 500 (server/http_connection.hpp): nothing
    // of the exception is echoed (the router, not the transport, names what a route threw).
    const std::string got = readUntil(fd, "\"code\":\"internal\"}");
    EXPECT_EQ(got.rfind("HTTP/1.1 500", 0), 0u) << got;
    EXPECT_NE(got.find("\"detail\":\"internal error\""), std::string::npos) << got;
    EXPECT_EQ(got.find("boom"), std::string::npos) << got;
    close(fd);
}

// The cancel token trips when the client closes while its request is being handled.
TEST_F(Transport, CancelTokenTripsWhenTheClientLeaves) {
    const int fd = connectFd();
    sendText(fd, "GET /wait HTTP/1.1\r\nHost: h\r\n\r\n");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto t0 = Clock::now();
    close(fd);
    while (!sawCancel_ && Clock::now() - t0 < std::chrono::seconds(5))
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    EXPECT_TRUE(sawCancel_);
    EXPECT_LT(ms, 1000.0);
    EXPECT_GE(transport_->stats().cancelled, 1u);
}

// Clients that pipeline and then leave at random points (before, during or after their
// answers), from 8 threads at once: the transport keeps answering, and every connection is
// closed and forgotten afterwards.
TEST_F(Transport, ManyClientsLeavingAtRandomPoints) {
    std::atomic<int> complete{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 8; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 40; ++i) {
                const int fd = connectFd();
                const std::string req = "GET /sleep HTTP/1.1\r\nHost: h\r\n\r\nGET /e HTTP/1.1\r\nHost: h\r\n\r\n";
                if (send(fd, req.data(), req.size(), MSG_NOSIGNAL) != ssize_t(req.size())) {
                    close(fd);
                    continue;
                }
                switch ((t + i) % 3) {
                    case 0:  // leaves at once, mid-request
                        break;
                    case 1:  // leaves after the first answer
                        readUntil(fd, "GET /sleep []");
                        break;
                    default:  // takes both answers
                        complete += readUntil(fd, "GET /e []").find("GET /e []") != std::string::npos;
                }
                close(fd);
            }
        });
    for (auto& th : threads) th.join();
    EXPECT_GE(complete.load(), 100);  // 8 x 40 / 3 clients read both answers
    const auto t0 = Clock::now();
    while (transport_->stats().open > 0 && Clock::now() - t0 < std::chrono::seconds(5))
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_EQ(transport_->stats().open, 0u);
    const int fd = connectFd();
    sendText(fd, "GET /after HTTP/1.1\r\nHost: h\r\n\r\n");
    EXPECT_NE(readUntil(fd, "GET /after []").find("GET /after []"), std::string::npos);
    close(fd);
}

}  // namespace
}  // namespace geoslice::server
