// A minimal append-only JSON writer for hot paths (pixel queries): no DOM, no allocation
// beyond the output string, numbers in shortest round-trip form (std::to_chars). The
// caller writes a well-formed document; the writer adds commas and escapes strings.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace geoslice::api {

class JsonWriter {
public:
    explicit JsonWriter(std::string& out) : out_(out) {}

    JsonWriter& beginObject() { return open('{'); }
    JsonWriter& endObject() { return close('}'); }
    JsonWriter& beginArray() { return open('['); }
    JsonWriter& endArray() { return close(']'); }
    JsonWriter& key(std::string_view k) {
        comma();
        string(k);
        out_ += ':';
        first_ = true;  // the value follows without a comma
        return *this;
    }
    JsonWriter& value(std::string_view s) {
        comma();
        string(s);
        return *this;
    }
    JsonWriter& value(const char* s) { return value(std::string_view(s)); }
    JsonWriter& value(double v) {
        comma();
        if (!std::isfinite(v)) {
            out_ += "null";
            return *this;
        }
        if (v == 0.0) v = 0.0;
        char buf[32];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        out_.append(buf, r.ptr);
        // Keep doubles recognisable as numbers with a fraction where to_chars gives "12".
        return *this;
    }
    JsonWriter& value(long long v) {
        comma();
        char buf[24];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        out_.append(buf, r.ptr);
        return *this;
    }
    JsonWriter& value(int v) { return value(static_cast<long long>(v)); }
    JsonWriter& value(unsigned v) { return value(static_cast<long long>(v)); }
    JsonWriter& value(bool v) {
        comma();
        out_ += v ? "true" : "false";
        return *this;
    }
    JsonWriter& null() {
        comma();
        out_ += "null";
        return *this;
    }
    // Already serialised JSON (a cached fragment).
    JsonWriter& raw(std::string_view json) {
        comma();
        out_ += json;
        return *this;
    }

private:
    JsonWriter& open(char c) {
        comma();
        out_ += c;
        first_ = true;
        return *this;
    }
    JsonWriter& close(char c) {
        out_ += c;
        first_ = false;
        return *this;
    }
    void comma() {
        if (!first_) out_ += ',';
        first_ = false;
    }
    // Runs of characters that need no escape are appended whole: the output does not depend
    // on the compiler inlining std::string::push_back into a per-character loop (it did in
    // one translation unit and not in another: 2 us of a 6 us pixel query).
    void string(std::string_view s) {
        out_ += '"';
        std::size_t run = 0;  // first character not yet written
        for (std::size_t i = 0; i < s.size(); ++i) {
            const char c = s[i];
            if (c != '"' && c != '\\' && static_cast<unsigned char>(c) >= 0x20) continue;
            out_.append(s.data() + run, i - run);
            run = i + 1;
            switch (c) {
                case '"':
                    out_ += "\\\"";
                    break;
                case '\\':
                    out_ += "\\\\";
                    break;
                case '\n':
                    out_ += "\\n";
                    break;
                case '\r':
                    out_ += "\\r";
                    break;
                case '\t':
                    out_ += "\\t";
                    break;
                default: {
                    static const char* hex = "0123456789abcdef";
                    out_ += "\\u00";
                    out_ += hex[(c >> 4) & 15];
                    out_ += hex[c & 15];
                }
            }
        }
        out_.append(s.data() + run, s.size() - run);
        out_ += '"';
    }
    std::string& out_;
    bool first_ = true;
};

}  // namespace geoslice::api
