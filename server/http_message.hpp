// An HTTP/1.1 request and response as the routes see them (server/router.hpp,
// server/routes/), and the message-level helpers of the transport (server/http_transport.hpp):
// request-target splitting, Accept-Encoding, which content types are compressed, gzip.
// No sockets and no Beast here: the routes, the fuzz target and the unit tests use these alone.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace geoslice::api {
struct ApiKey;
}

namespace geoslice::server {

// One request as a route sees it. Member names follow cpp-httplib's (the previous HTTP
// layer), so the routes read as before.
struct HttpRequest {
    std::string method;  // "GET", "POST", "OPTIONS"; HEAD is routed as GET (no body is sent)
    std::string target;  // the request-target as received
    std::string path;    // percent-decoded path, without the query
    std::multimap<std::string, std::string> params;            // decoded query parameters
    std::vector<std::pair<std::string, std::string>> headers;  // as received, in order
    std::string body;
    std::vector<std::string> matches;  // set by the router: [0] = path, then the groups
    // The API key the request authenticated with (set by the router on routes that need one
    // while keys are on; owned by ServerState::keys); null otherwise.
    const api::ApiKey* key = nullptr;
    // Set to true when the client goes away (the connection closes or fails) while the
    // request is being handled, or when the server stops: work for it may be dropped.
    // Written by the I/O threads, read by anyone.
    std::shared_ptr<std::atomic<bool>> cancelled = std::make_shared<std::atomic<bool>>(false);

    bool isCancelled() const { return cancelled->load(std::memory_order_relaxed); }
    // First value of a header (names compare case-insensitively); "" when absent.
    std::string get_header_value(std::string_view name) const;
    bool has_header(std::string_view name) const;
};

struct HttpResponse {
    int status = 200;
    std::vector<std::pair<std::string, std::string>> headers;
    std::string body;

    void set_header(std::string name, std::string value);  // adds a field (repeats allowed)
    void erase_header(std::string_view name);              // every field of that name
    void set_content(std::string content, std::string contentType);
    std::string get_header_value(std::string_view name) const;
};

// Splits a request-target into its percent-decoded path and query parameters ('+' is a
// space in the query). Malformed escapes are kept as they are.
void parseTarget(std::string_view target, std::string& path, std::multimap<std::string, std::string>& params);
// A request the transport must refuse before routing: its status and why.
struct Refusal {
    int status = 400;
    std::string detail;
};
// RFC 9112 framing rules that Beast's parser does not enforce, checked on the parsed header
// (`version` 10 or 11; the header fields as received): a Transfer-Encoding other than one
// lone "chunked" is 501 (6.1: the body's length is unknown, so the connection closes), one
// on HTTP/1.0 or beside a Content-Length is 400 (6.1, 6.3); an HTTP/1.1 request without
// exactly one Host is 400 (3.2). The caller answers and closes the connection.
std::optional<Refusal> checkFraming(unsigned version,
                                    const std::vector<std::pair<std::string_view, std::string_view>>& fields);
// Where a request's header block ends: the offset just past its empty line ("\r\n\r\n", or
// "\n\n"), searching `bytes` from `from`; npos when it has not arrived yet.
std::size_t headerBlockEnd(std::string_view bytes, std::size_t from = 0);
// A header line folded onto the one before it (obs-fold: a line that starts with a space
// or a tab, RFC 9112 5.2), which a server must refuse or unfold; Beast unfolds silently, so
// the transport refuses it here from the raw block. The 1-based line number, or 0.
std::size_t findObsFold(std::string_view headerBlock);

// True when an Accept-Encoding value accepts gzip (a q of 0 refuses it).
bool acceptsGzip(std::string_view acceptEncoding);
// True for content types worth compressing (text, JSON, SVG, XML, JavaScript).
bool compressibleType(std::string_view contentType);
// Bodies under this many bytes are sent as they are (gzip would not save a packet).
constexpr std::size_t kGzipMinBytes = 256;
// Whether the transport gzips a body of this type and size for a client that accepts
// gzip: the one rule that both the transport (which compresses) and the ETag choice
// (respond.hpp: a distinct ETag per encoding) follow.
bool willGzip(std::string_view contentType, std::size_t bodyBytes, bool clientAcceptsGzip);
// The ETag of the gzip encoding of the representation tagged `etag` ("abc" -> "abc-gzip",
// W/"abc" -> W/"abc-gzip"): a strong ETag names one sequence of bytes (RFC 9110 8.8.3), so
// the gzip and identity bodies must not share one.
std::string gzipEtag(std::string_view etag);
// gzip (RFC 1952) of `data` at zlib's default level.
std::string gzipCompress(std::string_view data);

}  // namespace geoslice::server
