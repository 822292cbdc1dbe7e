// Raw bytes to a server on loopback and what comes back, for requests no HTTP client
// library would send (invalid UTF-8 in the request line, smuggling probes, folded headers).
// Every read has a deadline; nothing here retries a request (an interrupted system call
// is resumed).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
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
        if (n < 0 && errno == EINTR) continue;
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
        // A signal (libFuzzer's timer every -timeout/2 s, a profiler's) interrupts poll and
        // recv with EINTR: wait again, never take it for a timeout or a close.
        pollfd p{fd, POLLIN, 0};
        const int ready = poll(&p, 1, int(left));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) break;
        const ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n < 0 && errno == EINTR) continue;
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

// The body of the first answer in `reply` (its Content-Length bytes after the empty line),
// "" when none.
inline std::string firstBody(std::string_view reply) {
    const auto at = reply.find("\r\n\r\n");
    if (at == std::string_view::npos) return {};
    const std::string_view head = reply.substr(0, at);
    std::size_t length = reply.size() - at - 4;
    for (std::size_t line = head.find("\r\n"); line != std::string_view::npos; line = head.find("\r\n", line + 2)) {
        constexpr std::string_view kName = "content-length:";
        std::string name(head.substr(line + 2, kName.size()));
        for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (name == kName)
            length = std::strtoul(std::string(head.substr(line + 2 + kName.size(), 20)).c_str(), nullptr, 10);
    }
    return std::string(reply.substr(at + 4, length));
}

}  // namespace geoslice::test
