#include "server/http_transport.hpp"

#include <sys/resource.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <sstream>
#include <thread>

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include "server/http_connection.hpp"

namespace geoslice::server {

namespace transport_detail {

template <class F>
void Core::forEachConnection(F f) {
    std::vector<std::shared_ptr<Connection>> all;
    {
        std::lock_guard lock(registryMutex);
        for (auto& [id, weak] : registry)
            if (auto c = weak.lock()) all.push_back(std::move(c));
    }
    for (auto& c : all) f(c);
}

void Core::accept() {
    acceptor.async_accept(net::make_strand(ioc),
                          [this](beast::error_code ec, tcp::socket socket) { onAccept(ec, std::move(socket)); });
}

bool Core::evictOne() {
    std::shared_ptr<Connection> oldest;
    std::int64_t since = 0;
    forEachConnection([&](const std::shared_ptr<Connection>& c) {
        const Phase p = c->currentPhase();
        if (p != Phase::Idle && p != Phase::Header && p != Phase::Body && p != Phase::Closing) return;
        const std::int64_t t = c->phaseSince.load();
        if (!oldest || t < since) {
            oldest = c;
            since = t;
        }
    });
    if (!oldest) return false;
    counters.evicted++;
    net::post(oldest->stream.get_executor(), [oldest] { oldest->closeNow(); });
    return true;
}

void Core::reject(tcp::socket& socket) {
    // Every connection is busy with a request: 503 at once, written without waiting (it
    // fits the socket's send buffer), then closed.
    counters.rejected++;
    HttpResponse res;
    errorBody(res, 503, "the server has " + std::to_string(config.maxConnections) + " connections open; retry shortly",
              "");
    res.set_header("Retry-After", "1");
    const Response out = Connection::toBeast(std::move(res), 11, false, false, false);
    std::ostringstream bytes;
    bytes << out;
    beast::error_code ec;
    socket.non_blocking(true, ec);
    socket.write_some(net::buffer(bytes.str()), ec);
    socket.shutdown(tcp::socket::shutdown_send, ec);
    socket.close(ec);
}

void Core::onAccept(beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted || stopping) return;
    if (ec) {
        // Out of file descriptors (EMFILE) and the like: wait a little instead of spinning.
        spdlog::warn("event=accept_failed error=\"{}\"", ec.message());
        acceptRetry.expires_after(std::chrono::milliseconds(50));
        acceptRetry.async_wait([this](beast::error_code e) {
            if (!e && !stopping) accept();
        });
        return;
    }
    counters.accepted++;
    beast::error_code ignored;
    socket.set_option(tcp::no_delay(true), ignored);
    if (openConnections() >= config.maxConnections && !evictOne()) {
        reject(socket);
    } else {
        std::shared_ptr<Connection> c;
        {
            std::lock_guard lock(registryMutex);
            c = std::make_shared<Connection>(*this, ++nextId, std::move(socket));
            registry.emplace(c->id, c);
        }
        net::post(c->stream.get_executor(), [c] { c->start(); });
    }
    accept();
}

}  // namespace transport_detail

using namespace transport_detail;

struct HttpTransport::Impl : Core {
    using Core::Core;
};

HttpTransport::HttpTransport(TransportConfig config, Handler handler, ErrorBody errorBody)
    : impl_(std::make_unique<Impl>(std::move(config), std::move(handler), std::move(errorBody))) {}

HttpTransport::~HttpTransport() { stop(0); }

