// Hostile clients against the real `geoslice serve` process on loopback: slowloris,
// pipelining, connect bursts, a second instance on the same port, idle keep-alive
// connections, header deadlines, slow readers and the connection cap. Every loop has a
// count and a time bound; all traffic goes to 127.0.0.1.
//
// Responses are parsed with Beast (the client side of the same library the server uses);
// plain sockets send the hostile bytes.
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// `geoslice serve` in a child process on a free port (or `port`), demo model, no GL.
class ServerProcess {
public:
    explicit ServerProcess(std::vector<std::string> extra = {}, int port = 0) {
        int out[2], err[2];
        if (pipe(out) != 0 || pipe(err) != 0) return;
        pid_ = fork();
        if (pid_ == 0) {
            dup2(out[1], 1);
            dup2(err[1], 2);
            close(out[0]);
            close(err[0]);
            std::vector<std::string> args = {
                GEOSLICE_BINARY, "serve",     "--port", std::to_string(port), "--host", "127.0.0.1",   "--gl",
                "none",          "--workers", "1",      "--demo-triangles",   "20000",  "--log-level", "warn"};
            args.insert(args.end(), extra.begin(), extra.end());
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            execv(GEOSLICE_BINARY, argv.data());
            _exit(127);
        }
        close(out[1]);
        close(err[1]);
        outFd_ = out[0];
        errFd_ = err[0];
        // The banner names the port: "geoslice serving on http://127.0.0.1:PORT  (...".
        std::string line;
        const auto t0 = Clock::now();
        while (msSince(t0) < 60000) {
            pollfd p{outFd_, POLLIN, 0};
            if (poll(&p, 1, 1000) <= 0) continue;
            char c;
            if (read(outFd_, &c, 1) != 1) break;
            if (c != '\n') {
                line += c;
                continue;
            }
            if (const auto at = line.find("serving on http://"); at != std::string::npos) {
                const auto colon = line.find(':', at + 18);
                port_ = std::stoi(line.substr(colon + 1));
                break;
            }
            line.clear();
        }
    }
    ~ServerProcess() {
        if (pid_ > 0 && !exited_) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        if (outFd_ >= 0) close(outFd_);
        if (errFd_ >= 0) close(errFd_);
    }
    int port() const { return port_; }
    pid_t pid() const { return pid_; }
    // Polls /readyz until the demo model is in (bounded: 60 s).
    bool waitReady();
    // Waits (bounded) for exit; the exit status, or nullopt when it is still running.
    std::optional<int> waitExit(double ms) {
        const auto t0 = Clock::now();
        while (msSince(t0) < ms) {
            int status = 0;
            if (waitpid(pid_, &status, WNOHANG) == pid_) {
                exited_ = true;
                return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return std::nullopt;
    }
    std::string stderrText() {
        std::string s;
        char buf[4096];
        while (true) {
            pollfd p{errFd_, POLLIN, 0};
            if (poll(&p, 1, 0) <= 0) break;
            const ssize_t n = read(errFd_, buf, sizeof buf);
            if (n <= 0) break;
            s.append(buf, std::size_t(n));
        }
        return s;
    }
    // User + system CPU seconds of the process (/proc/PID/stat fields 14 and 15).
    double cpuSeconds() const {
        std::ifstream f("/proc/" + std::to_string(pid_) + "/stat");
        std::string stat((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        std::istringstream rest(stat.substr(stat.rfind(')') + 2));
        std::string field;
        long long utime = 0, stime = 0;
        for (int i = 3; i <= 15 && rest >> field; ++i) {
            if (i == 14) utime = std::stoll(field);
            if (i == 15) stime = std::stoll(field);
        }
        return double(utime + stime) / double(sysconf(_SC_CLK_TCK));
    }

private:
    pid_t pid_ = -1;
    int port_ = 0, outFd_ = -1, errFd_ = -1;
    bool exited_ = false;
};

// A raw blocking socket to 127.0.0.1:port (-1 on failure).
int connectTo(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

bool sendAll(int fd, const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
        const ssize_t n = send(fd, s.data() + done, s.size() - done, MSG_NOSIGNAL);
        if (n <= 0) return false;
        done += std::size_t(n);
    }
    return true;
}

// One keep-alive client connection (Beast parses the answers).
class Client {
public:
    explicit Client(int port) : socket_(ioc_) {
        beast::error_code ec;
        socket_.connect({net::ip::make_address("127.0.0.1"), std::uint16_t(port)}, ec);
        ok_ = !ec;
        // Bound every read: a stuck server fails the test instead of hanging it.
        timeval tv{30, 0};
        setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    }
    bool ok() const { return ok_; }
    bool send(const std::string& bytes) { return sendAll(socket_.native_handle(), bytes); }
    std::optional<http::response<http::string_body>> read() {
        http::response_parser<http::string_body> p;
        p.body_limit(64 << 20);
        beast::error_code ec;
        http::read(socket_, buffer_, p, ec);
        if (ec) return std::nullopt;
        return p.release();
    }
    std::optional<http::response<http::string_body>> get(const std::string& target) {
        if (!send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n")) return std::nullopt;
        return read();
    }
    int fd() { return socket_.native_handle(); }

private:
    net::io_context ioc_;
    net::ip::tcp::socket socket_;
    beast::flat_buffer buffer_;
    bool ok_ = false;
};

// One request on a fresh connection: (status, milliseconds from connect to answer).
std::pair<int, double> timedGet(int port, const std::string& target) {
    const auto t0 = Clock::now();
    Client c(port);
    if (!c.ok()) return {-1, msSince(t0)};
    auto r = c.get(target);
    return {r ? int(r->result_int()) : -1, msSince(t0)};
}

double metric(int port, const std::string& name) {
    Client c(port);
    auto r = c.get("/metrics");
    if (!r) return -1.0;
    const std::string& b = r->body();
    const auto at = b.find("\n" + name + " ");
    return at == std::string::npos ? -1.0 : std::stod(b.substr(at + name.size() + 2));
}

bool ServerProcess::waitReady() {
    const auto t0 = Clock::now();
    while (port_ > 0 && msSince(t0) < 60000) {
        if (timedGet(port_, "/readyz").first == 200) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

const std::string kSection = "/v1/models/demo/section.png?plane=0,1,0,-3388846&size=256x128";

// 300 connections that send a header byte every second: /healthz and a section are still
// answered at once, and SIGTERM ends the process within 5 s while they keep trickling.
TEST(Transport, SlowlorisStarvesNothingAndSigtermEndsInTime) {
    ServerProcess srv;
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    ASSERT_EQ(timedGet(srv.port(), "/healthz").first, 200);
    const std::string header =
        "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
    constexpr int kSockets = 300;
    std::vector<int> fds;
    for (int i = 0; i < kSockets; ++i) {
        const int fd = connectTo(srv.port());
        ASSERT_GE(fd, 0) << "connect " << i;
        fds.push_back(fd);
    }
    std::atomic<bool> stop{false};
    std::atomic<int> bytesSent{0};
    std::thread trickle([&] {
        // One byte per socket per second, for at most 12 s (bounded).
        for (std::size_t k = 0; k < header.size() && k < 12 && !stop; ++k) {
            for (int fd : fds)
                if (send(fd, &header[k], 1, MSG_NOSIGNAL) == 1) ++bytesSent;
            for (int t = 0; t < 100 && !stop; ++t) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    const double open = metric(srv.port(), "geoslice_connections_open");
    EXPECT_GE(open, double(kSockets)) << "the slow sockets are held open by the server";
    std::vector<double> healthMs, sectionMs;
    for (int i = 0; i < 5; ++i) {
        const auto [hs, hms] = timedGet(srv.port(), "/healthz");
        // A plane never asked before: a real render each time.
        const auto [ss, sms] = timedGet(srv.port(), "/v1/models/demo/section.png?plane=0,1,0," +
                                                        std::to_string(-3388000 - 37 * i) + "&size=256x128");
        EXPECT_EQ(hs, 200);
        EXPECT_EQ(ss, 200);
        healthMs.push_back(hms);
        sectionMs.push_back(sms);
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    std::printf(
        "slowloris %d sockets (%.0f open): /healthz median %.2f ms max %.2f ms; section median %.2f ms max "
        "%.2f ms\n",
        kSockets, open, median(healthMs), *std::max_element(healthMs.begin(), healthMs.end()), median(sectionMs),
        *std::max_element(sectionMs.begin(), sectionMs.end()));
    // Starvation, not speed (the figures are printed above; benchmarks time, tests do not):
    // slowloris sockets that starved the server left requests waiting for the 10 s header
    // deadline, far above this bound.
    EXPECT_LT(median(healthMs), 2000.0);
    EXPECT_LT(median(sectionMs), 2000.0);
    const auto t0 = Clock::now();
    kill(srv.pid(), SIGTERM);
    const auto code = srv.waitExit(10000);
    const double termMs = msSince(t0);
    stop = true;
    trickle.join();
    for (int fd : fds) close(fd);
    ASSERT_TRUE(code) << "still running 10 s after SIGTERM";
    EXPECT_EQ(*code, 0);
    EXPECT_LT(termMs, 5000.0);
    std::printf("SIGTERM with %d slow sockets open: exited in %.0f ms\n", kSockets, termMs);
}

// A request header must arrive whole within the header deadline, however it trickles.
TEST(Transport, HeaderDeadlineIsATotalNotPerRead) {
    ServerProcess srv({"--header-timeout-ms", "1000"});
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    const int fd = connectTo(srv.port());
    ASSERT_GE(fd, 0);
    const auto t0 = Clock::now();
    const std::string header = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
    double closedAfter = -1.0;
    for (std::size_t k = 0; k < header.size() && msSince(t0) < 5000; ++k) {
        if (send(fd, &header[k], 1, MSG_NOSIGNAL) != 1) break;
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, 100) > 0) {  // readable: the server closed (EOF) or answered
            char c;
            if (recv(fd, &c, 1, 0) <= 0) {
                closedAfter = msSince(t0);
                break;
            }
        }
    }
    close(fd);
    std::printf("a header trickled at 10 bytes/s was cut after %.0f ms (deadline 1000 ms)\n", closedAfter);
    EXPECT_GE(closedAfter, 900.0);
    EXPECT_LT(closedAfter, 2000.0);
}

// 200 pipelined requests on one connection, sent at once: 200 answers, in order. A mix of
// answers made at once (404 naming the request, /healthz) and renders.
TEST(Transport, PipelinedRequestsAnsweredInOrder) {
    ServerProcess srv;
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    Client c(srv.port());
    ASSERT_TRUE(c.ok());
    std::string all;
    constexpr int kRequests = 200;
    for (int i = 0; i < kRequests; ++i) {
        std::string target = "/v1/models/m" + std::to_string(i);
        if (i % 10 == 3) target = "/healthz";
        if (i % 25 == 7)
            target = "/v1/models/demo/section.png?plane=0,1,0," + std::to_string(-3388000 - i) + "&size=128x64";
        all += "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    }
    ASSERT_TRUE(c.send(all));
    int answered = 0, inOrder = 0;
    for (int i = 0; i < kRequests; ++i) {
        auto r = c.read();
        if (!r) break;
        ++answered;
        bool ok = false;
        if (i % 25 == 7)
            ok = r->result_int() == 200 && r->body().rfind("\x89PNG", 0) == 0;
        else if (i % 10 == 3)
            ok = r->result_int() == 200 && r->body().find("\"ok\"") != std::string::npos;
        else
            ok = r->result_int() == 404 && r->body().find("'m" + std::to_string(i) + "'") != std::string::npos;
        inOrder += ok;
        EXPECT_TRUE(ok) << "answer " << i << ": " << r->result_int() << " " << r->body().substr(0, 200);
    }
    std::printf("pipelining: %d requests sent at once, %d answered, %d in order\n", kRequests, answered, inOrder);
    EXPECT_EQ(answered, kRequests);
    EXPECT_EQ(inOrder, kRequests);
}

// 500 connects at once: none waits for a SYN retransmission (1 s), and each is answered.
TEST(Transport, ConnectBurstWithoutSynStalls) {
    ServerProcess srv;
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    constexpr int kConnections = 500;
    std::vector<int> fds(kConnections, -1);
    std::vector<double> connectMs(kConnections, -1.0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(srv.port()));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const auto t0 = Clock::now();
    for (int i = 0; i < kConnections; ++i) {
        fds[i] = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
        ASSERT_GE(fds[i], 0);
        const int rc = connect(fds[i], reinterpret_cast<sockaddr*>(&a), sizeof a);
        if (rc == 0) connectMs[i] = msSince(t0);
        ASSERT_TRUE(rc == 0 || errno == EINPROGRESS) << i;
    }
    // Each connect completes when the socket becomes writable (bounded: 5 s).
    while (msSince(t0) < 5000) {
        std::vector<pollfd> p;
        std::vector<int> which;
        for (int i = 0; i < kConnections; ++i)
            if (connectMs[i] < 0) {
                p.push_back({fds[i], POLLOUT, 0});
                which.push_back(i);
            }
        if (p.empty()) break;
        if (poll(p.data(), p.size(), 50) <= 0) continue;
        for (std::size_t k = 0; k < p.size(); ++k)
            if (p[k].revents) connectMs[which[k]] = msSince(t0);
    }
    int connected = 0;
    for (int i = 0; i < kConnections; ++i) {
        int err = 0;
        socklen_t len = sizeof err;
        getsockopt(fds[i], SOL_SOCKET, SO_ERROR, &err, &len);
        connected += connectMs[i] >= 0 && err == 0;
    }
    const double slowest = *std::max_element(connectMs.begin(), connectMs.end());
    // Every connection gets an answer (the server accepted all of them).
    int answered = 0;
    for (int i = 0; i < kConnections; ++i) {
        const int flags = fcntl(fds[i], F_GETFL);
        fcntl(fds[i], F_SETFL, flags & ~O_NONBLOCK);
        timeval tv{10, 0};
        setsockopt(fds[i], SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
        sendAll(fds[i], "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
    }
    for (int i = 0; i < kConnections; ++i) {
        std::string got;
        char buf[1024];
        ssize_t n;
        while (got.size() < 4096 && (n = recv(fds[i], buf, sizeof buf, 0)) > 0) got.append(buf, std::size_t(n));
        answered += got.rfind("HTTP/1.1 200", 0) == 0;
        close(fds[i]);
    }
    std::printf("burst of %d connects: %d connected, slowest %.1f ms; %d answered\n", kConnections, connected, slowest,
                answered);
    EXPECT_EQ(connected, kConnections);
    EXPECT_LT(slowest, 1000.0) << "a connect waited for a SYN retransmission";
    EXPECT_EQ(answered, kConnections);
}

// A second server on the same port is refused with a clear message and a non-zero exit;
// the first keeps serving.
TEST(Transport, SecondInstanceOnTheSamePortIsRefused) {
    ServerProcess first;
    ASSERT_GT(first.port(), 0);
    ASSERT_TRUE(first.waitReady());
    ServerProcess second({}, first.port());
    EXPECT_EQ(second.port(), 0) << "the second instance says it is serving";
    const auto code = second.waitExit(30000);
    ASSERT_TRUE(code) << "the second instance did not exit";
    EXPECT_NE(*code, 0);
    const std::string err = second.stderrText();
    EXPECT_NE(err.find("already in use"), std::string::npos) << err;
    std::printf("second instance: exit %d, \"%s\"\n", *code, err.substr(0, err.find('\n')).c_str());
    EXPECT_EQ(timedGet(first.port(), "/healthz").first, 200);
}

// 200 idle keep-alive connections cost no CPU: the server's CPU time over 5 s is under
// 50 ms (1 % of a core; the previous HTTP layer polled each idle connection, ~0.17 % of a
// core each, 34 % for 200), and every connection still answers afterwards.
TEST(Transport, IdleKeepAliveConnectionsCostNothing) {
    ServerProcess srv({"--keep-alive-ms", "60000"});
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    constexpr int kConnections = 200;
    std::vector<std::unique_ptr<Client>> clients;
    for (int i = 0; i < kConnections; ++i) {
        clients.push_back(std::make_unique<Client>(srv.port()));
        ASSERT_TRUE(clients.back()->ok());
        auto r = clients.back()->get("/healthz");
        ASSERT_TRUE(r);
        ASSERT_EQ(r->result_int(), 200);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the loader and probes are done
    const double cpu0 = srv.cpuSeconds();
    std::this_thread::sleep_for(std::chrono::seconds(5));
    const double cpu = srv.cpuSeconds() - cpu0;
    int stillOpen = 0;
    for (auto& c : clients) {
        auto r = c->get("/healthz");
        stillOpen += r && r->result_int() == 200;
    }
    std::printf("%d idle keep-alive connections for 5 s: server CPU %.3f s (%.2f %% of a core); %d still answer\n",
                kConnections, cpu, cpu / 5.0 * 100.0, stillOpen);
    // Resolution: one clock tick (10 ms).
    EXPECT_LT(cpu, 0.05);
    EXPECT_EQ(stillOpen, kConnections);
}

// A client that never reads its answers is cut off by the send deadline: it pipelines
// requests for ~40 MB of answers and reads nothing.
TEST(Transport, SlowReaderBoundedBySendDeadline) {
    ServerProcess srv({"--send-timeout-ms", "1000"});
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    Client reader(srv.port());
    ASSERT_TRUE(reader.ok());
    const int small = 4096;
    setsockopt(reader.fd(), SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    std::string all;
    for (int i = 0; i < 2000; ++i) all += "GET /openapi.json HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    // Bounded: the server stops reading once its pipeline buffer is full, so send in
    // non-blocking mode and keep what does not fit.
    fcntl(reader.fd(), F_SETFL, fcntl(reader.fd(), F_GETFL) | O_NONBLOCK);
    (void)send(reader.fd(), all.data(), all.size(), MSG_NOSIGNAL);
    const auto t0 = Clock::now();
    double timeouts = 0;
    while (msSince(t0) < 8000 && (timeouts = metric(srv.port(), "geoslice_connection_timeouts_total")) < 1.0)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::printf("a client that reads nothing was cut off after %.0f ms (send deadline 1000 ms)\n", msSince(t0));
    EXPECT_GE(timeouts, 1.0);
    EXPECT_EQ(timedGet(srv.port(), "/healthz").first, 200);
}

// At the connection cap a new client is served: the connection that has waited longest
// for a request (here a slow header) is closed for it.
TEST(Transport, ConnectionCapClosesTheLongestWaitingForANewClient) {
    ServerProcess srv({"--max-connections", "32"});
    ASSERT_GT(srv.port(), 0);
    ASSERT_TRUE(srv.waitReady());
    std::vector<int> fds;
    for (int i = 0; i < 40; ++i) {
        const int fd = connectTo(srv.port());
        ASSERT_GE(fd, 0);
        sendAll(fd, "GET /healthz HTTP/1.1\r\n");  // and nothing more
        fds.push_back(fd);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto [status, ms] = timedGet(srv.port(), "/healthz");
    EXPECT_EQ(status, 200);
    const double evicted = metric(srv.port(), "geoslice_connections_evicted_total");
    const double open = metric(srv.port(), "geoslice_connections_open");
    std::printf("cap 32, 40 slow headers: a new client answered in %.1f ms, %.0f evicted, %.0f open\n", ms, evicted,
                open);
    EXPECT_GE(evicted, 8.0);
    EXPECT_LE(open, 33.0);
    for (int fd : fds) close(fd);
}

}  // namespace
