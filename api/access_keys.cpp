#include "api/access_keys.hpp"

#include <algorithm>
#include <cstring>

#include "api/catalog.hpp"
#include "model/loaders.hpp"

namespace geoslice::api {
namespace {

// ---- SHA-256, FIPS 180-4 section 6.2 --------------------------------------------------

constexpr std::uint32_t kRound[64] = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

constexpr std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }

void compress(std::uint32_t h[8], const std::uint8_t block[64]) {
    std::uint32_t w[64];
    for (int i = 0; i < 16; ++i)
        w[i] = std::uint32_t(block[4 * i]) << 24 | std::uint32_t(block[4 * i + 1]) << 16 |
               std::uint32_t(block[4 * i + 2]) << 8 | std::uint32_t(block[4 * i + 3]);
    for (int i = 16; i < 64; ++i) {
        const std::uint32_t s0 = rotr(w[i - 15], 7) ^ rotr(w[i - 15], 18) ^ (w[i - 15] >> 3);
        const std::uint32_t s1 = rotr(w[i - 2], 17) ^ rotr(w[i - 2], 19) ^ (w[i - 2] >> 10);
        w[i] = w[i - 16] + s0 + w[i - 7] + s1;
    }
    std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
    for (int i = 0; i < 64; ++i) {
        const std::uint32_t t1 = k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kRound[i] + w[i];
        const std::uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
        k = g;
        g = f;
        f = e;
        e = d + t1;
        d = c;
        c = b;
        b = a;
        a = t1 + t2;
    }
    h[0] += a;
    h[1] += b;
    h[2] += c;
    h[3] += d;
    h[4] += e;
    h[5] += f;
    h[6] += g;
    h[7] += k;
}

// ---- keys text -------------------------------------------------------------------------

constexpr std::size_t kMinKeyChars = 16, kMaxKeyChars = 512;

bool isNameChar(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
           c == '-';
}

// RFC 7235 token68 characters (the '=' padding is allowed anywhere: keys are opaque).
bool isKeyChar(char c) { return isNameChar(c) || c == '~' || c == '+' || c == '/' || c == '='; }

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> out;
    while (true) {
        const std::size_t at = s.find(sep);
        out.push_back(s.substr(0, at));
        if (at == std::string_view::npos) return out;
        s.remove_prefix(at + 1);
    }
}

std::vector<std::string_view> fields(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
        if (i > start) out.push_back(s.substr(start, i - start));
    }
    return out;
}

}  // namespace

Sha256Digest sha256(std::string_view bytes) {
    std::uint32_t h[8] = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                          0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
    std::size_t left = bytes.size();
    for (; left >= 64; left -= 64, p += 64) compress(h, p);
    // Padding: 0x80, zeros, the message length in bits as a big-endian 64-bit number.
    std::uint8_t tail[128] = {};
    std::memcpy(tail, p, left);
    tail[left] = 0x80;
    const std::size_t tailBytes = left + 9 <= 64 ? 64 : 128;
    const std::uint64_t bits = std::uint64_t(bytes.size()) * 8;
    for (int i = 0; i < 8; ++i) tail[tailBytes - 1 - i] = std::uint8_t(bits >> (8 * i));
    compress(h, tail);
    if (tailBytes == 128) compress(h, tail + 64);
    Sha256Digest out;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 4; ++j) out[std::size_t(4 * i + j)] = std::uint8_t(h[i] >> (24 - 8 * j));
    return out;
}

bool digestsEqual(const Sha256Digest& a, const Sha256Digest& b) {
    // OR of every byte difference: the loop runs to the end whatever the bytes are.
    std::uint8_t diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff = std::uint8_t(diff | (a[i] ^ b[i]));
    return diff == 0;
}

bool ApiKey::mayRead(std::string_view modelId) const {
    if (allModels) return true;
    for (const std::string& m : models)
        if (m == modelId) return true;
    return false;
}

