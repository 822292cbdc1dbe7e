// api/request.hpp: what a request carries, parsed without a socket. Each case pins the
// value read and, for bad input, the error code (which server/ maps to a status) and the
// words that name the bad parameter or field.
#include <gtest/gtest.h>

#include "api/plan.hpp"
#include "api/request.hpp"
#include "view/view_limits.hpp"

namespace geoslice::api {
namespace {

template <class T>
void expectError(const Result<T>& r, ErrorCode code, const std::string& needle) {
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, code) << r.error().message;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
}

TEST(ApiRequest, QueryParamsJoinPlanesInOrderAndRefuseOtherRepeats) {
    std::multimap<std::string, std::string> q{{"plane", "0,1,0,-5"}, {"size", "64x64"}, {"plane", "1,0,0,2"}};
    auto p = paramsFromQuery(q);
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_EQ(p.value().at("plane"), "0,1,0,-5;1,0,0,2");
    EXPECT_EQ(p.value().at("size"), "64x64");
    expectError(paramsFromQuery({{"size", "1x1"}, {"size", "2x2"}}), ErrorCode::InvalidArgument,
                "parameter 'size' is given more than once");
    auto empty = paramsFromQuery({});
    ASSERT_TRUE(empty);
    EXPECT_TRUE(empty.value().empty());
}

TEST(ApiRequest, JsonFieldsBecomeTheTextAQueryStringWouldCarry) {
    const auto j = nlohmann::json::parse(
        R"({"plane": [0, 1, 0, -3388846.5], "planes": [[1, 0, 0, 2], [0, 0, 1, -0.25]], "size": "64x32",
            "vx": 2, "dx": 0.1, "colour": true})");
    auto p = paramsFromJson(j, "the section definition");
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_EQ(p.value().at("plane"), "0,1,0,-3388846.5");
    EXPECT_EQ(p.value().at("planes"), "1,0,0,2;0,0,1,-0.25");
    EXPECT_EQ(p.value().at("size"), "64x32");
    EXPECT_EQ(p.value().at("vx"), "2");
    EXPECT_EQ(p.value().at("dx"), "0.1");  // shortest round trip, not 0.10000000000000001
    EXPECT_EQ(p.value().at("colour"), "true");
    expectError(paramsFromJson(nlohmann::json::array(), "'view'"), ErrorCode::InvalidArgument,
                "'view' must be a JSON object");
    expectError(paramsFromJson(nlohmann::json::parse(R"({"plane": [0, "1"]})"), "'view'"), ErrorCode::InvalidArgument,
                "'plane' must be an array of numbers");
    expectError(paramsFromJson(nlohmann::json::parse(R"({"plane": [[0, 1], [0, null]]})"), "'view'"),
                ErrorCode::InvalidArgument, "'plane' must be an array of numbers");
    expectError(paramsFromJson(nlohmann::json::parse(R"({"a": null})"), "'view'"), ErrorCode::InvalidArgument,
                "'a' must be a string, number or array");
}

TEST(ApiRequest, MediaTypes) {
    EXPECT_EQ(mediaType("Application/JSON ; charset=utf-8"), "application/json");
    EXPECT_EQ(mediaType(""), "");
    EXPECT_TRUE(isJsonMediaType("application/json"));
    EXPECT_TRUE(isJsonMediaType("application/problem+json"));
    EXPECT_FALSE(isJsonMediaType("+json"));
    EXPECT_FALSE(isJsonMediaType("text/plain"));
    EXPECT_FALSE(isJsonMediaType("application/jsonx"));
}

TEST(ApiRequest, QualityAndSpace) {
    EXPECT_EQ(parseQuality({}).value(), 0);
    EXPECT_EQ(parseQuality({{"quality", "85"}}).value(), 85);
    expectError(parseQuality({{"quality", "0"}}), ErrorCode::OutOfRange, "quality");
    expectError(parseQuality({{"quality", "abc"}}), ErrorCode::InvalidArgument, "quality");
    EXPECT_EQ(parseVectorSpace({}, true).value(), VectorFrame::LonLat);  // RFC 7946 by default
    EXPECT_EQ(parseVectorSpace({}, false).value(), VectorFrame::Plane);  // no CRS: no lon/lat
    EXPECT_EQ(parseVectorSpace({{"space", "plane"}}, true).value(), VectorFrame::Plane);
    EXPECT_EQ(parseVectorSpace({{"space", "world"}}, true).value(), VectorFrame::LonLat);
    EXPECT_EQ(parseVectorSpace({{"space", "projected"}}, true).value(), VectorFrame::Projected);
    expectError(parseVectorSpace({{"space", "local"}}, true), ErrorCode::InvalidArgument,
                "parameter 'space': 'local' is not 'world', 'projected' or 'plane'");
}

