// The transport's state (private to server/http_transport.cpp and server/http_connection.cpp):
// `Core`, what HttpTransport owns (config, counters, the registry of open connections, the
// io_context, acceptor and threads, the handler pool), and `Connection`, one socket's
// request/answer cycle: header and body reads with their deadlines, dispatch to the handler
// pool, the watch read that notices a client leaving, the write, keep-alive, lingering close.
// Every Connection member runs on its strand (its stream's executor) unless it says otherwise.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include "server/handler_pool.hpp"
#include "server/http_transport.hpp"

namespace geoslice::server::transport_detail {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

// What a connection is doing; Idle, Header and Body are "waiting for a request" (evictable).
enum class Phase : int { Idle, Header, Body, Handling, Writing, Closing, Closed };

inline std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

using Response = http::response<http::string_body>;

inline constexpr const char* kInternalErrorBody =
    R"({"type":"about:blank","title":"Internal Server Error","status":500,"detail":"internal error",)"
    R"("code":"internal"})";

struct Connection;
using Handler = HttpTransport::Handler;
using ErrorBody = HttpTransport::ErrorBody;

struct Core {
    TransportConfig config;
    Handler handler;
    ErrorBody errorBody;

    struct Counters {
        std::atomic<std::uint64_t> accepted{0}, rejected{0}, evicted{0}, headerTimeouts{0}, bodyTimeouts{0},
            sendTimeouts{0}, badRequests{0}, cancelled{0};
    } counters;
    std::atomic<bool> stopping{false};

    // Every open connection (declared before the io_context: connections destroyed with
    // it unregister themselves here).
    mutable std::mutex registryMutex;
    std::unordered_map<std::uint64_t, std::weak_ptr<Connection>> registry;  // guarded by registryMutex
    std::uint64_t nextId = 0;                                               // guarded by registryMutex

    net::io_context ioc;
    std::optional<net::executor_work_guard<net::io_context::executor_type>> work;
    net::strand<net::io_context::executor_type> acceptStrand{net::make_strand(ioc)};  // acceptor and its timer
    tcp::acceptor acceptor{acceptStrand};
    net::steady_timer acceptRetry{acceptStrand};
    std::vector<std::thread> ioThreads;
    std::optional<HandlerPool> pool;
    std::mutex stopMutex;
    bool started = false, stopped = false;  // guarded by stopMutex

    Core(TransportConfig c, Handler h, ErrorBody e)
        : config(std::move(c)),
          handler(std::move(h)),
          errorBody(std::move(e)),
          ioc(int(std::max(1u, config.ioThreads))) {}

    void accept();
    void onAccept(beast::error_code ec, tcp::socket socket);
    bool evictOne();
    void reject(tcp::socket& socket);
    template <class F>
    void forEachConnection(F f);
    std::size_t openConnections() const {
        std::lock_guard lock(registryMutex);
        return registry.size();
    }
};

struct Connection : std::enable_shared_from_this<Connection> {
    Core& owner;
    const std::uint64_t id;
    beast::tcp_stream stream;
    beast::flat_buffer buffer;
    std::optional<http::request_parser<http::string_body>> parser;
    std::atomic<int> phase{int(Phase::Header)};
    std::atomic<std::int64_t> phaseSince{nowNs()};
    Clock::time_point headerDeadline;
    std::shared_ptr<std::atomic<bool>> cancel;  // of the request being handled
    std::size_t served = 0;
    bool watching = false;  // a read that notices the peer leaving during a request
    // The answer is out: what to do once the watch read has ended (one read at a time).
    enum class AfterWatch { Nothing, NextRequest, LingerClose } afterWatch = AfterWatch::Nothing;
    bool peerGone = false;
    std::size_t lingered = 0;
    std::size_t headerScanned = 0;  // bytes of the buffer searched for the header's end

    // A request header (with what is pipelined behind it) must fit here.
    static constexpr std::size_t kReadChunk = 16 << 10;

    Connection(Core& o, std::uint64_t i, tcp::socket&& s)
        : owner(o), id(i), stream(std::move(s)), buffer(o.config.maxHeaderBytes + 2 * kReadChunk) {}

    ~Connection() {
        std::lock_guard lock(owner.registryMutex);
        owner.registry.erase(id);
    }

    void setPhase(Phase p) {
        phase.store(int(p));
        phaseSince.store(nowNs());
    }
    Phase currentPhase() const { return Phase(phase.load()); }

    void start();
    // Next request: at once when its bytes are already here (pipelining), else wait idle.
    void nextRequest();
    void readHeader();
    // True when `ec` ended the connection (closed or answered with an error).
    bool readFailed(beast::error_code ec, bool body);
    void onHeader(beast::error_code ec);
    void readBody();
    void dispatch();
    // Runs on a handler thread (compression is CPU work the I/O threads should not do).
    static Response toBeast(HttpResponse&& res, unsigned version, bool keepAlive, bool head, bool gzip);
    // The handler thread's last resort: a prepared 500 (connection: close) that formats
    // nothing from the request; null only when even its copy cannot be allocated.
    static std::shared_ptr<Response> fixedInternalError(unsigned version) noexcept;
    // While a request is handled, read on: a closed or failed connection trips the
    // request's cancel token; pipelined bytes are kept for the next request.
    void watch();
    void onWatch(beast::error_code ec, std::size_t n);
    void onHandled(const std::shared_ptr<Response>& out);
    void onWritten(beast::error_code ec, bool keepAlive);
    // Answers a request the transport refuses, then closes.
    void answerError(int status, const std::string& detail);
    // Half-closes, then reads and drops what the client still sends (at most 1 MiB or 2 s)
    // so that its unread bytes do not turn our last answer into a reset (nginx's
    // lingering_close).
    void lingerClose();
    void drain();
    void closeNow();
};

}  // namespace geoslice::server::transport_detail