Result<std::vector<ApiKey>> parseApiKeys(std::string_view text, const std::string& source) {
    std::vector<ApiKey> keys;
    std::size_t lineNo = 0;
    for (std::string_view line : split(text, '\n')) {
        ++lineNo;
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        std::size_t entryNo = 0;
        for (std::string_view entry : split(line, ';')) {
            ++entryNo;
            const std::vector<std::string_view> f = fields(entry);
            if (f.empty()) continue;
            // Where: the line, and the entry on it when a line holds several (GEOSLICE_KEYS).
            const std::string at =
                source + " line " + std::to_string(lineNo) +
                (line.find(';') != std::string_view::npos ? " entry " + std::to_string(entryNo) : "");
            if (f.size() != 3)
                return makeError(ErrorCode::InvalidArgument,
                                 at + ": " + std::to_string(f.size()) +
                                     " fields; an entry is NAME KEY MODELS (MODELS: * or ids separated by commas)");
            ApiKey k;
            if (f[0].size() > 64 || !std::all_of(f[0].begin(), f[0].end(), isNameChar))
                return makeError(ErrorCode::InvalidArgument,
                                 at + ": the name must be 1 to 64 characters of A-Z a-z 0-9 . _ -");
            k.name = std::string(f[0]);
            // The key itself is never quoted back, only what is wrong with it.
            if (f[1].size() < kMinKeyChars || f[1].size() > kMaxKeyChars)
                return makeError(ErrorCode::InvalidArgument,
                                 at + ": the key of '" + k.name + "' must be " + std::to_string(kMinKeyChars) + " to " +
                                     std::to_string(kMaxKeyChars) + " characters (e.g. openssl rand -hex 32)");
            if (!std::all_of(f[1].begin(), f[1].end(), isKeyChar))
                return makeError(
                    ErrorCode::InvalidArgument,
                    at + ": the key of '" + k.name + "' holds a character outside A-Z a-z 0-9 - . _ ~ + / =");
            k.digest = sha256(f[1]);
            if (f[2] == "*") {
                k.allModels = true;
            } else {
                for (std::string_view id : split(f[2], ',')) {
                    if (id == "*")
                        return makeError(ErrorCode::InvalidArgument,
                                         at + ": '" + k.name + "': '*' stands alone (every model), not in a list");
                    if (!isValidModelId(id))
                        return makeError(ErrorCode::InvalidArgument,
                                         at + ": '" + k.name + "': '" + std::string(id.substr(0, 80)) +
                                             "' is not a model id ([A-Za-z0-9][A-Za-z0-9._-]{0,63})");
                    k.models.emplace_back(id);
                }
            }
            keys.push_back(std::move(k));
        }
    }
    if (keys.empty())
        return makeError(ErrorCode::InvalidArgument,
                         source + " holds no keys (an entry is NAME KEY MODELS); remove it to serve without keys");
    return keys;
}

Result<AccessKeys> AccessKeys::from(std::vector<ApiKey> keys) {
    for (std::size_t i = 0; i < keys.size(); ++i)
        for (std::size_t j = 0; j < i; ++j) {
            if (keys[i].name == keys[j].name)
                return makeError(ErrorCode::InvalidArgument, "API key name '" + keys[i].name + "' is given twice");
            if (digestsEqual(keys[i].digest, keys[j].digest))
                return makeError(ErrorCode::InvalidArgument,
                                 "API keys '" + keys[j].name + "' and '" + keys[i].name + "' are the same key");
        }
    AccessKeys a;
    a.keys_ = std::move(keys);
    return a;
}

const ApiKey* AccessKeys::authenticate(std::string_view presented) const {
    if (keys_.empty() || presented.empty() || presented.size() > kMaxKeyChars) return nullptr;
    const Sha256Digest d = sha256(presented);
    // Every digest is compared; the index of the match (keys are unique: at most one) is
    // chosen with a mask, so neither the loop nor its timing depends on where it is.
    std::size_t found = keys_.size();
    for (std::size_t i = 0; i < keys_.size(); ++i) {
        const std::size_t mask = std::size_t(0) - std::size_t(digestsEqual(keys_[i].digest, d));
        found = (found & ~mask) | (i & mask);
    }
    return found < keys_.size() ? &keys_[found] : nullptr;
}

Result<AccessKeys> loadAccessKeys(const std::string& keysFile, const std::string& keysText) {
    std::vector<ApiKey> all;
    if (!keysFile.empty()) {
        auto text = readFile(keysFile, 1 << 20);
        if (!text) return text.error();
        auto keys = parseApiKeys(text.value(), "keys file " + keysFile);
        if (!keys) return keys.error();
        all = std::move(keys.value());
    }
    if (!keysText.empty()) {
        auto keys = parseApiKeys(keysText, "environment GEOSLICE_KEYS");
        if (!keys) return keys.error();
        all.insert(all.end(), keys.value().begin(), keys.value().end());
    }
    return AccessKeys::from(std::move(all));
}

}  // namespace geoslice::api
