#include "server/respond.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cstdio>
#include <utility>

#include "api/params.hpp"
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
        case 416:
            return "Range Not Satisfiable";
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

namespace {

std::string_view opaqueTag(std::string_view tag) {  // weak comparison: W/ ignored
    if (tag.size() >= 2 && tag[0] == 'W' && tag[1] == '/') tag.remove_prefix(2);
    return tag;
}

// One "bytes=first-last" range of a body of `size` bytes (RFC 9110 14.1.2): [first, last],
// nullopt for a form this server ignores (several ranges, another unit: the whole body is
// sent, as 14.2 allows), or {size, 0} when unsatisfiable.
std::optional<std::pair<std::size_t, std::size_t>> byteRange(std::string_view range, std::size_t size) {
    range = text::trim(range);
    if (range.rfind("bytes=", 0) != 0) return std::nullopt;
    range.remove_prefix(6);
    if (range.find(',') != std::string_view::npos) return std::nullopt;
    const auto dash = range.find('-');
    if (dash == std::string_view::npos) return std::nullopt;
    auto number = [](std::string_view d, std::size_t& v) {
        d = text::trim(d);
        if (d.empty() || d.size() > 18) return false;
        v = 0;
        for (char c : d) {
            if (c < '0' || c > '9') return false;
            v = v * 10 + std::size_t(c - '0');
        }
        return true;
    };
    std::size_t first = 0, last = 0;
    const bool hasFirst = number(range.substr(0, dash), first);
    const bool hasLast = number(range.substr(dash + 1), last);
    if (!hasFirst) {  // suffix: the last `last` bytes
        if (!hasLast || !text::trim(range.substr(0, dash)).empty()) return std::nullopt;
        if (last == 0 || size == 0) return std::make_pair(size, std::size_t(0));
        return std::make_pair(size - std::min(last, size), size - 1);
    }
    if (!hasLast) {
        if (!text::trim(range.substr(dash + 1)).empty()) return std::nullopt;
        last = size ? size - 1 : 0;
    }
    if (first >= size) return std::make_pair(size, std::size_t(0));
    if (last < first) return std::nullopt;  // invalid: ignored
    return std::make_pair(first, std::min(last, size - 1));
}

}  // namespace

std::optional<std::string> matchingEtag(std::string_view ifNoneMatch, const std::string& etag) {
    ifNoneMatch = text::trim(ifNoneMatch);
    if (ifNoneMatch.empty()) return std::nullopt;
    if (ifNoneMatch == "*") return etag;
    const std::string gz = gzipEtag(etag);
    while (!ifNoneMatch.empty()) {
        const auto comma = ifNoneMatch.find(',');
        const std::string_view tag = text::trim(ifNoneMatch.substr(0, comma));
        ifNoneMatch = comma == std::string_view::npos ? std::string_view() : ifNoneMatch.substr(comma + 1);
        if (opaqueTag(tag) == opaqueTag(etag)) return etag;
        if (opaqueTag(tag) == opaqueTag(gz)) return gz;
    }
    return std::nullopt;
}

bool etagMatches(std::string_view ifNoneMatch, const std::string& etag) {
    return matchingEtag(ifNoneMatch, etag).has_value();
}

// A rendered answer's freshness: a URL pinned to the model's version (`version=`, checked against
// the model before any answer: server/routes/common.hpp versionPinHolds) never changes, so
// caches keep it a year; an unpinned one may change at the next re-bake, so shared caches
// keep it a minute and then revalidate with its ETag.
static std::string renderedCacheControl(const HttpRequest& req) {
    return req.params.count(std::string(api::kVersionParam)) ? "public, max-age=31536000, immutable"
                                                             : "public, max-age=60";
}

bool answerNotModified(const HttpRequest& req, HttpResponse& res, const std::string& etag) {
    const auto held = matchingEtag(req.get_header_value("If-None-Match"), etag);
    if (!held) return false;
    res.set_header("ETag", *held);
    res.set_header("Cache-Control", renderedCacheControl(req));
    res.status = 304;
    return true;
}

void sendEncoded(const HttpRequest& req, HttpResponse& res, const Encoded& e) {
    if (answerNotModified(req, res, e.etag)) return;
    res.set_header("ETag", e.etag);
    res.set_header("Cache-Control", renderedCacheControl(req));
    res.status = 200;
    if (e.contentType == "application/pdf") {
        res.set_header("Accept-Ranges", "bytes");
        const std::string range = req.get_header_value("Range");
        const std::string ifRange = req.get_header_value("If-Range");
        // If-Range: only the same strong ETag keeps the range (a date never does here).
        if (!range.empty() && (ifRange.empty() || ifRange == e.etag)) {
            if (auto r = byteRange(range, e.body.size())) {
                const std::string total = std::to_string(e.body.size());
                if (r->first >= e.body.size()) {
                    res.set_header("Content-Range", "bytes */" + total);
                    problem(res, 416,
                            "header 'Range': '" + text::escapeText(range.substr(0, 80)) +
                                "' starts past the end of the " + total + "-byte document",
                            req.path, "range_not_satisfiable");
                    return;
                }
                res.status = 206;
                res.set_header("Content-Range",
                               "bytes " + std::to_string(r->first) + "-" + std::to_string(r->second) + "/" + total);
                res.set_content(e.body.substr(r->first, r->second - r->first + 1), e.contentType);
                return;
            }
        }
    }
    res.set_content(e.body, e.contentType);
}

void addValidators(const HttpRequest& req, HttpResponse& res) {
    if (req.method != "GET" || res.status != 200 || !res.get_header_value("ETag").empty()) return;
    char tag[32];
    std::snprintf(tag, sizeof tag, "\"b-%016llx\"",
                  static_cast<unsigned long long>(XXH3_64bits(res.body.data(), res.body.size())));
    if (res.get_header_value("Cache-Control").empty()) res.set_header("Cache-Control", "no-cache");
    const auto held = matchingEtag(req.get_header_value("If-None-Match"), tag);
    res.set_header("ETag", held ? *held : std::string(tag));
    if (held) {
        res.status = 304;
        res.body.clear();
    }
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
