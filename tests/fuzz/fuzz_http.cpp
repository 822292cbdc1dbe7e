// libFuzzer target for the HTTP request side of the transport: the bytes are what a
// client sends on one connection (possibly several pipelined requests). Beast parses them
// with the server's limits; each request's target goes through parseTarget and its
// Accept-Encoding through acceptsGzip (server/http_message.hpp). Invariants checked:
// percent-decoding never lengthens text (path and parameters together are no longer than
// the target), and parsing the same target twice gives the same result.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>
#include <string_view>

#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>

#include "server/http_message.hpp"

namespace http = boost::beast::http;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace geoslice::server;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto check = [](std::string_view target) {
        std::string path, path2;
        std::multimap<std::string, std::string> params, params2;
        parseTarget(target, path, params);
        std::size_t decoded = path.size();
        for (const auto& [k, v] : params) decoded += k.size() + v.size();
        if (decoded > target.size()) std::abort();
        parseTarget(target, path2, params2);
        if (path2 != path || params2 != params) std::abort();
    };
    check(bytes);
    (void)acceptsGzip(bytes);
    (void)compressibleType(bytes);
    // The stream, request after request, as a connection reads it (bounded by the input).
    std::size_t offset = 0;
    for (int n = 0; n < 64 && offset < bytes.size(); ++n) {
        http::request_parser<http::string_body> parser;
        parser.header_limit(64 << 10);
        parser.body_limit(1 << 20);
        parser.eager(true);
        boost::beast::error_code ec;
        std::size_t used = 0;
        while (offset + used < bytes.size() && !parser.is_done()) {
            const std::size_t k =
                parser.put(boost::asio::buffer(bytes.data() + offset + used, bytes.size() - offset - used), ec);
            if (ec == http::error::need_more) break;
            if (ec) return 0;
            if (k == 0) break;
            used += k;
        }
        if (!parser.is_done()) return 0;
        const auto& msg = parser.get();
        const auto target = msg.target();
        check(std::string_view(target.data(), target.size()));
        const auto enc = msg[http::field::accept_encoding];
        (void)acceptsGzip(std::string_view(enc.data(), enc.size()));
        offset += used;
    }
    return 0;
}
