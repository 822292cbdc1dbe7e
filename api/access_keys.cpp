#include "api/access_keys.hpp"

#include <algorithm>
#include <cstring>

#include <openssl/crypto.h>
#include <openssl/evp.h>

#include "api/catalog.hpp"
#include "model/io/loaders.hpp"

namespace geoslice::api {
namespace {

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
    // OpenSSL's (libssl-dev): a digest is not written by hand.
    Sha256Digest d{};
    unsigned int length = 0;
    const int ok = EVP_Digest(bytes.data(), bytes.size(), d.data(), &length, EVP_sha256(), nullptr);
    GS_ASSERT(ok == 1 && length == d.size(), "OpenSSL's SHA-256 failed");
    return d;
}

bool digestsEqual(const Sha256Digest& a, const Sha256Digest& b) {
    return CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;  // constant time (OpenSSL)
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
