// Replays every file of the given files/folders through LLVMFuzzerTestOneInput, plus
// truncations of each at a spread of lengths. Used when the build is not a libFuzzer build.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {
void replay(const std::filesystem::path& p, std::size_t& runs) {
    std::ifstream in(p, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
    ++runs;
    for (int k = 1; k < 16; ++k) {  // truncated copies, in fresh buffers so ASan sees overreads
        std::size_t n = bytes.size() * static_cast<std::size_t>(k) / 16;
        std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
        LLVMFuzzerTestOneInput(cut.data(), cut.size());
        ++runs;
    }
}
}  // namespace

int main(int argc, char** argv) {
    std::size_t runs = 0;
    for (int i = 1; i < argc; ++i) {
        std::filesystem::path p(argv[i]);
        if (std::filesystem::is_directory(p)) {
            for (const auto& e : std::filesystem::recursive_directory_iterator(p))
                if (e.is_regular_file()) replay(e.path(), runs);
        } else {
            replay(p, runs);
        }
    }
    std::printf("replayed %zu inputs\n", runs);
    return 0;
}
