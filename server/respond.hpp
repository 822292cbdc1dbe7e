// Answers: the one place where error codes become HTTP statuses (STYLE.md rule 4), RFC 9457
// problem details, JSON bodies, cached answers with their ETag and 304s. Any handler thread.
#pragma once

#include <string>

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

// True when an If-None-Match value names `etag` (strong comparison: a W/ tag never
// matches) or is "*".
bool etagMatches(const std::string& ifNoneMatch, const std::string& etag);
// 304 for `etag` when the request's If-None-Match names it (true: answered).
bool answerNotModified(const HttpRequest& req, HttpResponse& res, const std::string& etag);
// A cached answer: 200 with its body, or 304 when If-None-Match names its ETag.
void sendEncoded(const HttpRequest& req, HttpResponse& res, const Encoded& e);

// A POST body must be JSON (application/json or a +json type): false after answering 415.
bool requireJsonBody(const HttpRequest& req, HttpResponse& res);

}  // namespace geoslice::server
