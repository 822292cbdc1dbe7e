// Saved sections (api/saved_sections.hpp): sidecar entries and POST bodies checked field by
// field (every error names the entry and the field), ids stable and distinct, the query a
// section request reads back to the same geometry, and the directory store: save, save
// again (same id, first `created` kept), list, find, delete, hostile ids, a torn or foreign
// file skipped with its name, a file size limit refused without leaving a file behind.
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "api/plan.hpp"
#include "api/request.hpp"
#include "api/saved_sections.hpp"

namespace geoslice::api {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

SectionTarget target() {
    SectionTarget t;
    t.model = "mine";
    t.crs = Crs::local();
    t.bounds.min = {1000.0, 2000.0, -500.0};
    t.bounds.max = {3000.0, 5000.0, 300.0};
    t.origin = {2000.0, 3500.0, 0.0};
    return t;
}

fs::path freshDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    return d;
}

std::string errorOf(const json& j) {
    auto s = parseSavedSection(j, "sections[2]", target(), "model");
    return s ? std::string() : s.error().message;
}

TEST(SavedSections, AnEntryReadsAsASectionRequest) {
    auto s = parseSavedSection(json::parse(R"({"number": 12, "vertices": [[1500, 2100], [1500.5, 4900]], "vx": 2})"),
                               "sections[0]", target(), "model");
    ASSERT_TRUE(s) << s.error().message;
    EXPECT_EQ(s.value().number, "12");
    EXPECT_EQ(s.value().name, "Line 12");
    EXPECT_EQ(s.value().query, "line=1500,2100,1500.5,4900&vx=2");
    EXPECT_TRUE(isSavedSectionId(s.value().id));
    // The query is what a section request takes, and reads back to the same line.
    Params p;
    for (auto kv : {std::pair{"line", "1500,2100,1500.5,4900"}, std::pair{"vx", "2"}}) p[kv.first] = kv.second;
    auto def = parseSectionDef(p, "mine", Crs::local());
    ASSERT_TRUE(def);
    EXPECT_EQ("model=mine&" + s.value().query + "&bg=00000000", def.value().canonical());

    auto e = parseSavedSection(json::parse(R"({"name": "十二号勘探线", "elevation": -100})"), "x", target(), "saved");
    ASSERT_TRUE(e) << e.error().message;
    EXPECT_EQ(e.value().query, "elevation=-100");
    EXPECT_EQ(e.value().number, "");
    auto p2 = parseSavedSection(json::parse(R"({"name": "Dip", "plane": "0,2,0,-7000"})"), "x", target(), "saved");
    ASSERT_TRUE(p2) << p2.error().message;
    EXPECT_EQ(p2.value().query, "plane=0,1,0,-3500&vx=1");  // normalised, vx 1 by default
}

TEST(SavedSections, EveryBadFieldIsNamed) {
    const std::pair<const char*, const char*> cases[] = {
        {R"([1, 2])", "is not a JSON object"},
        {R"({"vertices": [[1500, 2100], [1600, 2200]]})", "needs a 'name' or a 'number'"},
        {R"({"name": "a"})", "needs 'vertices'"},
        {R"({"name": "a", "vertices": [[1500, 2100], [1600, 2200]], "plane": "1,0,0,-1500"})", "give one of"},
        {R"({"name": "a", "vertices": [[1500, 2100]]})", "has 1 points"},
        {R"({"name": "a", "vertices": [[1500, 2100], [1600]]})", "'vertices'[1] is not an [x, y] pair"},
        {R"({"name": "a", "vertices": [[1500, 2100], [1500, 2100]]})", "coincide"},
        {R"({"name": "a", "vertices": [[9000, 2100], [9100, 2200]]})", "misses the model"},
        {R"({"name": "a", "plane": "1,0,0,-9000"})", "sections[2]"},
        {R"({"name": "a", "elevation": 900})", "sections[2]"},
        {R"({"name": "a", "vertices": [[1500, 2100], [1600, 2200]], "vx": 0})", "vx"},
        {R"({"name": "a", "vertices": [[1500, 2100], [1600, 2200]], "colour": "x"})", "unknown field 'colour'"},
        {R"({"name": 5, "vertices": [[1500, 2100], [1600, 2200]]})", "'name' is not a text"},
        {R"({"number": 1.5, "vertices": [[1500, 2100], [1600, 2200]]})", "'number' is not a text or a whole number"},
        {R"({"name": "a\u0007b", "vertices": [[1500, 2100], [1600, 2200]]})", "control character"},
        {R"({"name": "a", "plane": "1,0,0,-1500;0,1,0,-3000"})", "one plane"},
    };
    for (const auto& [body, needle] : cases) {
        const std::string e = errorOf(json::parse(body));
        EXPECT_NE(e.find(needle), std::string::npos) << body << " -> " << e;
        if (std::string(body).front() == '{') {
            EXPECT_NE(e.find("sections[2]"), std::string::npos) << e;
        }
    }
    EXPECT_NE(errorOf({{"name", std::string(201, 'x')}, {"elevation", 0}}).find("201 bytes"), std::string::npos);
    std::string bad = "ab";
    bad[1] = char(0xC3);  // a lead byte with nothing after it
    EXPECT_NE(errorOf({{"name", bad}, {"elevation", 0}}).find("not valid UTF-8"), std::string::npos);
}