Result<int> HttpTransport::listen() {
    Impl& im = *impl_;
    auto& cfg = im.config;
    // Each connection holds a descriptor: raise the soft limit towards the hard one, and
    // keep the cap below what the process may open.
    rlimit lim{};
    if (getrlimit(RLIMIT_NOFILE, &lim) == 0) {
        const rlim_t want = rlim_t(cfg.maxConnections + 256);
        if (lim.rlim_cur != RLIM_INFINITY && lim.rlim_cur < want) {
            lim.rlim_cur = lim.rlim_max == RLIM_INFINITY ? want : std::min(want, lim.rlim_max);
            setrlimit(RLIMIT_NOFILE, &lim);
            getrlimit(RLIMIT_NOFILE, &lim);
        }
        if (lim.rlim_cur != RLIM_INFINITY && lim.rlim_cur < want) {
            const std::size_t cap =
                lim.rlim_cur > 512 ? std::size_t(lim.rlim_cur) - 256 : std::size_t(lim.rlim_cur) / 2;
            spdlog::warn("event=connection_cap_lowered from={} to={} rlimit_nofile={}", cfg.maxConnections, cap,
                         lim.rlim_cur);
            cfg.maxConnections = cap;
        }
    }
    const std::string where = cfg.host + ":" + std::to_string(cfg.port);
    beast::error_code ec;
    tcp::resolver resolver(im.ioc);
    auto endpoints = resolver.resolve(cfg.host, std::to_string(cfg.port),
                                      tcp::resolver::passive | tcp::resolver::numeric_service, ec);
    if (ec || endpoints.empty())
        return makeError(ErrorCode::IoError, "cannot listen on " + where + ": cannot resolve '" + cfg.host +
                                                 "': " + (ec ? ec.message() : "no address"));
    const tcp::endpoint endpoint = endpoints.begin()->endpoint();
    im.acceptor.open(endpoint.protocol(), ec);
    if (!ec) im.acceptor.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec && cfg.reusePort) {
        const int one = 1;
        if (setsockopt(im.acceptor.native_handle(), SOL_SOCKET, SO_REUSEPORT, &one, sizeof one) != 0)
            ec = beast::error_code(errno, beast::system_category());
    }
    if (ec) return makeError(ErrorCode::IoError, "cannot listen on " + where + ": " + ec.message());
    im.acceptor.bind(endpoint, ec);
    if (ec == net::error::address_in_use)
        return makeError(ErrorCode::IoError, "cannot listen on " + where +
                                                 ": the address is already in use (another server listens there; "
                                                 "stop it or choose another port)");
    if (ec) return makeError(ErrorCode::IoError, "cannot listen on " + where + ": " + ec.message());
    // SOMAXCONN: bursts of connects wait in the kernel's queue instead of retrying SYNs.
    im.acceptor.listen(net::socket_base::max_listen_connections, ec);
    if (ec) return makeError(ErrorCode::IoError, "cannot listen on " + where + ": " + ec.message());
    return int(im.acceptor.local_endpoint().port());
}

void HttpTransport::start() {
    Impl& im = *impl_;
    std::lock_guard lock(im.stopMutex);
    if (im.started) return;
    im.started = true;
    im.pool.emplace(im.config.handlerThreads);
    im.work.emplace(net::make_work_guard(im.ioc));
    net::post(im.acceptStrand, [&im] { im.accept(); });
    for (unsigned i = 0; i < std::max(1u, im.config.ioThreads); ++i) im.ioThreads.emplace_back([&im] { im.ioc.run(); });
}

void HttpTransport::stop(int graceMs) {
    Impl& im = *impl_;
    std::lock_guard lock(im.stopMutex);
    if (!im.started || im.stopped) return;
    im.stopped = true;
    im.stopping = true;
    net::post(im.acceptStrand, [&im] {
        beast::error_code ignored;
        im.acceptor.close(ignored);
        im.acceptRetry.cancel();
    });
    // Connections waiting for a request close now; answers being made or sent may finish.
    auto closeWaiting = [&im] {
        im.forEachConnection([](const std::shared_ptr<Connection>& c) {
            net::post(c->stream.get_executor(), [c] {
                const Phase p = c->currentPhase();
                if (p == Phase::Idle || p == Phase::Header || p == Phase::Body) c->closeNow();
            });
        });
    };
    closeWaiting();
    const auto until = Clock::now() + std::chrono::milliseconds(std::max(0, graceMs));
    while (Clock::now() < until) {
        bool busy = im.pool->pending() > 0;
        if (!busy)
            im.forEachConnection([&busy](const std::shared_ptr<Connection>& c) {
                const Phase p = c->currentPhase();
                busy = busy || p == Phase::Handling || p == Phase::Writing;
            });
        if (!busy) break;
        closeWaiting();  // those that finished an answer meanwhile
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    // closeNow trips the cancel token of a request still being handled.
    im.forEachConnection(
        [](const std::shared_ptr<Connection>& c) { net::post(c->stream.get_executor(), [c] { c->closeNow(); }); });
    im.work.reset();
    // Give the posted closes a moment to run, then stop whatever is left.
    const auto closeUntil = Clock::now() + std::chrono::milliseconds(200);
    while (im.openConnections() > 0 && Clock::now() < closeUntil)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    im.ioc.stop();
    for (auto& t : im.ioThreads)
        if (t.joinable()) t.join();
    im.pool->stop();  // handlers still running finish (the routes bound them); their answers are dropped
}

std::size_t HttpTransport::requestsInHandlers() const { return impl_->pool ? impl_->pool->pending() : 0; }

TransportStats HttpTransport::stats() const {
    const auto& c = impl_->counters;
    TransportStats s;
    s.accepted = c.accepted;
    s.open = impl_->openConnections();
    s.rejected = c.rejected;
    s.evicted = c.evicted;
    s.headerTimeouts = c.headerTimeouts;
    s.bodyTimeouts = c.bodyTimeouts;
    s.sendTimeouts = c.sendTimeouts;
    s.badRequests = c.badRequests;
    s.cancelled = c.cancelled;
    return s;
}

}  // namespace geoslice::server
