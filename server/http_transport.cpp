#include "server/http_transport.hpp"

#include <sys/resource.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <unordered_map>

#include <spdlog/spdlog.h>
#include <zlib.h>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

namespace geoslice::server {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

// ---- request and response --------------------------------------------------------------

namespace {

bool equalsNoCase(std::string_view a, std::string_view b) { return beast::iequals(a, b); }

int hexDigit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

std::string percentDecode(std::string_view s, bool plusIsSpace) {
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        const char c = s[i];
        if (c == '%' && i + 2 < s.size()) {
            const int hi = hexDigit(s[i + 1]), lo = hexDigit(s[i + 2]);
            if (hi >= 0 && lo >= 0) {
                out += char(hi * 16 + lo);
                i += 2;
                continue;
            }
        }
        out += plusIsSpace && c == '+' ? ' ' : c;
    }
    return out;
}

}  // namespace

std::string HttpRequest::get_header_value(std::string_view name) const {
    for (const auto& [k, v] : headers)
        if (equalsNoCase(k, name)) return v;
    return {};
}

bool HttpRequest::has_header(std::string_view name) const {
    return std::any_of(headers.begin(), headers.end(), [&](const auto& h) { return equalsNoCase(h.first, name); });
}

void HttpResponse::set_header(std::string name, std::string value) {
    headers.emplace_back(std::move(name), std::move(value));
}

void HttpResponse::set_content(std::string content, std::string contentType) {
    body = std::move(content);
    headers.erase(std::remove_if(headers.begin(), headers.end(),
                                 [](const auto& h) { return equalsNoCase(h.first, "Content-Type"); }),
                  headers.end());
    headers.emplace_back("Content-Type", std::move(contentType));
}

std::string HttpResponse::get_header_value(std::string_view name) const {
    for (const auto& [k, v] : headers)
        if (equalsNoCase(k, name)) return v;
    return {};
}

void parseTarget(std::string_view target, std::string& path, std::multimap<std::string, std::string>& params) {
    // absolute-form (RFC 9112 3.2.2): "http://host/path?query"
    if (const auto scheme = target.find("://"); scheme != std::string_view::npos && target.substr(0, 1) != "/") {
        const auto slash = target.find('/', scheme + 3);
        target = slash == std::string_view::npos ? std::string_view("/") : target.substr(slash);
    }
    if (const auto hash = target.find('#'); hash != std::string_view::npos) target = target.substr(0, hash);
    const auto q = target.find('?');
    path = percentDecode(target.substr(0, q), false);
    params.clear();
    if (q == std::string_view::npos) return;
    std::string_view query = target.substr(q + 1);
    while (!query.empty()) {
        const auto amp = query.find('&');
        const std::string_view pair = query.substr(0, amp);
        query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
        if (pair.empty()) continue;
        const auto eq = pair.find('=');
        if (eq == std::string_view::npos)
            params.emplace(percentDecode(pair, true), std::string());
        else
            params.emplace(percentDecode(pair.substr(0, eq), true), percentDecode(pair.substr(eq + 1), true));
    }
}

bool acceptsGzip(std::string_view acceptEncoding) {
    // "gzip;q=0.5, br" (RFC 9110 12.5.3). Not Beast's http::ext_list: fuzz_http found it
    // reading past the end of a malformed list (",1,0,*;q;Q") in Boost 1.74.
    auto trim = [](std::string_view v) {
        while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
        while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
        return v;
    };
    while (!acceptEncoding.empty()) {
        const auto comma = acceptEncoding.find(',');
        std::string_view item = acceptEncoding.substr(0, comma);
        acceptEncoding = comma == std::string_view::npos ? std::string_view() : acceptEncoding.substr(comma + 1);
        const auto semi = item.find(';');
        const std::string_view coding = trim(item.substr(0, semi));
        if (!equalsNoCase(coding, "gzip") && coding != "*") continue;
        double q = 1.0;
        for (std::string_view params = semi == std::string_view::npos ? std::string_view() : item.substr(semi + 1);
             !params.empty();) {
            const auto next = params.find(';');
            const std::string_view param = trim(params.substr(0, next));
            params = next == std::string_view::npos ? std::string_view() : params.substr(next + 1);
            if (param.size() > 2 && (param[0] == 'q' || param[0] == 'Q') && param[1] == '=')
                q = std::strtod(std::string(param.substr(2)).c_str(), nullptr);
        }
        return q > 0.0;
    }
    return false;
}