// Ids: the same section is one id wherever it is parsed; any change of model, source,
// geometry, number or name makes another. Random lines across the model.
TEST(SavedSections, IdsAreStableAndDistinct) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> x(1000, 3000), y(2000, 5000);
    std::set<std::string> ids;
    for (int i = 0; i < 500; ++i) {
        json j = {{"number", std::to_string(i)}, {"vertices", {{x(rng), y(rng)}, {x(rng), y(rng)}}}};
        auto a = parseSavedSection(j, "a", target(), "model");
        auto b = parseSavedSection(j, "b", target(), "model");
        ASSERT_TRUE(a && b);
        EXPECT_EQ(a.value().id, b.value().id);
        EXPECT_TRUE(ids.insert(a.value().id).second);
        auto saved = parseSavedSection(j, "a", target(), "saved");
        EXPECT_TRUE(ids.insert(saved.value().id).second);
        j["name"] = "renamed";
        EXPECT_TRUE(ids.insert(parseSavedSection(j, "a", target(), "model").value().id).second);
    }
}

TEST(SavedSections, SidecarWithBomDuplicatesAndErrorsNamed) {
    const fs::path d = freshDir("geoslice_sections_sidecar");
    fs::create_directories(d);
    auto write = [&](const std::string& text) {
        std::ofstream(d / "m.sections.json", std::ios::binary) << text;
        return loadSectionsSidecar((d / "m.sections.json").string(), target());
    };
    auto ok = write(
        "\xEF\xBB\xBF"
        R"({"sections": [{"number": "3", "vertices": [[1500, 2100], [1500, 4900]]},
                                                  {"number": "1", "name": "Line 1 - main", "vertices": [[1700, 2100], [1700, 4900]]}]})");
    ASSERT_TRUE(ok) << ok.error().message;
    ASSERT_EQ(ok.value().size(), 2u);
    EXPECT_EQ(ok.value()[0].name, "Line 3");
    EXPECT_EQ(ok.value()[1].name, "Line 1 - main");
    EXPECT_EQ(ok.value()[1].source, "model");
    auto arr = write(R"([{"number": "3", "vertices": [[1500, 2100], [1500, 4900]]}])");
    ASSERT_TRUE(arr);
    auto dup = write(R"([{"number": "3", "vertices": [[1500, 2100], [1500, 4900]]},
                        {"number": "3", "name": "other", "vertices": [[1600, 2100], [1600, 4900]]}])");
    ASSERT_FALSE(dup);
    EXPECT_NE(dup.error().message.find("sections[1]: number '3' is given twice"), std::string::npos)
        << dup.error().message;
    auto sameName = write(R"([{"number": "3", "vertices": [[1500, 2100], [1500, 4900]]},
                             {"name": "Line 3", "vertices": [[1600, 2100], [1600, 4900]]}])");
    ASSERT_FALSE(sameName);
    EXPECT_NE(sameName.error().message.find("name 'Line 3' is given twice"), std::string::npos);
    for (const char* text : {"{", R"({"lines": []})", R"({"sections": 5})", "\xFF\xFE"}) {
        auto r = write(text);
        ASSERT_FALSE(r) << text;
        EXPECT_NE(r.error().message.find("m.sections.json"), std::string::npos) << r.error().message;
    }
    fs::remove_all(d);
}

