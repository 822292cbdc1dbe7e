// `geoslice serve` as a separate process for end-to-end tests that must survive what they
// send (a crash of the server is then a failed check, not a dead test runner), or that
// send it signals. Starts the executable on a free loopback port, reads the port from its
// first stdout line, keeps its stderr in a log file, and kills it on destruction.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <httplib.h>

namespace geoslice::test {

class ServeProcess {
public:
    using Env = std::vector<std::pair<std::string, std::string>>;

    // Starts `geoslice serve --host 127.0.0.1 --port 0 ARGS...` with `env` added; nullptr
    // when it did not print its port within 60 s (the log then says why). `inChild` runs in
    // the forked child just before exec (after its stdout and stderr are set up): setrlimit,
    // dropping root; it must only make async-signal-safe calls.
    static std::unique_ptr<ServeProcess> start(const std::vector<std::string>& args, const Env& env = {},
                                               const std::function<void()>& inChild = {}) {
        auto p = std::unique_ptr<ServeProcess>(new ServeProcess());
        p->log_ = std::filesystem::temp_directory_path() /
                  ("geoslice_serve_" + std::to_string(getpid()) + "_" + std::to_string(counter()++) + ".log");
        int out[2];
        if (pipe(out) != 0) return nullptr;
        std::vector<std::string> argv{GEOSLICE_BINARY, "serve", "--host", "127.0.0.1", "--port", "0"};
        argv.insert(argv.end(), args.begin(), args.end());
        const pid_t pid = fork();
        if (pid < 0) return nullptr;
        if (pid == 0) {
            dup2(out[1], 1);
            close(out[0]);
            const int err = open(p->log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (err >= 0) dup2(err, 2);
            for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
            if (inChild) inChild();
            std::vector<char*> cargv;
            for (auto& a : argv) cargv.push_back(a.data());
            cargv.push_back(nullptr);
            execv(GEOSLICE_BINARY, cargv.data());
            _exit(127);
        }
        close(out[1]);
        p->pid_ = pid;
        p->out_ = out[0];
        // "geoslice serving on http://127.0.0.1:PORT ..."
        std::string line;
        char c;
        while (line.find("serving on") == std::string::npos) {
            line.clear();
            while (read(p->out_, &c, 1) == 1 && c != '\n') line += c;
            if (line.empty()) return nullptr;
        }
        const auto at = line.find("127.0.0.1:");
        if (at == std::string::npos) return nullptr;
        p->port_ = std::atoi(line.c_str() + at + 10);
        return p;
    }

    ~ServeProcess() {
        if (pid_ > 0 && running()) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        if (out_ >= 0) close(out_);
        std::error_code ec;
        std::filesystem::remove(log_, ec);
    }

    int port() const { return port_; }
    pid_t pid() const { return pid_; }
    httplib::Client client(int readTimeoutS = 30) const {
        httplib::Client c("127.0.0.1", port_);
        c.set_read_timeout(readTimeoutS, 0);
        c.set_connection_timeout(5, 0);
        return c;
    }
    // True once /readyz says 200 (within `timeout`).
    bool waitReady(std::chrono::milliseconds timeout = std::chrono::milliseconds(60000)) const {
        const auto until = std::chrono::steady_clock::now() + timeout;
        auto c = client(5);
        while (std::chrono::steady_clock::now() < until) {
            auto r = c.Get("/readyz");
            if (r && r->status == 200) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    }
    bool running() {
        if (exited_) return false;
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            exited_ = true;
            status_ = status;
            return false;
        }
        return true;
    }
    // SIGTERM, then waits up to `timeout` for the exit; returns the wait status, or -1
    // when it did not end in time (it is then killed).
    int terminate(std::chrono::milliseconds timeout, double* tookMs = nullptr) {
        const auto t0 = std::chrono::steady_clock::now();
        kill(pid_, SIGTERM);
        while (std::chrono::steady_clock::now() - t0 < timeout) {
            if (!running()) {
                if (tookMs)
                    *tookMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                return status_;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        exited_ = true;
        return -1;
    }
    // The wait status once it exited (running() false).
    int status() const { return status_; }
    std::string log() const {
        std::ifstream in(log_);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    }

private:
    ServeProcess() = default;
    static int& counter() {
        static int n = 0;
        return n;
    }
    pid_t pid_ = -1;
    int out_ = -1;
    int port_ = 0;
    bool exited_ = false;
    int status_ = 0;
    std::filesystem::path log_;
};

// Milliseconds since t0 on the steady clock.
inline double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The fastest of `tries` GETs of /healthz, ms (the machine is shared: one slow answer is
// scheduling noise, a server that is pinned or dead is slow or absent every time).
inline double healthzMs(const ServeProcess& s, int tries = 5) {
    auto c = s.client(10);
    double best = 1e9;
    for (int i = 0; i < tries; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        auto r = c.Get("/healthz");
        const double ms = msSince(t0);
        if (r && r->status == 200) best = std::min(best, ms);
    }
    return best;
}

}  // namespace geoslice::test
