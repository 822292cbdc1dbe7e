// model/text_scan.hpp: the case-folding and digit helpers the CRS and Geo3DML readers share.
// Exact string results: no tolerance applies.
#include <gtest/gtest.h>

#include "model/text_scan.hpp"

using namespace geoslice;

TEST(TextScan, EqualsNoCaseFoldsAsciiLettersOnly) {
    EXPECT_TRUE(text::equalsNoCase("EPSG", "epsg"));
    EXPECT_TRUE(text::equalsNoCase("", ""));
    EXPECT_FALSE(text::equalsNoCase("epsg", "eps"));
    EXPECT_FALSE(text::equalsNoCase("local", "locale"));
    EXPECT_FALSE(text::equalsNoCase("@", "`"));                // 0x40 / 0x60: not letters, not folded
    EXPECT_FALSE(text::equalsNoCase("\xC3\x89", "\xC3\xA9"));  // É / é: only ASCII folds
}

TEST(TextScan, StartsWithNoCase) {
    EXPECT_TRUE(text::startsWithNoCase("urn:OGC:def:crs:EPSG::2056", "urn:ogc:def:crs:epsg:"));
    EXPECT_TRUE(text::startsWithNoCase("<?XML version", "<?xml"));
    EXPECT_TRUE(text::startsWithNoCase("abc", ""));
    EXPECT_FALSE(text::startsWithNoCase("ep", "epsg:"));
    EXPECT_FALSE(text::startsWithNoCase("esri:102100", "epsg:"));
}

TEST(TextScan, IsDigits) {
    EXPECT_TRUE(text::isDigits("4526"));
    EXPECT_TRUE(text::isDigits("0"));
    EXPECT_FALSE(text::isDigits(""));
    EXPECT_FALSE(text::isDigits("+4526"));
    EXPECT_FALSE(text::isDigits("45 26"));
    EXPECT_FALSE(text::isDigits("4526a"));
}
