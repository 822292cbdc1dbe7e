// api/json_writer.hpp: the pixel query's JSON writer. Strings are escaped as JSON requires
// (RFC 8259 section 7): quote, backslash and every control character; everything else,
// UTF-8 included, is copied as it is.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "api/json_writer.hpp"

namespace geoslice::api {
namespace {

TEST(JsonWriter, EscapesQuotesBackslashesAndControlCharacters) {
    std::string out;
    JsonWriter w(out);
    w.beginObject();
    w.key("k\"1").value(std::string_view("a\"b\\c\nd\re\tf\x01g\x1fh"));
    w.key("plain").value("no escapes at all");
    w.key("").value("");
    w.endObject();
    EXPECT_EQ(out,
              "{\"k\\\"1\":\"a\\\"b\\\\c\\nd\\re\\tf\\u0001g\\u001fh\",\"plain\":\"no escapes at all\",\"\":\"\"}");
}

TEST(JsonWriter, EveryAsciiCharacterAndUtf8RoundTrip) {
    std::string text;
    for (int c = 0; c < 128; ++c) text += char(c);
    text += "雾迷山组 end\"";
    std::string out;
    JsonWriter w(out);
    w.beginArray().value(std::string_view(text)).value(std::string_view(text.substr(1, 40))).endArray();
    const auto doc = nlohmann::json::parse(out);
    ASSERT_EQ(doc.size(), 2u);
    EXPECT_EQ(doc[0].get<std::string>(), text);
    EXPECT_EQ(doc[1].get<std::string>(), text.substr(1, 40));
}

}  // namespace
}  // namespace geoslice::api
