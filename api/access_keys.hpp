// API keys and the models each may read (server/router.cpp authenticates, the model routes
// check the scope: server/routes/common.hpp findModel). No HTTP here.
//
// Keys text (a keys file, `--keys FILE` / GEOSLICE_KEYS_FILE, or GEOSLICE_KEYS): one entry a
// line, or entries separated by ';'; '#' starts a comment; blank entries are skipped. An
// entry is three fields separated by spaces or tabs:
//
//   NAME   KEY                                        MODELS
//   survey 6f1d0c...(at least 16 characters)          north-pit,south-pit
//   ops    Zm9vYmFyYmF6...                            *
//
//   NAME    [A-Za-z0-9._-]{1,64}, unique: what logs say instead of the key.
//   KEY     16 to 512 characters of A-Za-z0-9 - . _ ~ + / = (RFC 7235 token68, so it can be
//           sent as `Authorization: Bearer KEY`), unique. `openssl rand -hex 32` makes one.
//   MODELS  '*' (every model, also models added later), or model ids separated by commas.
//
// Only the SHA-256 digest of each key is kept. A presented key is hashed and compared with
// every digest with no early exit (authenticate): the time taken does not depend on which
// key, if any, matches, nor on how many bytes of it match. Errors name the source and the
// line, never a key.
//
// Threads: an AccessKeys is immutable once built; any thread may call authenticate.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "model/result.hpp"

namespace geoslice::api {

using Sha256Digest = std::array<std::uint8_t, 32>;

// SHA-256 (FIPS 180-4) of `bytes`.
Sha256Digest sha256(std::string_view bytes);
// True when a == b, comparing all 32 bytes whatever they hold (no early exit).
bool digestsEqual(const Sha256Digest& a, const Sha256Digest& b);

struct ApiKey {
    std::string name;                 // logged in place of the key
    bool allModels = false;           // MODELS was '*'
    std::vector<std::string> models;  // ids this key may read (when not allModels)
    Sha256Digest digest{};            // SHA-256 of the key; the key itself is not kept

    bool mayRead(std::string_view modelId) const;
};

// Parses keys text (format above). `source` names it in errors ("keys file /etc/k",
// "environment GEOSLICE_KEYS"). Text without any entry is an error: a keys source that is
// given but empty must not leave the server open.
Result<std::vector<ApiKey>> parseApiKeys(std::string_view text, const std::string& source);

class AccessKeys {
public:
    AccessKeys() = default;  // no keys: authentication off
    // Fails when two entries share a key or a name.
    static Result<AccessKeys> from(std::vector<ApiKey> keys);

    bool enabled() const { return !keys_.empty(); }
    std::size_t size() const { return keys_.size(); }
    // The key whose digest equals the digest of `presented`, or null. Every key's digest is
    // compared in full (digestsEqual), and the match is selected without a branch.
    const ApiKey* authenticate(std::string_view presented) const;

private:
    std::vector<ApiKey> keys_;
};

// The keys of a keys file (path; "" = none) and of keys text from the environment ("" =
// none), together. Neither given: authentication off.
Result<AccessKeys> loadAccessKeys(const std::string& keysFile, const std::string& keysText);

}  // namespace geoslice::api
