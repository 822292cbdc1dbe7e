// api/access_keys.hpp: SHA-256 against the FIPS 180-4 example vectors, the digest compare,
// the keys-text parser (format, errors that never quote a key) and authentication by digest.
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "api/access_keys.hpp"

namespace geoslice::api {
namespace {

std::string hex(const Sha256Digest& d) {
    static const char* digits = "0123456789abcdef";
    std::string out;
    for (std::uint8_t b : d) {
        out += digits[b >> 4];
        out += digits[b & 15];
    }
    return out;
}

TEST(Sha256, FipsExamples) {
    // FIPS 180-4 / NIST CSRC example values: one block, two blocks (padding spills into a
    // second block at 56 bytes), and a million bytes.
    EXPECT_EQ(hex(sha256("")), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(hex(sha256("abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(hex(sha256("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(hex(sha256(std::string(1000000, 'a'))),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    // Lengths around the block and padding boundaries differ from each other.
    std::string previous;
    for (std::size_t n : {54, 55, 56, 57, 63, 64, 65, 119, 120}) {
        const std::string h = hex(sha256(std::string(n, 'k')));
        EXPECT_NE(h, previous) << n;
        previous = h;
    }
}

TEST(DigestsEqual, ComparesEveryByte) {
    const Sha256Digest a = sha256("one key");
    Sha256Digest b = a;
    EXPECT_TRUE(digestsEqual(a, b));
    for (std::size_t i : {0, 1, 15, 31}) {
        b = a;
        b[i] ^= 0x01;
        EXPECT_FALSE(digestsEqual(a, b)) << i;
        b[i] ^= 0x81;  // the low bit back, the high bit different
        EXPECT_FALSE(digestsEqual(a, b)) << i;
    }
}

const std::string kKeyA = "0123456789abcdef0123456789abcdef";
const std::string kKeyB = "Zm9vYmFyYmF6cXV4LS4_fis-PT09PT09";  // base64-ish, all token68 characters
const std::string kKeyC = "c-c-c-c-c-c-c-c-c";

TEST(ParseApiKeys, EntriesCommentsAndScopes) {
    const std::string text =
        "# name key models\n"
        "\n"
        "reader  " +
        kKeyA +
        "  north-pit,south_pit.2   # two models\r\n"
        "\tadmin\t" +
        kKeyB +
        "\t*\n"
        "one " +
        kKeyC + " m1 ; two " + kKeyC + "x m2\n";
    auto keys = parseApiKeys(text, "keys file k");
    ASSERT_TRUE(keys) << keys.error().message;
    ASSERT_EQ(keys.value().size(), 4u);
    const ApiKey& reader = keys.value()[0];
    EXPECT_EQ(reader.name, "reader");
    EXPECT_FALSE(reader.allModels);
    EXPECT_EQ(reader.models, (std::vector<std::string>{"north-pit", "south_pit.2"}));
    EXPECT_TRUE(reader.mayRead("north-pit"));
    EXPECT_TRUE(reader.mayRead("south_pit.2"));
    EXPECT_FALSE(reader.mayRead("north"));
    EXPECT_FALSE(reader.mayRead("north-pit2"));
    EXPECT_TRUE(digestsEqual(reader.digest, sha256(kKeyA)));
    EXPECT_TRUE(keys.value()[1].allModels);
    EXPECT_TRUE(keys.value()[1].mayRead("anything"));
    EXPECT_EQ(keys.value()[2].name, "one");
    EXPECT_EQ(keys.value()[3].name, "two");
    EXPECT_EQ(keys.value()[3].models, std::vector<std::string>{"m2"});
}

TEST(ParseApiKeys, ErrorsNameTheLineNeverTheKey) {
    const std::string good = "ok " + kKeyA + " a\n";
    struct Case {
        std::string text, needle, secret;
    };
    const std::vector<Case> cases = {
        {good + "short Sh0rtK3y *\n", "line 2", "Sh0rtK3y"},
        {good + "bad " + kKeyC + "!x *\n", "holds a character", kKeyC},
        {good + "two-fields " + kKeyC + "\n", "2 fields", kKeyC},
        {good + "four " + kKeyC + " a b\n", "4 fields", kKeyC},
        {good + "badname! " + kKeyC + " a\n", "the name", kKeyC},
        {good + "m " + kKeyC + " a,,b\n", "is not a model id", kKeyC},
        {good + "m " + kKeyC + " a,*\n", "stands alone", kKeyC},
        {good + "m " + kKeyC + " ../etc\n", "is not a model id", kKeyC},
        {"# only a comment\n\n  \n", "holds no keys", ""},
        {"", "holds no keys", ""},
        {"x " + std::string(513, 'k') + " *\n", "16 to 512", std::string(513, 'k')},
    };
    for (const Case& c : cases) {
        auto keys = parseApiKeys(c.text, "keys file k");
        ASSERT_FALSE(keys) << c.text;
        EXPECT_NE(keys.error().message.find(c.needle), std::string::npos) << keys.error().message;
        EXPECT_NE(keys.error().message.find("keys file k"), std::string::npos) << keys.error().message;
        if (!c.secret.empty()) {
            EXPECT_EQ(keys.error().message.find(c.secret), std::string::npos);
        }
        EXPECT_EQ(keys.error().message.find(kKeyA), std::string::npos) << keys.error().message;
    }
    // GEOSLICE_KEYS: entries on one line are numbered.
    auto env = parseApiKeys("a " + kKeyA + " m; b short m", "environment GEOSLICE_KEYS");
    ASSERT_FALSE(env);
    EXPECT_NE(env.error().message.find("line 1 entry 2"), std::string::npos) << env.error().message;
}

TEST(AccessKeys, AuthenticatesByDigestOnly) {
    auto parsed = parseApiKeys("a " + kKeyA + " m1\nb " + kKeyB + " *\nc " + kKeyC + " m1,m2", "k");
    ASSERT_TRUE(parsed);
    auto keys = AccessKeys::from(parsed.value());
    ASSERT_TRUE(keys);
    EXPECT_TRUE(keys.value().enabled());
    EXPECT_EQ(keys.value().size(), 3u);
    // Each key at each position is found, and only that one.
    for (const auto& [key, name] : {std::pair{kKeyA, "a"}, std::pair{kKeyB, "b"}, std::pair{kKeyC, "c"}}) {
        const ApiKey* k = keys.value().authenticate(key);
        ASSERT_NE(k, nullptr) << name;
        EXPECT_EQ(k->name, name);
    }
    // Near misses: one character changed at either end, a prefix, an extension, case.
    for (const std::string& bad :
         {"1" + kKeyA.substr(1), kKeyA.substr(0, 31) + "0", kKeyA.substr(0, 31), kKeyA + "0",
          std::string("0123456789ABCDEF0123456789ABCDEF"), std::string(), std::string(" "), std::string(600, 'a')})
        EXPECT_EQ(keys.value().authenticate(bad), nullptr) << bad;
    EXPECT_FALSE(AccessKeys().enabled());
    EXPECT_EQ(AccessKeys().authenticate(kKeyA), nullptr);
}

TEST(AccessKeys, RefusesDuplicates) {
    auto sameKey = parseApiKeys("a " + kKeyA + " m1\nb " + kKeyA + " m2", "k");
    ASSERT_TRUE(sameKey);
    auto k1 = AccessKeys::from(sameKey.value());
    ASSERT_FALSE(k1);
    EXPECT_NE(k1.error().message.find("the same key"), std::string::npos);
    EXPECT_EQ(k1.error().message.find(kKeyA), std::string::npos);
    auto sameName = parseApiKeys("a " + kKeyA + " m1\na " + kKeyB + " m2", "k");
    ASSERT_TRUE(sameName);
    EXPECT_FALSE(AccessKeys::from(sameName.value()));
}

TEST(AccessKeys, FileAndEnvironmentTogether) {
    const auto path = std::filesystem::temp_directory_path() / ("geoslice_keys_" + std::to_string(getpid()));
    std::ofstream(path) << "filekey " << kKeyA << " m1\n";
    auto both = loadAccessKeys(path.string(), "envkey " + kKeyB + " m2");
    ASSERT_TRUE(both) << both.error().message;
    EXPECT_EQ(both.value().size(), 2u);
    ASSERT_NE(both.value().authenticate(kKeyA), nullptr);
    EXPECT_EQ(both.value().authenticate(kKeyA)->name, "filekey");
    ASSERT_NE(both.value().authenticate(kKeyB), nullptr);
    EXPECT_EQ(both.value().authenticate(kKeyB)->name, "envkey");
    auto none = loadAccessKeys("", "");
    ASSERT_TRUE(none);
    EXPECT_FALSE(none.value().enabled());
    EXPECT_FALSE(loadAccessKeys(path.string() + ".missing", ""));
    EXPECT_FALSE(loadAccessKeys(path.string(), "again " + kKeyA + " m3"));  // the same key twice
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace geoslice::api
