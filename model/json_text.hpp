// The one way geoslice turns a JSON document into text. nlohmann's dump() throws
// type_error 316 on a string that is not UTF-8; a name read from a file in another encoding
// or a byte taken from a request must never end a process that way. Every document is
// written through jsonText, which replaces such bytes with U+FFFD; tests/check_json_dump.sh
// fails the build's tests on a bare dump() outside this header.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace geoslice {

// `indent` < 0: compact; otherwise pretty-printed with that many spaces.
template <class BasicJson>
std::string jsonText(const BasicJson& j, int indent = -1) {
    return j.dump(indent, ' ', false, BasicJson::error_handler_t::replace);  // json-dump-ok
}

}  // namespace geoslice
