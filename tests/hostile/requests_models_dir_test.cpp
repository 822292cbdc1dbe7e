// The models and bake directories as the outside campaign left them: a bake that fails on a
// full disk or past a file size limit, odd entries in the models directory (a FIFO, symlink
// loops, a 2 GiB sparse file...), and corrupt packages moved aside again and again. Each
// against the real `geoslice serve` process (tests/common/serve_process.hpp).
#include <grp.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/common/serve_process.hpp"

namespace geoslice::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// A fresh directory under the temp dir, removed (and unmounted, when a test mounted on it) at
// the end.
struct Scratch {
    fs::path path;
    explicit Scratch(const std::string& name)
        : path(fs::temp_directory_path() / ("geoslice_" + name + "_" + std::to_string(getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

// `geoslice generate` into `out` (a synthetic mine of about `triangles` triangles).
void generate(const fs::path& out, int triangles) {
    const std::string cmd = std::string(GEOSLICE_BINARY) + " generate --triangles " + std::to_string(triangles) +
                            " --out " + out.string() + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
}

// A closed, outward tetrahedron, 10 m edges: the smallest model there is (a few hundred
// bytes of OBJ, a package of about 75 KiB).
void writeTetra(const fs::path& out) {
    std::ofstream(out) << "o Rock\nv 0 0 500\nv 10 0 500\nv 0 10 500\nv 0 0 510\n"
                          "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

json getJson(const ServeProcess& s, const std::string& path, int* status = nullptr) {
    auto r = s.client(30).Get(path.c_str());
    if (!r) return json();
    if (status) *status = r->status;
    return json::parse(r->body, nullptr, false);
}

// The entry of `list` (a /readyz array) whose `key` is `value`, or null.
json entryOf(const json& list, const std::string& key, const std::string& value) {
    if (list.is_array())
        for (const auto& e : list)
            if (e.contains(key) && e[key] == value) return e;
    return json();
}

// Every file under `dir` whose name ends with `suffix`.
std::vector<std::string> filesEndingWith(const fs::path& dir, const std::string& suffix) {
    std::vector<std::string> out;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().string().ends_with(suffix)) out.push_back(it->path().string());
    return out;
}

// What a bake that cannot write must leave: a served model (from memory, no "baked" in its
// summary), a /readyz warning naming it and `why`, no .partial file and no half package, and
// the model that fits served too.
void expectServedUnbaked(const ServeProcess& s, const fs::path& bakeDir, const std::string& why) {
    int status = 0;
    const json ready = getJson(s, "/readyz", &status);
    EXPECT_EQ(status, 200) << ready.dump(2);
    EXPECT_EQ(ready["models"]["loaded"], 2) << ready.dump(2);
    EXPECT_TRUE(ready["models"]["failed"].empty()) << ready.dump(2);
    const json warning = entryOf(ready["models"]["warnings"], "id", "mine");
    ASSERT_TRUE(warning.is_object()) << ready.dump(2);
    const std::string text = warning["warning"];
    EXPECT_NE(text.find(why), std::string::npos) << text;
    EXPECT_NE(text.find("served from memory"), std::string::npos) << text;
    EXPECT_NE(text.find("mesh.glb"), std::string::npos) << text;  // names the file it could not write
    const json mine = getJson(s, "/v1/models/mine", &status);
    EXPECT_EQ(status, 200) << mine.dump();
    EXPECT_FALSE(mine.contains("baked"));
    // It answers: a section through the middle of its bounds is a PNG.
    const double y = 0.5 * (mine["bounds"]["min"][1].get<double>() + mine["bounds"]["max"][1].get<double>());
    auto png =
        s.client(60).Get(("/v1/models/mine/section.png?plane=0,1,0," + std::to_string(-y) + "&size=128x64").c_str());
    ASSERT_TRUE(png);
    EXPECT_EQ(png->status, 200) << png->body;
    // The small model fits the limit and is baked.
    const json tiny = getJson(s, "/v1/models/tiny", &status);
    EXPECT_EQ(status, 200) << tiny.dump();
    EXPECT_TRUE(tiny.contains("baked")) << tiny.dump();
    EXPECT_TRUE(filesEndingWith(bakeDir, ".partial").empty());
    EXPECT_FALSE(fs::exists(bakeDir / "mine")) << "the failed bake's package folder is left behind";
    EXPECT_NE(s.log().find("event=bake_failed id=mine"), std::string::npos) << s.log();
}

// Item 1, always available: RLIMIT_FSIZE on the server process. Its bake's writes past
// 256 KiB fail with EFBIG (SIGXFSZ is ignored by the server: it would otherwise be killed).
// The mine's mesh.glb is about 520 KiB; the tetrahedron's largest file (its ID texture, which
// has a minimum size) about 70 KiB.
TEST(HostileFiles, BakePastAFileSizeLimitServesFromMemory) {
    Scratch dir("bake_fsize");
    fs::create_directories(dir.path / "models");
    generate(dir.path / "models" / "mine.glb", 20000);  // mesh.glb of about 0.5 MiB
    writeTetra(dir.path / "models" / "tiny.obj");
    const fs::path bake = dir.path / "bake";
    const std::vector<std::string> args = {"--gl",       "none",        "--models",  (dir.path / "models").string(),
                                           "--bake-dir", bake.string(), "--workers", "1"};
    {
        auto s = ServeProcess::start(args, {}, [] {
            const rlimit limit{256 << 10, 256 << 10};
            setrlimit(RLIMIT_FSIZE, &limit);
        });
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady()) << s->log();
        EXPECT_TRUE(s->running()) << "killed by SIGXFSZ? status " << s->status();
        expectServedUnbaked(*s, bake, "File too large");
        s->terminate(std::chrono::milliseconds(10000));
    }
    // Without the limit the next start bakes it: nothing of the failed bake was in the way.
    auto again = ServeProcess::start(args);
    ASSERT_NE(again, nullptr);
    ASSERT_TRUE(again->waitReady()) << again->log();
    int status = 0;
    const json mine = getJson(*again, "/v1/models/mine", &status);
    EXPECT_EQ(status, 200);
    EXPECT_TRUE(mine.contains("baked")) << again->log();
    EXPECT_TRUE(getJson(*again, "/readyz")["models"]["warnings"].empty());
    again->terminate(std::chrono::milliseconds(10000));
}

// Item 1 on a real full disk: a 256 KiB tmpfs as the bake dir (root only: mount(2) needs
// CAP_SYS_ADMIN; skipped, saying why, elsewhere). The tetrahedron's package takes about
// 100 KiB of it; the mine's mesh.glb alone (520 KiB) does not fit.
TEST(HostileFiles, BakeOnAFullDiskServesFromMemory) {
    Scratch dir("bake_full_disk");
    fs::create_directories(dir.path / "models");
    fs::create_directories(dir.path / "bake");
    const fs::path bake = dir.path / "bake";
    if (mount("tmpfs", bake.c_str(), "tmpfs", 0, "size=256k") != 0)
        GTEST_SKIP() << "cannot mount a 256 KiB tmpfs on " << bake << " (" << std::strerror(errno)
                     << "): needs root with CAP_SYS_ADMIN; BakePastAFileSizeLimitServesFromMemory covers the same path";
    struct Unmount {
        fs::path at;
        ~Unmount() { umount2(at.c_str(), MNT_DETACH); }
    } unmount{bake};
    generate(dir.path / "models" / "mine.glb", 20000);
    writeTetra(dir.path / "models" / "tiny.obj");
    auto s = ServeProcess::start(
        {"--gl", "none", "--models", (dir.path / "models").string(), "--bake-dir", bake.string(), "--workers", "1"});
    ASSERT_NE(s, nullptr);
    ASSERT_TRUE(s->waitReady()) << s->log();
    expectServedUnbaked(*s, bake, "No space left on device");
    s->terminate(std::chrono::milliseconds(10000));
}

// Item 2: odd entries in the models directory. Each is named in the log and in /readyz with
// the reason, none blocks or slows loading (a FIFO is never opened for reading; a sparse
// 2 GiB file is refused from its size, or with a larger limit from its first bytes).
TEST(HostileFiles, OddEntriesInTheModelsDirAreNamedAndNeverBlock) {
    Scratch dir("odd_entries");
    const fs::path models = dir.path / "models";
    fs::create_directories(models);
    writeTetra(models / "good.obj");
    ASSERT_EQ(mkfifo((models / "pipe.obj").c_str(), 0644), 0) << std::strerror(errno);
    fs::create_symlink("loop-b.obj", models / "loop-a.obj");
    fs::create_symlink("loop-a.obj", models / "loop-b.obj");
    fs::create_symlink("nowhere.obj", models / "dangling.obj");
    fs::create_directories(models / "x.obj");
    fs::create_directories(models / "pkg");
    std::ofstream(models / "pkg" / "mesh.glb") << "glTF";  // a package folder without its manifest
    writeTetra(models / "noread.obj");
    fs::permissions(models / "noread.obj", fs::perms::none);
    { std::ofstream big(models / "big.obj"); }
    fs::resize_file(models / "big.obj", std::uintmax_t(2) << 30);  // sparse: no blocks written
    ASSERT_EQ(fs::file_size(models / "big.obj"), std::uintmax_t(2) << 30);
    writeTetra(models / "bad name.obj");

    // Root reads any file: the server then runs as nobody, so that the unreadable file is
    // unreadable to it (the test's files are world-readable, the directories searchable).
    const bool root = geteuid() == 0;
    auto asNobody = [root] {
        if (!root) return;
        setgroups(0, nullptr);
        if (setgid(65534) != 0 || setuid(65534) != 0) _exit(126);
    };
    struct Expected {
        std::string entry, reason;
    };
    const std::vector<Expected> expected = {
        {"pipe.obj", "FIFO"},
        {"loop-a.obj", "symlink loop"},
        {"loop-b.obj", "symlink loop"},
        {"dangling.obj", "dangling symlink"},
        {"x.obj", "a directory, not a model file"},
        {"pkg", "a package folder without manifest.json"},
        {"noread.obj", "no read permission"},
        {"big.obj", "over the largest model file"},
        {"bad name.obj", "not a valid model id"},
    };
    for (const std::string limit : {"", "4096"}) {
        std::vector<std::string> args = {"--gl", "none", "--models", models.string(), "--workers", "1"};
        if (!limit.empty()) args.insert(args.end(), {"--max-model-mib", limit});
        const auto t0 = Clock::now();
        auto s = ServeProcess::start(args, {}, asNobody);
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady(std::chrono::milliseconds(10000))) << s->log();
        const double readyMs = msSince(t0);
        std::printf("odd entries (max-model-mib %s): /readyz 200 %.0f ms after start\n",
                    limit.empty() ? "default" : limit.c_str(), readyMs);
        EXPECT_LT(readyMs, 2000.0) << s->log();
        const json ready = getJson(*s, "/readyz");
        EXPECT_EQ(ready["models"]["loaded"], 1) << ready.dump(2);
        EXPECT_TRUE(ready["models"]["failed"].empty()) << ready.dump(2);
        EXPECT_EQ(ready["models"]["skipped"].size(), expected.size()) << ready.dump(2);
        const std::string log = s->log();
        for (const Expected& e : expected) {
            const json entry = entryOf(ready["models"]["skipped"], "entry", e.entry);
            ASSERT_TRUE(entry.is_object()) << e.entry << " is not in /readyz: " << ready.dump(2);
            std::string want = e.reason;
            if (e.entry == "big.obj" && !limit.empty()) want = "are all zero";  // its first bytes
            EXPECT_NE(entry["reason"].get<std::string>().find(want), std::string::npos)
                << e.entry << ": " << entry["reason"];
            EXPECT_NE(log.find("event=models_dir_entry_skipped entry=\"" + e.entry + "\""), std::string::npos)
                << e.entry << "\n"
                << log;
        }
        int status = 0;
        getJson(*s, "/v1/models/good", &status);
        EXPECT_EQ(status, 200);
        EXPECT_EQ(s->terminate(std::chrono::milliseconds(10000)), 0) << s->log();
    }
}

// Item 3: a package that keeps failing its checks is moved aside each time, but only the
// newest kCorruptCopiesKept (2) copies stay.
TEST(HostileFiles, CorruptCopiesAreBoundedToTheNewestTwo) {
    Scratch dir("corrupt_copies");
    fs::create_directories(dir.path / "models");
    generate(dir.path / "models" / "mine.glb", 2000);
    const fs::path bake = dir.path / "bake";
    const std::vector<std::string> args = {"--gl",       "none",        "--models",  (dir.path / "models").string(),
                                           "--bake-dir", bake.string(), "--workers", "1"};
    auto corrupt = [&] {
        const fs::path mesh = bake / "mine" / "mesh.glb";
        ASSERT_TRUE(fs::exists(mesh));
        std::fstream f(mesh, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(fs::file_size(mesh) / 2));
        f.write("XXXXXXXX", 8);
    };
    std::string lastLog;
    for (int run = 0; run < 4; ++run) {
        if (run > 0) corrupt();
        auto s = ServeProcess::start(args);
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady()) << s->log();
        int status = 0;
        const json mine = getJson(*s, "/v1/models/mine", &status);
        EXPECT_EQ(status, 200);
        EXPECT_TRUE(mine.contains("baked"));
        lastLog = s->log();
        s->terminate(std::chrono::milliseconds(10000));
    }
    // Three corrupt packages: copies 1 and 2, then 3 (deleting 1).
    EXPECT_FALSE(fs::exists(bake / "mine.corrupt-1"));
    EXPECT_TRUE(fs::exists(bake / "mine.corrupt-2" / "mesh.glb"));
    EXPECT_TRUE(fs::exists(bake / "mine.corrupt-3" / "mesh.glb"));
    EXPECT_NE(lastLog.find("event=corrupt_copy_deleted id=mine"), std::string::npos) << lastLog;
    EXPECT_NE(lastLog.find("mine.corrupt-1"), std::string::npos) << lastLog;
    // Copies left by hand, or numbered far apart: the newest by number stay.
    fs::create_directories(bake / "mine.corrupt-17");
    fs::create_directories(bake / "mine.corrupt-x");  // not a copy: left alone
    corrupt();
    {
        auto s = ServeProcess::start(args);
        ASSERT_NE(s, nullptr);
        ASSERT_TRUE(s->waitReady()) << s->log();
        s->terminate(std::chrono::milliseconds(10000));
    }
    std::vector<std::string> copies;
    for (const auto& e : fs::directory_iterator(bake))
        if (e.path().filename().string().starts_with("mine.corrupt-")) copies.push_back(e.path().filename().string());
    std::sort(copies.begin(), copies.end());
    EXPECT_EQ(copies, (std::vector<std::string>{"mine.corrupt-17", "mine.corrupt-18", "mine.corrupt-x"}));
}

}  // namespace
}  // namespace geoslice::test
