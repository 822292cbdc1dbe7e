// Raw bytes to a server on loopback and what comes back, for requests no HTTP client
// library would send (invalid UTF-8 in the request line, smuggling probes, folded headers).
// Every read has a deadline; nothing here retries.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace geoslice::test {

// Sends `bytes` on a new connection to 127.0.0.1:port, half-closes when `halfClose`, then
// reads until the server closes or `timeoutMs` pass. `closed` says whether the server
// closed the connection within that time.
struct RawExchange {
    std::string reply;
    bool connected = false;
    bool closed = false;
};

inline RawExchange rawExchange(int port, std::string_view bytes, int timeoutMs = 5000, bool halfClose = false) {
    RawExchange out;
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return out;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
        close(fd);
        return out;
    }
    out.connected = true;
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;
        sent += std::size_t(n);
    }
    if (halfClose) shutdown(fd, SHUT_WR);
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
    char buf[16384];
    while (true) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now()).count();
        if (left <= 0) break;
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, int(left)) <= 0) break;
        const ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n <= 0) {
            out.closed = true;
            break;
        }
        out.reply.append(buf, std::size_t(n));
    }
    close(fd);
    return out;
}

// The status codes of the HTTP/1.x answers in `reply`, in order (a status line is
// "HTTP/1.x NNN" at the start of the reply or after a body; bodies here are JSON, so the
// search for "HTTP/1." at a line start is exact enough for tests).
inline std::vector<int> statusCodes(std::string_view reply) {
    std::vector<int> codes;
    for (std::size_t at = 0; (at = reply.find("HTTP/1.", at)) != std::string_view::npos; at += 7) {
        if (at != 0 && reply[at - 1] != '\n' && reply[at - 1] != '}') continue;
        if (at + 12 <= reply.size()) codes.push_back(std::atoi(std::string(reply.substr(at + 9, 3)).c_str()));
    }
    return codes;
}

// The body of the first answer in `reply` (after its empty line), "" when none: its
// Content-Length bytes when the head gives one (a detail may itself say "HTTP/1.0"), else up
// to the next status line.
inline std::string firstBody(std::string_view reply) {
    const auto at = reply.find("\r\n\r\n");
    if (at == std::string_view::npos) return {};
    std::string_view rest = reply.substr(at + 4);
    std::string head(reply.substr(0, at + 2));
    for (char& c : head) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (const auto cl = head.find("\r\ncontent-length:"); cl != std::string::npos)
        return std::string(rest.substr(0, std::strtoull(head.c_str() + cl + 17, nullptr, 10)));
    const auto next = rest.find("HTTP/1.");
    return std::string(rest.substr(0, next));
}

}  // namespace geoslice::test
