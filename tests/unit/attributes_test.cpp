#include <gtest/gtest.h>

#include "model/attributes.hpp"

using namespace geoslice;

TEST(Attributes, ParsesColours) {
    EXPECT_EQ(parseColour("#ff8000"), (Rgba8{255, 128, 0, 255}));
    EXPECT_EQ(parseColour("#ff800080"), (Rgba8{255, 128, 0, 128}));
    EXPECT_EQ(parseColour("0.158703 0.472657 0.448879 1"), (Rgba8{40, 121, 114, 255}));  // GOCAD floats
    EXPECT_EQ(parseColour("10,20,30"), (Rgba8{10, 20, 30, 255}));
    EXPECT_FALSE(parseColour("#ff80"));
    EXPECT_FALSE(parseColour("red"));
    EXPECT_FALSE(parseColour("1 2"));
    EXPECT_FALSE(parseColour("300 0 0"));
    EXPECT_EQ(formatColour({1, 2, 3, 255}), "#010203");
}

TEST(Attributes, CsvKnownAndExtraColumnsRoundTrip) {
    const char* csv =
        "\xEF\xBB\xBFid,name,lithology,age,era,colour,density,grade,grade_unit,porosity,comment\r\n"
        "1,Xujiahe Fm,quartz sandstone,T3x,Mesozoic,#f2d16b,2.55,,,0.12,\"with, comma\"\r\n"
        "8,\xE8\x93\x9F\xE5\x8E\xBF\xE7\xBB\x84,\xE7\x81\xB0\xE5\xB2\xA9,,,,2.7,98.6,% SiO2,,\"say \"\"hi\"\"\"\n";
    auto t = AttributeTable::fromCsv(csv, "table.csv");
    ASSERT_TRUE(t.ok()) << t.error().message;
    ASSERT_EQ(t->size(), 2u);
    const AttributeRecord* r = t->find(1);
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(r->lithology, "quartz sandstone");
    EXPECT_EQ(r->colour, (Rgba8{0xf2, 0xd1, 0x6b, 255}));
    EXPECT_DOUBLE_EQ(*r->density, 2.55);
    EXPECT_FALSE(r->grade.has_value());
    EXPECT_DOUBLE_EQ(r->extra["porosity"].get<double>(), 0.12);
    EXPECT_EQ(r->extra["comment"], "with, comma");
    const AttributeRecord* ore = t->find(8);
    ASSERT_NE(ore, nullptr);
    EXPECT_EQ(ore->name, "\xE8\x93\x9F\xE5\x8E\xBF\xE7\xBB\x84");  // 蓟县组, bytes untouched
    EXPECT_EQ(ore->gradeUnit, "% SiO2");
    EXPECT_EQ(ore->extra["comment"], "say \"hi\"");

    // JSON round trip keeps every field.
    auto back = AttributeTable::fromJson(nlohmann::ordered_json::parse(t->toJson().dump()), "roundtrip");
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->toJson(), t->toJson());
}

TEST(Attributes, CsvErrorsNameFileAndLine) {
    struct Case {
        const char* text;
        const char* expect;
    };
    for (const Case& c :
         {Case{"name\nx\n", "line 1"}, Case{"id,name\n0,x\n", "line 2"}, Case{"id,name\n1,x\n1,y\n", "duplicate id 1"},
          Case{"id,name\n1\n", "1 fields"}, Case{"id,density\n1,abc\n", "density"},
          Case{"id,density\n1,nan\n", "density"}, Case{"id,name\n1,\"open\n", "unterminated quote"},
          Case{"id,colour\n1,#zz0000\n", "colour"}, Case{"id\n99999999999\n", "not an integer"}}) {
        auto t = AttributeTable::fromCsv(c.text, "bad.csv");
        ASSERT_FALSE(t.ok()) << c.text;
        EXPECT_NE(t.error().message.find("bad.csv"), std::string::npos) << t.error().message;
        EXPECT_NE(t.error().message.find(c.expect), std::string::npos) << t.error().message;
    }
}

TEST(Attributes, JsonErrors) {
    for (const char* text :
         {R"({"records": 3})", R"([{"name": "x"}])", R"([{"id": -1}])", R"([{"id": 1, "density": "heavy"}])",
          R"([{"id": 1, "colour": "#12"}])", R"([{"id": 1}, {"id": 1}])", R"([{"id": 1, "name": 5}])"}) {
        auto t = AttributeTable::fromJson(nlohmann::json::parse(text), "bad.json");
        ASSERT_FALSE(t.ok()) << text;
        EXPECT_NE(t.error().message.find("bad.json"), std::string::npos);
    }
}

TEST(Attributes, AddAssignsNextIdAndFindsByName) {
    AttributeTable t;
    AttributeRecord a;
    a.name = "a";
    EXPECT_EQ(t.add(a), 1u);
    AttributeRecord b;
    b.id = 10;
    b.name = "b";
    t.put(b);
    AttributeRecord c;
    c.name = "c";
    EXPECT_EQ(t.add(c), 11u);
    ASSERT_NE(t.findByName("b"), nullptr);
    EXPECT_EQ(t.findByName("b")->id, 10u);
    EXPECT_EQ(t.findByName("zz"), nullptr);
}

TEST(Attributes, ManyExtraFieldsStayLinear) {
    // ordered_json's operator[] searches linearly; 50,000 fields would take minutes if
    // every insertion searched. This finishes in milliseconds when appends are O(1).
    std::string header = "id", row = "1";
    for (int i = 0; i < 50000; ++i) {
        header += ",f" + std::to_string(i);
        row += "," + std::to_string(i);
    }
    auto t = AttributeTable::fromCsv(header + "\n" + row + "\n", "wide.csv");
    ASSERT_TRUE(t.ok()) << t.error().message;
    const auto& extra = t->find(1)->extra;
    ASSERT_EQ(extra.size(), 50000u);
    EXPECT_EQ(extra.get_ref<const nlohmann::ordered_json::object_t&>().back().first, "f49999");
    auto j = t->toJson();
    EXPECT_EQ(j["records"][0].size(), 50000u + 4u);  // id, name, colour, colour_source + extras
    auto dup = AttributeTable::fromCsv("id,name,name\n1,a,b\n", "dup.csv");
    ASSERT_FALSE(dup.ok());
    EXPECT_NE(dup.error().message.find("appears twice"), std::string::npos);
}

TEST(Attributes, ExtraNamedLikeATypedFieldIsShadowed) {
    AttributeRecord r;
    r.id = 3;
    r.name = "typed";
    r.extra["name"] = "extra";
    r.extra["note"] = "kept";
    auto j = r.toJson();
    EXPECT_EQ(j["name"], "typed");
    EXPECT_EQ(j["note"], "kept");
}
