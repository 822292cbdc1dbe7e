// The container's memory limit from cgroup files (server/container_memory.hpp), read from a
// fake /proc/self/cgroup and cgroup tree written here in both layouts, and the defaults fitted
// to it. The real cgroup, with a server inside it, is tests/deploy/cgroup_memory_test.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "server/container_memory.hpp"

namespace geoslice::server {
namespace {

namespace fs = std::filesystem;

struct Tree {
    fs::path root = fs::temp_directory_path() / ("geoslice-cgroup-" + std::to_string(::getpid()));
    Tree() { fs::remove_all(root); }
    ~Tree() { fs::remove_all(root); }
    void write(const std::string& rel, const std::string& text) {
        fs::create_directories((root / rel).parent_path());
        std::ofstream(root / rel) << text;
    }
    std::string proc() const { return (root / "proc-self-cgroup").string(); }
    std::string cg() const { return (root / "cg").string(); }
};

TEST(ContainerMemory, CgroupV2UnderItsOwnPathAndMaxMeansNone) {
    Tree t;
    t.write("proc-self-cgroup", "0::/kubepods/pod1/ctr\n");
    t.write("cg/kubepods/pod1/ctr/memory.max", "6442450944\n");
    auto m = containerMemoryLimit(t.proc(), t.cg());
    ASSERT_TRUE(m);
    EXPECT_EQ(m->limitBytes, 6442450944u);
    EXPECT_NE(m->source.find("memory.max"), std::string::npos);
    t.write("cg/kubepods/pod1/ctr/memory.max", "max\n");
    EXPECT_FALSE(containerMemoryLimit(t.proc(), t.cg()));
}

TEST(ContainerMemory, CgroupV1MemoryControllerAndTheKernelsNoLimit) {
    Tree t;
    t.write("proc-self-cgroup", "9:name=systemd:/\n5:cpu,cpuacct:/x\n4:memory:/geoslice\n");
    t.write("cg/memory/geoslice/memory.limit_in_bytes", "2147483648\n");
    auto m = containerMemoryLimit(t.proc(), t.cg());
    ASSERT_TRUE(m);
    EXPECT_EQ(m->limitBytes, 2147483648u);
    t.write("cg/memory/geoslice/memory.limit_in_bytes", "9223372036854771712\n");  // unlimited
    EXPECT_FALSE(containerMemoryLimit(t.proc(), t.cg()));
    // Inside a container's cgroup namespace the path is "/".
    t.write("proc-self-cgroup", "4:memory:/\n");
    t.write("cg/memory/memory.limit_in_bytes", "1073741824\n");
    ASSERT_TRUE(containerMemoryLimit(t.proc(), t.cg()));
    EXPECT_EQ(containerMemoryLimit(t.proc(), t.cg())->limitBytes, 1073741824u);
    // Nothing readable: no limit, no error.
    EXPECT_FALSE(containerMemoryLimit((t.root / "absent").string(), t.cg()));
}

TEST(ContainerMemory, DefaultsShrinkToTheirSharesAndExplicitValuesStay) {
    ServerConfig c;
    fitToContainer(c, {std::size_t(2) << 30, "memory.max"});
    EXPECT_EQ(c.memoryBudgetMiB, 1024u);  // half of 2 GiB
    EXPECT_EQ(c.cacheMiB, 256u);          // an eighth
    EXPECT_EQ(c.containerMemoryMiB, 2048u);
    ServerConfig big;
    fitToContainer(big, {std::size_t(64) << 30, "memory.max"});
    EXPECT_EQ(big.memoryBudgetMiB, ServerConfig{}.memoryBudgetMiB) << "never raised";
    EXPECT_EQ(big.cacheMiB, ServerConfig{}.cacheMiB);
    ServerConfig set;
    set.memoryBudgetMiB = 3000;
    set.cacheMiB = 100;
    fitToContainer(set, {std::size_t(2) << 30, "memory.max"});
    EXPECT_EQ(set.memoryBudgetMiB, 3000u) << "an operator's value is kept";
    EXPECT_EQ(set.cacheMiB, 100u);
}

}  // namespace
}  // namespace geoslice::server