TEST(SavedSections, TheStoreSavesListsFindsAndDeletes) {
    const fs::path d = freshDir("geoslice_sections_store");
    const SavedSectionStore store(d.string());
    auto list0 = store.list("mine");
    ASSERT_TRUE(list0);
    EXPECT_TRUE(list0.value().empty());  // no directory yet
    auto s = parseSavedSection(json::parse(R"({"name": "Decline", "vertices": [[1500, 2100], [2500, 4900]]})"), "b",
                               target(), "saved");
    ASSERT_TRUE(s);
    auto first = store.save(s.value());
    ASSERT_TRUE(first) << first.error().message;
    EXPECT_TRUE(first.value().second);
    EXPECT_FALSE(first.value().first.created.empty());
    auto again = store.save(s.value());
    ASSERT_TRUE(again);
    EXPECT_FALSE(again.value().second);
    EXPECT_EQ(again.value().first.created, first.value().first.created);
    auto found = store.find("mine", s.value().id);
    ASSERT_TRUE(found && found.value());
    EXPECT_EQ(found.value()->query, s.value().query);
    EXPECT_EQ(found.value()->name, "Decline");
    // Hostile ids are never a path.
    for (const char* id : {"../../etc/passwd", "", "0123456789ABCDEF", "0123456789abcdef0", "..", "/"}) {
        auto f = store.find("mine", id);
        ASSERT_TRUE(f) << id;
        EXPECT_FALSE(f.value()) << id;
        auto r = store.remove("mine", id);
        ASSERT_TRUE(r);
        EXPECT_FALSE(r.value());
    }
    // A foreign file and a torn one are skipped and named; temporary files are not listed.
    std::ofstream(d / "mine" / "0000000000000000.json") << "{\"id\": \"00";
    std::ofstream(d / "mine" / "notes.json") << R"({"id": "1111111111111111", "name": "x", "query": "elevation=0"})";
    std::ofstream(d / "mine" / ".abc.tmp-1") << "{}";
    std::vector<std::string> skipped;
    auto list = store.list("mine", &skipped);
    ASSERT_TRUE(list);
    ASSERT_EQ(list.value().size(), 1u);
    EXPECT_EQ(list.value()[0].id, s.value().id);
    EXPECT_EQ(skipped.size(), 2u);
    auto del = store.remove("mine", s.value().id);
    ASSERT_TRUE(del);
    EXPECT_TRUE(del.value());
    EXPECT_FALSE(store.find("mine", s.value().id).value());
    fs::remove_all(d);
}

// Concurrent saves of one section (as from several replicas) leave one whole file.
TEST(SavedSections, ConcurrentSavesLeaveOneWholeFile) {
    const fs::path d = freshDir("geoslice_sections_race");
    auto s = parseSavedSection(json::parse(R"({"name": "Race", "elevation": 0})"), "b", target(), "saved");
    ASSERT_TRUE(s);
    std::vector<std::thread> threads;
    std::atomic<int> ok{0};
    for (int i = 0; i < 8; ++i)
        threads.emplace_back([&] {
            const SavedSectionStore store(d.string());  // a store per "replica"
            for (int k = 0; k < 20; ++k)
                if (store.save(s.value())) ++ok;
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(ok.load(), 160);
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(d / "mine")) {
        ++files;
        EXPECT_EQ(e.path().filename().string(), s.value().id + ".json");
    }
    EXPECT_EQ(files, 1u);
    auto list = SavedSectionStore(d.string()).list("mine");
    ASSERT_TRUE(list);
    ASSERT_EQ(list.value().size(), 1u);
    fs::remove_all(d);
}

// A file size limit (as a full disk) is Unavailable, named, and leaves no file behind.
TEST(SavedSections, AFullDiskIsRefusedAndLeavesNothing) {
    const fs::path d = freshDir("geoslice_sections_full");
    fs::create_directories(d / "mine");
    auto s = parseSavedSection(json::parse(R"({"name": "Full", "elevation": 0})"), "b", target(), "saved");
    ASSERT_TRUE(s);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit tiny = old;
    tiny.rlim_cur = 16;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &tiny), 0);
    auto r = SavedSectionStore(d.string()).save(s.value());
    ::setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().code, ErrorCode::Unavailable) << r.error().message;
    EXPECT_NE(r.error().message.find("File too large"), std::string::npos) << r.error().message;
    EXPECT_TRUE(fs::is_empty(d / "mine"));
    fs::remove_all(d);
}

}  // namespace
}  // namespace geoslice::api
