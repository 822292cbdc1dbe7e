// Answers: the one place where error codes become HTTP statuses (STYLE.md rule 4), RFC 9457
// problem details, JSON bodies, cached answers with their ETag and 304s. Any handler thread.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "model/result.hpp"
#include "server/http_message.hpp"
#include "server/render_cache.hpp"

namespace geoslice::server {

using Json = nlohmann::ordered_json;

// InvalidArgument/ParseError/OutOfRange 400, NotFound 404, Unsupported 422, Unavailable 503,
// DeadlineExceeded 504, IoError/Internal 500.
int httpStatus(ErrorCode code);

// A problem-details body (application/problem+json) with `status`; `code` (e.g.
// "not_found") is added as "code" when given.
void problem(HttpResponse& res, int status, const std::string& detail, const std::string& instance,
             const char* code = nullptr);
// An error as an answer: its status and code name, and Retry-After when the server lacks
// capacity now (Unavailable).
void problem(HttpResponse& res, const Error& e, const std::string& instance);

void sendJson(HttpResponse& res, const Json& j, int status = 200);

// Conditional GETs (RFC 9110 13.1.2): If-None-Match compares weakly (W/"x" matches "x"),
// and a representation answers to its identity ETag and to its gzip ETag (gzipEtag(): the
// transport renames the ETag of a body it compresses). The tag to send back with the 304
// (the one the client holds), or nullopt when nothing matches. "*" matches `etag`.
std::optional<std::string> matchingEtag(std::string_view ifNoneMatch, const std::string& etag);
bool etagMatches(std::string_view ifNoneMatch, const std::string& etag);
// 304 for `etag` when the request's If-None-Match names it (true: answered).
bool answerNotModified(const HttpRequest& req, HttpResponse& res, const std::string& etag);
// A cached answer: 200 with its body, 304 when If-None-Match names its ETag, and for PDFs
// (Accept-Ranges: bytes) one byte range: 206 with Content-Range, 416 when it starts past the
// end; If-Range with another ETag (or a date) gives the whole body.
void sendEncoded(const HttpRequest& req, HttpResponse& res, const Encoded& e);
// Validators on every 200 GET that has none (route lists, the OpenAPI document, model
// summaries): an ETag hashed from the body (the same on every replica) and, unless the
// route set one, `Cache-Control: no-cache` (store, revalidate each time); If-None-Match then
// gives 304. Called by the router after each handler.
void addValidators(const HttpRequest& req, HttpResponse& res);

// A POST body must be JSON (application/json or a +json type): false after answering 415.
bool requireJsonBody(const HttpRequest& req, HttpResponse& res);

}  // namespace geoslice::server
