// The HTTP/1.1 transport of the section server: Boost.Beast over Boost.Asio (Debian's
// header-only Boost 1.74). It owns sockets, parsing, keep-alive and timeouts; the routes
// (server/router.hpp, server/routes/) see only HttpRequest -> HttpResponse (server/http_message.hpp).
//
//   acceptor (SOMAXCONN backlog, SO_REUSEADDR, SO_REUSEPORT only when asked)
//     -> I/O threads running one io_context: every socket operation is asynchronous, so an
//        idle or slow connection costs a file descriptor and a few KiB, never a thread or
//        a poll loop
//     -> per connection, requests are handled one after another (HTTP/1.1 pipelining:
//        answers go out in request order), each on the bounded handler pool, because
//        routes may block on render workers for up to their deadline
//
// Deadlines per connection, like nginx's: the whole request header must arrive within
// headerTimeoutMs of the connection's first byte (client_header_timeout; a total, not per
// read), the body within bodyTimeoutMs (client_body_timeout), an idle keep-alive
// connection is closed after keepAliveMs, and an answer must be taken by the client
// within sendTimeoutMs per 8 MiB (send_timeout). A body over maxBodyBytes is refused with
// 413 as soon as its Content-Length is read. At maxConnections, a new connection closes
// the connection that has waited longest for a request (idle or still sending its
// header); when every connection is busy with a request, the new one gets 503 and is
// closed.
//
// Threads: handler functions run on the handler pool, never on the I/O threads.
// start(), stop() and the counters may be called from any thread (not from a handler).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "model/result.hpp"
#include "server/http_message.hpp"

namespace geoslice::server {

struct TransportConfig {
    std::string host = "0.0.0.0";
    int port = 8080;         // 0 = any free port
    bool reusePort = false;  // SO_REUSEPORT: several processes share the port (off: refused)
    unsigned ioThreads = 1;
    unsigned handlerThreads = 128;       // requests handled at once (they may wait on renders)
    std::size_t maxConnections = 10000;  // lowered to fit RLIMIT_NOFILE
    std::size_t maxBodyBytes = 1 << 20;
    std::size_t maxHeaderBytes = 64 << 10;  // request line + headers
    int headerTimeoutMs = 10000;
    int bodyTimeoutMs = 10000;
    int keepAliveMs = 5000;
    int sendTimeoutMs = 10000;              // per 8 MiB of answer
    std::size_t keepAliveRequests = 10000;  // then the connection is closed after the answer
};

// Counters since start (read at any time).
struct TransportStats {
    std::uint64_t accepted = 0;
    std::uint64_t open = 0;
    std::uint64_t rejected = 0;  // 503 at the connection cap
    std::uint64_t evicted = 0;   // idle or header-phase connections closed for a new one
    std::uint64_t headerTimeouts = 0;
    std::uint64_t bodyTimeouts = 0;
    std::uint64_t sendTimeouts = 0;
    std::uint64_t badRequests = 0;  // malformed, too large: answered 400/413/431 and closed
    std::uint64_t cancelled = 0;    // requests whose client went away while being handled
};

class HttpTransport {
public:
    // Runs on a handler thread; fills the response. An exception becomes a 500.
    using Handler = std::function<void(HttpRequest&, HttpResponse&)>;
    // Builds the answer of a request the transport refuses by itself (400, 413, 431, 503):
    // status, detail, path. Runs on an I/O thread: keep it cheap.
    using ErrorBody =
        std::function<void(HttpResponse&, int status, const std::string& detail, const std::string& path)>;

    HttpTransport(TransportConfig config, Handler handler, ErrorBody errorBody);
    ~HttpTransport();  // stop(0)
    HttpTransport(const HttpTransport&) = delete;
    HttpTransport& operator=(const HttpTransport&) = delete;

    // Binds and listens; returns the bound port. Errors name the address and the cause
    // ("address already in use" when another process listens there).
    Result<int> listen();
    // Starts the I/O and handler threads (after listen()).
    void start();
    // Stops accepting, closes connections that wait for a request, lets answers being
    // handled or sent finish for at most graceMs, then closes every socket, trips every
    // cancel token and joins the threads. Handlers still running are waited for (the
    // routes bound them by the render deadline). Idempotent.
    void stop(int graceMs);

    // Requests queued for or running on the handler pool.
    std::size_t requestsInHandlers() const;
    TransportStats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace geoslice::server
