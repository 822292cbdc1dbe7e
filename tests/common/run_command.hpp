// Runs a shell command for end-to-end tests and returns its exit code and stdout.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace geoslice::test {

struct CmdResult {
    int exitCode = -1;  // -1 when the command could not start or was killed by a signal
    std::string out;    // stdout only
};

inline CmdResult runCommand(const std::string& cmd) {
    CmdResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    const int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// The geoslice executable under test, with stderr discarded.
inline CmdResult runGeoslice(const std::string& args) {
    return runCommand(std::string(GEOSLICE_BINARY) + " " + args + " 2>/dev/null");
}

}  // namespace geoslice::test
