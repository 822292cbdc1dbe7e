// GET a path with cpp-httplib, expect a status, parse the body as JSON: the one helper the
// server tests share (a discarded JSON value when the body is not JSON or no answer came).
#pragma once

#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

namespace geoslice::test {

// `contentType`, when given, must be the answer's Content-Type.
inline nlohmann::json getJson(httplib::Client& client, const std::string& path, int expectStatus = 200,
                              const std::string& contentType = "") {
    auto r = client.Get(path.c_str());
    EXPECT_TRUE(r) << path;
    if (!r) return nlohmann::json::value_t::discarded;
    EXPECT_EQ(r->status, expectStatus) << path << "\n" << r->body;
    if (!contentType.empty()) {
        EXPECT_EQ(r->get_header_value("Content-Type"), contentType) << path;
    }
    return nlohmann::json::parse(r->body, nullptr, false);
}

}  // namespace geoslice::test