TEST(ApiRequest, TileAddresses) {
    auto t = parseTileAddress("3", "-2", "7");
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(t.value().z, 3);
    EXPECT_EQ(t.value().x, -2);
    EXPECT_EQ(t.value().y, 7);
    EXPECT_TRUE(parseTileAddress("30", "1099511627776", "-1099511627776"));  // 2^40 at the edge
    expectError(parseTileAddress("31", "0", "0"), ErrorCode::NotFound, "tile coordinates are out of range");
    expectError(parseTileAddress("0", "1099511627777", "0"), ErrorCode::NotFound, "out of range");
    expectError(parseTileAddress("-1", "0", "0"), ErrorCode::NotFound, "out of range");
}

TEST(ApiRequest, QueryPixel) {
    auto p = parseQueryPixel({{"px", "12"}, {"py", "-3"}});
    ASSERT_TRUE(p);
    EXPECT_EQ(p.value().x, 12);
    EXPECT_EQ(p.value().y, -3);
    expectError(parseQueryPixel({{"px", "1"}}), ErrorCode::InvalidArgument, "give the pixel as 'px' and 'py'");
    expectError(parseQueryPixel({{"px", "1.5"}, {"py", "0"}}), ErrorCode::InvalidArgument, "px");
}

TEST(ApiRequest, SectionBody) {
    auto p = parseSectionBody(R"({"plane": [0, 1, 0, -5], "size": "256x256"})");
    ASSERT_TRUE(p) << p.error().message;
    EXPECT_EQ(p.value().at("plane"), "0,1,0,-5");
    expectError(parseSectionBody("{not json"), ErrorCode::ParseError, "the body is not valid JSON");
    expectError(parseSectionBody("[1, 2]"), ErrorCode::InvalidArgument, "the section definition must be a JSON object");
}

TEST(ApiRequest, QueryBatches) {
    const auto names = viewParamNames();
    auto b = parseQueryBatch(R"({"view": {"plane": [0, 1, 0, -5], "size": "8x8"}, "pixels": [[1, 2], [3, 4]]})", names);
    ASSERT_TRUE(b) << b.error().message;
    EXPECT_EQ(b.value().view.at("plane"), "0,1,0,-5");
    auto px = parseBatchPixels(b.value().pixels);
    ASSERT_TRUE(px);
    ASSERT_EQ(px.value().size(), 2u);
    EXPECT_EQ(px.value()[1].x, 3);
    EXPECT_EQ(px.value()[1].y, 4);

    expectError(parseQueryBatch("[]", names), ErrorCode::ParseError, "the body is not a JSON object");
    expectError(parseQueryBatch("{", names), ErrorCode::ParseError, "the body is not a JSON object");
    expectError(parseQueryBatch(R"({"view": {}, "pixels": [], "px": 1})", names), ErrorCode::InvalidArgument,
                "unknown field 'px' in the body; known: view, pixels");
    expectError(parseQueryBatch(R"({"view": {}})", names), ErrorCode::InvalidArgument, "the body needs 'view'");
    expectError(parseQueryBatch(R"({"view": {}, "pixels": {}})", names), ErrorCode::InvalidArgument,
                "the body needs 'view'");
    expectError(parseQueryBatch(R"({"view": {"sise": "8x8"}, "pixels": []})", names), ErrorCode::InvalidArgument,
                "field 'view': ");
    std::string many = R"({"view": {}, "pixels": [)";
    for (std::size_t i = 0; i <= kMaxBatchPixels; ++i) many += i ? ",[0,0]" : "[0,0]";
    many += "]}";
    expectError(
        parseQueryBatch(many, names), ErrorCode::OutOfRange,
        "at most " + std::to_string(kMaxBatchPixels) + " pixels per batch, got " + std::to_string(kMaxBatchPixels + 1));

    expectError(parseBatchPixels(nlohmann::json::parse("[[1, 2], [1.5, 2]]")), ErrorCode::InvalidArgument,
                "pixels[1] is not [px, py] with whole numbers");
    expectError(parseBatchPixels(nlohmann::json::parse("[[1, 2, 3]]")), ErrorCode::InvalidArgument, "pixels[0]");
    expectError(parseBatchPixels(nlohmann::json::parse("[5]")), ErrorCode::InvalidArgument, "pixels[0]");
}

}  // namespace
}  // namespace geoslice::api
