#include "server/respond.hpp"

#include "api/request.hpp"
#include "model/json_text.hpp"
#include "model/text_scan.hpp"

namespace geoslice::server {
namespace {

const char* statusTitle(int status) {
    switch (status) {
        case 400:
            return "Bad Request";
        case 401:
            return "Unauthorized";
        case 403:
            return "Forbidden";
        case 404:
            return "Not Found";
        case 405:
            return "Method Not Allowed";
        case 413:
            return "Content Too Large";
        case 415:
            return "Unsupported Media Type";
        case 422:
            return "Unprocessable Content";
        case 431:
            return "Request Header Fields Too Large";
        case 500:
            return "Internal Server Error";
        case 501:
            return "Not Implemented";
        case 503:
            return "Service Unavailable";
        case 504:
            return "Gateway Timeout";
        default:
            return "Error";
    }
}

}  // namespace

int httpStatus(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument:
        case ErrorCode::ParseError:
        case ErrorCode::OutOfRange:
            return 400;
        case ErrorCode::NotFound:
            return 404;
        case ErrorCode::Unsupported:
            return 422;
        case ErrorCode::Unavailable:
            return 503;
        case ErrorCode::DeadlineExceeded:
            return 504;
        case ErrorCode::IoError:
        case ErrorCode::Internal:
            return 500;
    }
    return 500;
}

void problem(HttpResponse& res, int status, const std::string& detail, const std::string& instance, const char* code) {
    Json j;
    j["type"] = "about:blank";
    j["title"] = statusTitle(status);
    j["status"] = status;
    // Both may hold bytes from the request (a path, a parameter): escaped here, so that the
    // body is UTF-8 and shows what was sent.
    j["detail"] = text::escapeText(detail, 4096);
    j["instance"] = text::escapeText(instance, 512);
    if (code) j["code"] = code;
    res.status = status;
    res.set_content(jsonText(j), "application/problem+json");
}

void problem(HttpResponse& res, const Error& e, const std::string& instance) {
    if (e.code == ErrorCode::Unavailable) res.set_header("Retry-After", "1");
    problem(res, httpStatus(e.code), e.message, instance, errorCodeName(e.code));
}

void sendJson(HttpResponse& res, const Json& j, int status) {
    res.status = status;
    res.set_content(jsonText(j), "application/json");
}

bool etagMatches(const std::string& ifNoneMatch, const std::string& etag) {
    if (ifNoneMatch.empty()) return false;
    if (ifNoneMatch == "*") return true;
    std::size_t pos = 0;
    while (pos < ifNoneMatch.size()) {
        std::size_t comma = ifNoneMatch.find(',', pos);
        if (comma == std::string::npos) comma = ifNoneMatch.size();
        std::string tag = ifNoneMatch.substr(pos, comma - pos);
        while (!tag.empty() && tag.front() == ' ') tag.erase(tag.begin());
        while (!tag.empty() && tag.back() == ' ') tag.pop_back();
        if (tag == etag) return true;  // strong comparison (a W/ tag never matches)
        pos = comma + 1;
    }
    return false;
}

bool answerNotModified(const HttpRequest& req, HttpResponse& res, const std::string& etag) {
    if (!etagMatches(req.get_header_value("If-None-Match"), etag)) return false;
    res.set_header("ETag", etag);
    res.set_header("Cache-Control", "public, max-age=86400");
    res.status = 304;
    return true;
}

void sendEncoded(const HttpRequest& req, HttpResponse& res, const Encoded& e) {
    res.set_header("ETag", e.etag);
    res.set_header("Cache-Control", "public, max-age=86400");
    if (etagMatches(req.get_header_value("If-None-Match"), e.etag)) {
        res.status = 304;
        return;
    }
    res.status = 200;
    res.set_content(e.body, e.contentType);
}

bool requireJsonBody(const HttpRequest& req, HttpResponse& res) {
    const std::string type = api::mediaType(req.get_header_value("Content-Type"));
    if (api::isJsonMediaType(type)) return true;
    problem(res, 415,
            "header 'Content-Type': '" + type.substr(0, 80) + "' is not application/json; the body must be JSON",
            req.path, "unsupported_media_type");
    return false;
}

}  // namespace geoslice::server
