// One connection's request/answer cycle (server/http_connection.hpp).
#include "server/http_connection.hpp"

#include <boost/asio/post.hpp>

#include <string_view>
#include <utility>
#include <vector>

namespace geoslice::server::transport_detail {

void Connection::start() {
    headerDeadline = Clock::now() + std::chrono::milliseconds(owner.config.headerTimeoutMs);
    readHeader();
}

void Connection::nextRequest() {
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

void Connection::readHeader() {
    setPhase(Phase::Header);
    // The whole header block first: Beast unfolds obs-fold lines silently, and RFC 9112 5.2
    // wants them refused, which only the raw bytes show. Bytes already scanned are not
    // scanned again (a client sending a byte at a time costs linear time).
    const std::string_view have(static_cast<const char*>(buffer.data().data()), buffer.size());
    std::size_t lead = 0;
    while (lead < have.size() && (have[lead] == '\r' || have[lead] == '\n')) ++lead;
    const std::size_t end = headerBlockEnd(have, std::max(lead, headerScanned > 2 ? headerScanned - 2 : 0));
    if (end == std::string_view::npos) {
        headerScanned = have.size();
        if (have.size() < owner.config.maxHeaderBytes) {
            stream.expires_at(headerDeadline);
            stream.async_read_some(buffer.prepare(kReadChunk),
                                   [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                                       if (self->readFailed(ec, false)) return;
                                       self->buffer.commit(n);
                                       self->readHeader();
                                   });
            return;
        }
        // Over the limit without its end: Beast's header_limit answers 431 below.
    } else if (const std::size_t line = findObsFold(have.substr(lead, end - lead)); line > 0) {
        headerScanned = 0;
        return answerError(400, "header line " + std::to_string(line) +
                                    " is folded onto the line before it (obs-fold, RFC 9112 5.2): not accepted");
    }
    headerScanned = 0;
    parser.emplace();
    parser->header_limit(std::uint32_t(owner.config.maxHeaderBytes));
    parser->body_limit(owner.config.maxBodyBytes);
    stream.expires_at(headerDeadline);
    http::async_read_header(stream, buffer, *parser,
                            [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onHeader(ec); });
}

bool Connection::readFailed(beast::error_code ec, bool body) {
    if (!ec) return false;
    if (ec == beast::error::timeout) {
        (body ? owner.counters.bodyTimeouts : owner.counters.headerTimeouts)++;
        closeNow();
    } else if (ec == http::error::body_limit) {
        answerError(413, "the request body is larger than the limit of " + std::to_string(owner.config.maxBodyBytes) +
                             " bytes");
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

void Connection::onHeader(beast::error_code ec) {
    if (readFailed(ec, false)) return;
    {
        const auto& msg = parser->get();
        std::vector<std::pair<std::string_view, std::string_view>> fields;
        for (const auto& f : msg) fields.emplace_back(f.name_string(), f.value());
        if (auto refusal = checkFraming(msg.version(), fields)) return answerError(refusal->status, refusal->detail);
    }
    if (parser->is_done()) return dispatch();
    setPhase(Phase::Body);
    stream.expires_after(std::chrono::milliseconds(owner.config.bodyTimeoutMs));
    if (beast::iequals(parser->get()[http::field::expect], "100-continue")) {
        auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, 11);
        return http::async_write(stream, *cont, [self = shared_from_this(), cont](beast::error_code e, std::size_t) {
            if (e) return self->closeNow();
            self->readBody();
        });
    }
    readBody();
}

void Connection::readBody() {
    http::async_read(stream, buffer, *parser, [self = shared_from_this()](beast::error_code ec, std::size_t) {
        if (self->readFailed(ec, true)) return;
        self->dispatch();
    });
}

void Connection::dispatch() {
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
        std::shared_ptr<Response> out;
        try {
            HttpResponse res;
            self->owner.handler(*req, res);
            out = std::make_shared<Response>(toBeast(std::move(res), version, keepAlive, head, gzip));
        } catch (...) {
            // The last catch: a fixed answer built from nothing the request holds, so
            // nothing here can throw again (the router catches what handlers throw; this
            // is for the router, the answer's conversion, or memory).
            out = fixedInternalError(version);
        }
        net::post(self->stream.get_executor(), [self, out] { self->onHandled(out); });
    });
}

Response Connection::toBeast(HttpResponse&& res, unsigned version, bool keepAlive, bool head, bool gzip) {
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
    const bool encodable =
        !noBody && compressibleType(contentType) && out.find(http::field::content_encoding) == out.end();
    if (encodable || s == 304) {
        // Added to what the router varies on (Origin, Authorization), not in its place. A 304
        // carries the Vary its 200 would (RFC 9110 15.4.5): its ETag depends on Accept-Encoding.
        const auto vary = out.find(http::field::vary);
        out.set(http::field::vary,
                vary == out.end() ? std::string("Accept-Encoding") : std::string(vary->value()) + ", Accept-Encoding");
    }
    if (encodable && willGzip(contentType, res.body.size(), gzip)) {
        std::string z = gzipCompress(res.body);
        if (!z.empty()) {
            res.body = std::move(z);
            out.set(http::field::content_encoding, "gzip");
            // The gzip bytes get their own ETag (respond.cpp matches both on revalidation).
            if (const auto etag = out.find(http::field::etag); etag != out.end())
                out.set(http::field::etag, gzipEtag(etag->value()));
        }
    }
    out.body() = std::move(res.body);
    out.keep_alive(keepAlive);
    out.prepare_payload();
    if (head) out.body().clear();  // Content-Length stays that of the GET answer
    return out;
}

namespace {

// The prepared 500 of the last catch for one HTTP version (10 or 11).
Response preparedInternalError(unsigned version) {
    Response r;
    r.version(version);
    r.result(500);
    r.set(http::field::content_type, "application/problem+json");
    r.body() = kInternalErrorBody;
    r.keep_alive(false);
    r.prepare_payload();
    return r;
}

}  // namespace

std::shared_ptr<Response> Connection::fixedInternalError(unsigned version) noexcept {
    // Built once per version on first use; a copy of a prepared message per failure.
    static const Response kFixed[2] = {preparedInternalError(10), preparedInternalError(11)};
    try {
        return std::make_shared<Response>(kFixed[version >= 11 ? 1 : 0]);
    } catch (...) {
        return nullptr;  // out of memory: onHandled closes the connection
    }
}

void Connection::watch() {
    if (buffer.size() + kReadChunk > buffer.max_size()) return;  // a full pipeline: stop reading
    watching = true;
    stream.expires_never();
    stream.async_read_some(buffer.prepare(kReadChunk),
                           [self = shared_from_this()](beast::error_code ec, std::size_t n) { self->onWatch(ec, n); });
}

void Connection::onWatch(beast::error_code ec, std::size_t n) {
    watching = false;
    const Phase p = currentPhase();
    if (p == Phase::Closed) return;
    const AfterWatch then = std::exchange(afterWatch, AfterWatch::Nothing);
    if (!ec) buffer.commit(n);
    if (then == AfterWatch::NextRequest) return ec && ec != net::error::operation_aborted ? closeNow() : nextRequest();
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

void Connection::onHandled(const std::shared_ptr<Response>& out) {
    if (currentPhase() != Phase::Handling) return;  // closed meanwhile (peer gone or stopping)
    if (peerGone || !out) return closeNow();
    setPhase(Phase::Writing);
    const auto perChunk = std::chrono::milliseconds(owner.config.sendTimeoutMs);
    stream.expires_after(perChunk * (1 + out->body().size() / (8u << 20)));
    http::async_write(stream, *out, [self = shared_from_this(), out](beast::error_code ec, std::size_t) {
        self->onWritten(ec, out->keep_alive());
    });
}

void Connection::onWritten(beast::error_code ec, bool keepAlive) {
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

void Connection::answerError(int status, const std::string& detail) {
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

void Connection::lingerClose() {
    setPhase(Phase::Closing);
    beast::error_code ignored;
    stream.socket().shutdown(tcp::socket::shutdown_send, ignored);
    buffer.consume(buffer.size());
    stream.expires_after(std::chrono::seconds(2));
    drain();
}

void Connection::drain() {
    stream.async_read_some(buffer.prepare(kReadChunk),
                           [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                               self->lingered += n;
                               if (ec || self->lingered > (1u << 20)) return self->closeNow();
                               self->buffer.consume(self->buffer.size());
                               self->drain();
                           });
}

void Connection::closeNow() {
    if (currentPhase() == Phase::Closed) return;
    setPhase(Phase::Closed);
    if (cancel && !cancel->exchange(true)) owner.counters.cancelled++;
    beast::error_code ignored;
    stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream.close();
}

}  // namespace geoslice::server::transport_detail