bool compressibleType(std::string_view type) {
    type = type.substr(0, type.find(';'));
    if (type.rfind("text/", 0) == 0) return type != "text/event-stream";
    if (type.size() > 5 && type.substr(type.size() - 5) == "+json") return true;
    if (type.size() > 4 && type.substr(type.size() - 4) == "+xml") return true;
    return type == "application/json" || type == "application/javascript" || type == "application/xml";
}

std::string gzipCompress(std::string_view data) {
    z_stream z{};
    // windowBits 15 + 16: a gzip header and trailer instead of zlib's
    if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
    std::string out(deflateBound(&z, uLong(data.size())) + 32, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = uInt(data.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    const int rc = deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    return rc == Z_STREAM_END ? out : std::string();
}

// ---- handler pool ----------------------------------------------------------------------

namespace transport_detail {

class HandlerPool {
public:
    explicit HandlerPool(unsigned threads) {
        for (unsigned i = 0; i < std::max(1u, threads); ++i) threads_.emplace_back([this] { run(); });
    }
    ~HandlerPool() { stop(); }
    void submit(std::function<void()> job) {
        {
            std::lock_guard lock(mutex_);
            queue_.push_back(std::move(job));
        }
        ready_.notify_one();
    }
    std::size_t pending() const {
        std::lock_guard lock(mutex_);
        return queue_.size() + busy_;
    }
    // Runs what is queued, then joins.
    void stop() {
        {
            std::lock_guard lock(mutex_);
            stopping_ = true;
        }
        ready_.notify_all();
        for (auto& t : threads_)
            if (t.joinable()) t.join();
    }

private:
    void run() {
        std::unique_lock lock(mutex_);
        while (true) {
            ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (queue_.empty()) return;
            auto job = std::move(queue_.front());
            queue_.pop_front();
            ++busy_;
            lock.unlock();
            job();
            lock.lock();
            --busy_;
        }
    }
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<std::function<void()>> queue_;  // guarded by mutex_
    std::vector<std::thread> threads_;         // set by the constructor, joined by stop()
    std::size_t busy_ = 0;                     // guarded by mutex_
    bool stopping_ = false;                    // guarded by mutex_
};

// What a connection is doing; Idle, Header and Body are "waiting for a request" (evictable).
enum class Phase : int { Idle, Header, Body, Handling, Writing, Closing, Closed };

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

using Response = http::response<http::string_body>;

// ---- transport -------------------------------------------------------------------------

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

    void start() {
        headerDeadline = Clock::now() + std::chrono::milliseconds(owner.config.headerTimeoutMs);
        readHeader();
    }

    // Next request: at once when its bytes are already here (pipelining), else wait idle.
    void nextRequest() {
        if (owner.stopping) return closeNow();
        if (buffer.size() > 0) {
            headerDeadline = Clock::now() + std::chrono::milliseconds(owner.config.headerTimeoutMs);
            return readHeader();
        }
        setPhase(Phase::Idle);
        stream.expires_after(std::chrono::milliseconds(owner.config.keepAliveMs));
        stream.async_read_some(
            buffer.prepare(kReadChunk), [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                if (ec) return self->closeNow();
                self->buffer.commit(n);
                self->headerDeadline = Clock::now() + std::chrono::milliseconds(self->owner.config.headerTimeoutMs);
                self->readHeader();
            });
    }

    void readHeader() {
        setPhase(Phase::Header);
        parser.emplace();
        parser->header_limit(std::uint32_t(owner.config.maxHeaderBytes));
        parser->body_limit(owner.config.maxBodyBytes);
        stream.expires_at(headerDeadline);
        http::async_read_header(stream, buffer, *parser,
                                [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onHeader(ec); });
    }

    // True when `ec` ended the connection (closed or answered with an error).
    bool readFailed(beast::error_code ec, bool body) {
        if (!ec) return false;
        if (ec == beast::error::timeout) {
            (body ? owner.counters.bodyTimeouts : owner.counters.headerTimeouts)++;
            closeNow();
        } else if (ec == http::error::body_limit) {
            answerError(413, "the request body is larger than the limit of " +
                                 std::to_string(owner.config.maxBodyBytes) + " bytes");
        } else if (ec == http::error::header_limit) {
            answerError(431, "the request line and headers are larger than the limit of " +
                                 std::to_string(owner.config.maxHeaderBytes) + " bytes");
        } else if (ec == http::error::end_of_stream || ec == net::error::eof || ec == net::error::connection_reset ||
                   ec == net::error::operation_aborted || ec == http::error::partial_message ||
                   ec == beast::errc::not_connected) {
            closeNow();
        } else {
            answerError(400, "malformed request: " + ec.message());
        }
        return true;
    }

    void onHeader(beast::error_code ec) {
        if (readFailed(ec, false)) return;
        if (parser->is_done()) return dispatch();
        setPhase(Phase::Body);
        stream.expires_after(std::chrono::milliseconds(owner.config.bodyTimeoutMs));
        if (beast::iequals(parser->get()[http::field::expect], "100-continue")) {
            auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, 11);
            return http::async_write(stream, *cont,
                                     [self = shared_from_this(), cont](beast::error_code e, std::size_t) {
                                         if (e) return self->closeNow();
                                         self->readBody();
                                     });
        }
        readBody();
    }

    void readBody() {
        http::async_read(stream, buffer, *parser, [self = shared_from_this()](beast::error_code ec, std::size_t) {
            if (self->readFailed(ec, true)) return;
            self->dispatch();
        });
    }

    void dispatch() {
        auto msg = parser->release();
        parser.reset();
        auto req = std::make_shared<HttpRequest>();
        const bool head = msg.method() == http::verb::head;
        req->method = head ? "GET" : std::string(msg.method_string());
        req->target = std::string(msg.target());
        parseTarget(req->target, req->path, req->params);
        req->headers.reserve(std::size_t(std::distance(msg.begin(), msg.end())));
        for (const auto& f : msg) req->headers.emplace_back(std::string(f.name_string()), std::string(f.value()));
        req->body = std::move(msg.body());
        cancel = req->cancelled;
        ++served;
        const bool keepAlive = msg.keep_alive() && served < owner.config.keepAliveRequests && !owner.stopping.load();
        const bool gzip = acceptsGzip(msg[http::field::accept_encoding]);
        const unsigned version = msg.version();
        setPhase(Phase::Handling);
        watch();
        owner.pool->submit([self = shared_from_this(), req, head, keepAlive, gzip, version] {
            HttpResponse res;
            try {
                self->owner.handler(*req, res);
            } catch (const std::exception& e) {
                res = HttpResponse();
                self->owner.errorBody(res, 500, std::string("internal error: ") + e.what(), req->path);
            }
            auto out = std::make_shared<Response>(toBeast(std::move(res), version, keepAlive, head, gzip));
            net::post(self->stream.get_executor(), [self, out] { self->onHandled(out); });
        });
    }

    // Runs on a handler thread (compression is CPU work the I/O threads should not do).
    static Response toBeast(HttpResponse&& res, unsigned version, bool keepAlive, bool head, bool gzip) {
        Response out;
        out.version(version);
        out.result(unsigned(res.status));
        std::string contentType;
        for (auto& [name, value] : res.headers) {
            if (beast::iequals(name, "Connection")) {
                if (beast::iequals(value, "close")) keepAlive = false;
                continue;
            }
            if (beast::iequals(name, "Content-Length")) continue;  // computed below
            if (beast::iequals(name, "Content-Type")) contentType = value;
            out.insert(name, value);
        }
        const unsigned s = unsigned(res.status);
        const bool noBody = s / 100 == 1 || s == 204 || s == 304;
        if (noBody) res.body.clear();
        if (!noBody && compressibleType(contentType) && out.find(http::field::content_encoding) == out.end()) {
            out.set(http::field::vary, "Accept-Encoding");
            if (gzip && res.body.size() >= 256) {
                std::string z = gzipCompress(res.body);
                if (!z.empty()) {
                    res.body = std::move(z);
                    out.set(http::field::content_encoding, "gzip");
                }
            }
        }
        out.body() = std::move(res.body);
        out.keep_alive(keepAlive);
        out.prepare_payload();
        if (head) out.body().clear();  // Content-Length stays that of the GET answer
        return out;
    }

    // While a request is handled, read on: a closed or failed connection trips the
    // request's cancel token; pipelined bytes are kept for the next request.
    void watch() {
        if (buffer.size() + kReadChunk > buffer.max_size()) return;  // a full pipeline: stop reading
        watching = true;
        stream.expires_never();
        stream.async_read_some(
            buffer.prepare(kReadChunk),
            [self = shared_from_this()](beast::error_code ec, std::size_t n) { self->onWatch(ec, n); });
    }

    void onWatch(beast::error_code ec, std::size_t n) {
        watching = false;
        const Phase p = currentPhase();
        if (p == Phase::Closed) return;
        const AfterWatch then = std::exchange(afterWatch, AfterWatch::Nothing);
        if (!ec) buffer.commit(n);
        if (then == AfterWatch::NextRequest)
            return ec && ec != net::error::operation_aborted ? closeNow() : nextRequest();
        if (then == AfterWatch::LingerClose) return lingerClose();
        if (!ec) {
            if (p == Phase::Handling) watch();
            return;
        }
        if (ec == net::error::operation_aborted) return;
        // The peer closed or reset the connection.
        peerGone = true;
        if (cancel && !cancel->exchange(true)) owner.counters.cancelled++;
        if (p == Phase::Handling) closeNow();  // its answer is dropped when it comes
    }

    void onHandled(const std::shared_ptr<Response>& out) {
        if (currentPhase() != Phase::Handling) return;  // closed meanwhile (peer gone or stopping)
        if (peerGone) return closeNow();
        setPhase(Phase::Writing);
        const auto perChunk = std::chrono::milliseconds(owner.config.sendTimeoutMs);
        stream.expires_after(perChunk * (1 + out->body().size() / (8u << 20)));
        http::async_write(stream, *out, [self = shared_from_this(), out](beast::error_code ec, std::size_t) {
            self->onWritten(ec, out->keep_alive());
        });
    }

    void onWritten(beast::error_code ec, bool keepAlive) {
        cancel.reset();
        if (ec) {
            if (ec == beast::error::timeout) owner.counters.sendTimeouts++;
            return closeNow();
        }
        const bool close = !keepAlive || peerGone || owner.stopping;
        if (watching) {  // finish the watch read first: never two reads at once
            afterWatch = close ? AfterWatch::LingerClose : AfterWatch::NextRequest;
            beast::error_code ignored;
            stream.socket().cancel(ignored);
            return;
        }
        close ? lingerClose() : nextRequest();
    }

    // Answers a request the transport refuses, then closes.
    void answerError(int status, const std::string& detail) {
        owner.counters.badRequests++;
        HttpResponse res;
        owner.errorBody(res, status, detail,
                        parser && parser->get().target().size() ? std::string(parser->get().target()) : "");
        parser.reset();
        auto out = std::make_shared<Response>(toBeast(std::move(res), 11, false, false, false));
        setPhase(Phase::Writing);
        stream.expires_after(std::chrono::milliseconds(owner.config.sendTimeoutMs));
        http::async_write(stream, *out, [self = shared_from_this(), out](beast::error_code e, std::size_t) {
            if (e) return self->closeNow();
            self->lingerClose();
        });
    }

    // Half-closes, then reads and drops what the client still sends (at most 1 MiB or 2 s)
    // so that its unread bytes do not turn our last answer into a reset (nginx's
    // lingering_close).
    void lingerClose() {
        setPhase(Phase::Closing);
        beast::error_code ignored;
        stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
        buffer.consume(buffer.size());
        stream.expires_after(std::chrono::seconds(2));
        drain();
    }

    void drain() {
        stream.async_read_some(buffer.prepare(kReadChunk),
                               [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                                   self->lingered += n;
                                   if (ec || self->lingered > (1u << 20)) return self->closeNow();
                                   self->buffer.consume(self->buffer.size());
                                   self->drain();
                               });
    }

    void closeNow() {
        if (currentPhase() == Phase::Closed) return;
        setPhase(Phase::Closed);
        if (cancel && !cancel->exchange(true)) owner.counters.cancelled++;
        beast::error_code ignored;
        stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
        stream.close();
    }
};

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
