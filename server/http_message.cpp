// HttpRequest / HttpResponse and the transport's message-level helpers (server/http_message.hpp).
#include "server/http_message.hpp"

#include <algorithm>
#include <cstdlib>

#include <zlib.h>
#include <boost/beast/core/string.hpp>

namespace geoslice::server {

namespace beast = boost::beast;

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

void HttpResponse::erase_header(std::string_view name) {
    headers.erase(
        std::remove_if(headers.begin(), headers.end(), [&](const auto& h) { return equalsNoCase(h.first, name); }),
        headers.end());
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

std::optional<Refusal> checkFraming(unsigned version,
                                    const std::vector<std::pair<std::string_view, std::string_view>>& fields) {
    std::size_t hosts = 0, encodings = 0, lengths = 0;
    std::string_view encoding;
    for (const auto& [name, value] : fields) {
        if (equalsNoCase(name, "Host")) ++hosts;
        if (equalsNoCase(name, "Content-Length")) ++lengths;
        if (equalsNoCase(name, "Transfer-Encoding")) {
            ++encodings;
            encoding = value;
        }
    }
    auto shown = [](std::string_view v) { return "'" + std::string(v.substr(0, 80)) + "'"; };
    if (encodings > 0) {
        if (version < 11)
            return Refusal{400, "Transfer-Encoding in an HTTP/1.0 request: its framing cannot be trusted"};
        std::string_view v = encoding;
        while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
        while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
        if (encodings > 1 || !equalsNoCase(v, "chunked"))
            return Refusal{501, "Transfer-Encoding " +
                                    (encodings > 1 ? std::string("given more than once") : shown(v)) +
                                    " is not supported: only a lone 'chunked' is"};
        if (lengths > 0)
            return Refusal{400, "both Transfer-Encoding and Content-Length: the body's length is ambiguous"};
    }
    if (version >= 11 && hosts != 1)
        return Refusal{400, hosts == 0 ? std::string("an HTTP/1.1 request must have a Host header")
                                       : "an HTTP/1.1 request must have one Host header, not " + std::to_string(hosts)};
    return std::nullopt;
}

std::size_t headerBlockEnd(std::string_view bytes, std::size_t from) {
    for (std::size_t i = bytes.find('\n', from); i != std::string_view::npos; i = bytes.find('\n', i + 1)) {
        if (i + 1 < bytes.size() && bytes[i + 1] == '\n') return i + 2;
        if (i + 2 < bytes.size() && bytes[i + 1] == '\r' && bytes[i + 2] == '\n') return i + 3;
    }
    return std::string_view::npos;
}

std::size_t findObsFold(std::string_view headerBlock) {
    // Empty lines before the request line are allowed (RFC 9112 2.2) and skipped.
    std::size_t start = 0;
    while (start < headerBlock.size() && (headerBlock[start] == '\r' || headerBlock[start] == '\n')) ++start;
    std::size_t line = 1;
    for (std::size_t i = headerBlock.find('\n', start); i != std::string_view::npos && i + 1 < headerBlock.size();
         i = headerBlock.find('\n', i + 1)) {
        ++line;
        if (headerBlock[i + 1] == ' ' || headerBlock[i + 1] == '\t') return line;
    }
    return 0;
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

bool willGzip(std::string_view contentType, std::size_t bodyBytes, bool clientAcceptsGzip) {
    return clientAcceptsGzip && bodyBytes >= kGzipMinBytes && compressibleType(contentType);
}

std::string gzipEtag(std::string_view etag) {
    if (etag.size() < 2 || etag.back() != '"') return std::string(etag);
    return std::string(etag.substr(0, etag.size() - 1)) + "-gzip\"";
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

}  // namespace geoslice::server
