// image/image_encode.hpp: every encoder's output is decoded by the codec library itself
// (TurboJPEG, libpng's simplified reader, WebPDecodeRGBA), not by geoslice code, and
// compared with the input: lossless formats exactly, lossy ones with the tolerances below.
#include <png.h>
#include <turbojpeg.h>
#include <webp/decode.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "image/image_encode.hpp"

namespace geoslice {
namespace {

// Levels of 255: JPEG at q85 on flat colour away from an edge stays within 6 levels.
constexpr int kJpegFlatLevels = 6;

struct Rgba {
    int width = 0, height = 0;
    std::vector<std::uint8_t> px;
};

// Section-like: horizontal strata of flat colour with a smooth shading ramp, a dark trace
// line, and a transparent band (background) at the top. 128x96 keeps the test fast.
Rgba sectionImage(int w = 128, int h = 96) {
    Rgba img{w, h, std::vector<std::uint8_t>(std::size_t(w) * h * 4)};
    const std::uint8_t strata[4][3] = {{200, 160, 90}, {90, 140, 60}, {150, 80, 70}, {70, 90, 160}};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = &img.px[(std::size_t(y) * w + x) * 4];
            if (y < h / 8) {
                p[0] = p[1] = p[2] = 0;
                p[3] = 0;
                continue;
            }
            const int layer = std::min(3, (y + x / 8) * 4 / h);
            const double shade = 0.8 + 0.2 * double(x) / w;
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(std::lround(strata[layer][c] * shade));
            p[3] = 255;
            if (x == w / 2) p[0] = p[1] = p[2] = 20;
        }
    return img;
}

Rgba decodeJpeg(const std::vector<std::uint8_t>& bytes) {
    Rgba out;
    tjhandle tj = tjInitDecompress();
    int sub = 0, space = 0;
    EXPECT_EQ(tjDecompressHeader3(tj, bytes.data(), bytes.size(), &out.width, &out.height, &sub, &space), 0);
    out.px.resize(std::size_t(out.width) * out.height * 4);
    EXPECT_EQ(tjDecompress2(tj, bytes.data(), bytes.size(), out.px.data(), out.width, 0, out.height, TJPF_RGBA, 0), 0)
        << tjGetErrorStr2(tj);
    tjDestroy(tj);
    return out;
}

Rgba decodePng(const std::vector<std::uint8_t>& bytes) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    Rgba out;
    if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
        ADD_FAILURE() << "libpng: " << image.message;
        return out;
    }
    image.format = PNG_FORMAT_RGBA;
    out.width = int(image.width);
    out.height = int(image.height);
    out.px.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, out.px.data(), 0, nullptr))
        ADD_FAILURE() << "libpng: " << image.message;
    return out;
}

Rgba decodeWebp(const std::vector<std::uint8_t>& bytes) {
    Rgba out;
    std::uint8_t* px = WebPDecodeRGBA(bytes.data(), bytes.size(), &out.width, &out.height);
    if (!px) {
        ADD_FAILURE() << "WebPDecodeRGBA failed";
        return out;
    }
    out.px.assign(px, px + std::size_t(out.width) * out.height * 4);
    WebPFree(px);
    return out;
}

struct Diff {
    int maxAbs = 0;
    double meanAbs = 0.0;
};
// RGB difference over pixels that are opaque in `ref` (straight alpha: colour under alpha 0
// is undefined), plus the exact alpha check done by the caller.
Diff rgbDiff(const Rgba& ref, const Rgba& got) {
    Diff d;
    std::size_t n = 0;
    for (std::size_t i = 0; i < ref.px.size(); i += 4) {
        if (ref.px[i + 3] == 0) continue;
        for (int c = 0; c < 3; ++c) {
            const int e = std::abs(int(ref.px[i + c]) - int(got.px[i + c]));
            d.maxAbs = std::max(d.maxAbs, e);
            d.meanAbs += e;
            ++n;
        }
    }
    d.meanAbs /= double(std::max<std::size_t>(n, 1));
    return d;
}

TEST(ImageEncode, PngIsLosslessWithAlphaForBothFiltersAndLevels) {
    const Rgba img = sectionImage();
    for (PngFilter filter : {PngFilter::Sub, PngFilter::None})
        for (int level : {0, 1, 2, 6}) {
            EncodeOptions o;
            o.pngFilter = filter;
            o.pngLevel = level;
            auto bytes = encodeImage(img.px, img.width, img.height, ImageFormat::Png, o);
            ASSERT_TRUE(bytes.ok()) << bytes.error().message;
            const Rgba back = decodePng(*bytes);
            ASSERT_EQ(back.width, img.width);
            ASSERT_EQ(back.height, img.height);
            EXPECT_EQ(back.px, img.px) << "level " << level;
        }
}

TEST(ImageEncode, PngWithoutAlphaKeepsRgbExactly) {
    const Rgba img = sectionImage();
    EncodeOptions o;
    o.keepAlpha = false;
    auto bytes = encodeImage(img.px, img.width, img.height, ImageFormat::Png, o);
    ASSERT_TRUE(bytes.ok());
    const Rgba back = decodePng(*bytes);
    ASSERT_EQ(back.px.size(), img.px.size());
    for (std::size_t i = 0; i < img.px.size(); i += 4) {
        ASSERT_EQ(back.px[i + 0], img.px[i + 0]);
        ASSERT_EQ(back.px[i + 1], img.px[i + 1]);
        ASSERT_EQ(back.px[i + 2], img.px[i + 2]);
        ASSERT_EQ(back.px[i + 3], 255);
    }
}

TEST(ImageEncode, ReadPngRgbaReadsWhatWasWritten) {
    const Rgba img = sectionImage(33, 17);  // odd sizes: no row padding assumptions
    const std::string path = testing::TempDir() + "geoslice_encode_roundtrip.png";
    ASSERT_TRUE(writeImage(path, img.px.data(), img.width, img.height).ok());
    auto back = readPngRgba(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 33);
    EXPECT_EQ(back->height, 17);
    EXPECT_EQ(back->rgba, img.px);
    std::remove(path.c_str());
}

TEST(ImageEncode, ReadPngRgbaRejectsMissingAndMalformedFiles) {
    auto missing = readPngRgba(testing::TempDir() + "no_such_dir/none.png");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, ErrorCode::IoError);
    // A valid signature followed by garbage, and a truncated real PNG.
    const std::string path = testing::TempDir() + "geoslice_bad.png";
    const Rgba img = sectionImage(16, 16);
    auto good = encodeImage(img.px, 16, 16, ImageFormat::Png);
    ASSERT_TRUE(good.ok());
    for (std::size_t keep : {std::size_t(8), good->size() / 2}) {
        {
            std::ofstream f(path, std::ios::binary);
            f.write(reinterpret_cast<const char*>(good->data()), std::streamsize(keep));
            f << "garbage";
        }
        auto r = readPngRgba(path);
        ASSERT_FALSE(r.ok()) << "kept " << keep << " bytes";
        EXPECT_EQ(r.error().code, ErrorCode::ParseError);
        EXPECT_NE(r.error().message.find(path), std::string::npos);
    }
    std::remove(path.c_str());
}

// JPEG at q95 with 4:2:0 chroma: the flat strata come back within a few levels; the error
// concentrates at colour edges (chroma is halved), so the max is loose and the mean tight.
TEST(ImageEncode, JpegDecodesWithinTolerance) {
    const Rgba img = sectionImage();
    EncodeOptions o;
    o.jpegQuality = 95;
    o.matte[0] = o.matte[1] = o.matte[2] = 0;  // the transparent band is black RGB anyway
    auto bytes = encodeImage(img.px, img.width, img.height, ImageFormat::Jpeg, o);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    ASSERT_GE(bytes->size(), 4u);
    EXPECT_EQ((*bytes)[0], 0xFF);
    EXPECT_EQ((*bytes)[1], 0xD8);  // SOI
    const Rgba back = decodeJpeg(*bytes);
    ASSERT_EQ(back.width, img.width);
    const Diff d = rgbDiff(img, back);
    EXPECT_LE(d.meanAbs, 3.0);
    EXPECT_LE(d.maxAbs, 90);
}

TEST(ImageEncode, JpegFlattensTransparencyOnTheMatte) {
    Rgba img{32, 32, std::vector<std::uint8_t>(32 * 32 * 4, 0)};  // fully transparent black
    for (std::size_t i = 0; i < img.px.size(); i += 4) {          // right half: 50% red
        if ((i / 4) % 32 >= 16) img.px[i] = 255, img.px[i + 3] = 128;
    }
    EncodeOptions o;
    o.matte[0] = 0, o.matte[1] = 0, o.matte[2] = 255;
    auto bytes = encodeImage(img.px, 32, 32, ImageFormat::Jpeg, o);
    ASSERT_TRUE(bytes.ok());
    const Rgba back = decodeJpeg(*bytes);
    // Away from the edge (x = 16), left is the matte (0,0,255) and right is
    // 128/255 red over 127/255 blue = (128, 0, 127); JPEG at q85: within 6 levels.
    for (int y = 0; y < 32; ++y) {
        const std::uint8_t* l = &back.px[(std::size_t(y) * 32 + 4) * 4];
        const std::uint8_t* r = &back.px[(std::size_t(y) * 32 + 28) * 4];
        EXPECT_NEAR(l[0], 0, kJpegFlatLevels);
        EXPECT_NEAR(l[1], 0, kJpegFlatLevels);
        EXPECT_NEAR(l[2], 255, kJpegFlatLevels);
        EXPECT_NEAR(r[0], 128, kJpegFlatLevels);
        EXPECT_NEAR(r[1], 0, kJpegFlatLevels);
        EXPECT_NEAR(r[2], 127, kJpegFlatLevels);
    }
}

// The JPEG encoder feeds libjpeg 16-row strips (so that a cancel is read per strip) with
// the settings TurboJPEG's one call uses (4:2:0, fast DCT, baseline quality tables): the
// bytes equal tjCompress2's on the same pixels, opaque (RGBX straight in) and with
// transparency (composited on the matte, here by the test, strip by strip in the encoder).
TEST(ImageEncode, JpegStripsEncodeTheBytesOfTurboJpegsOneCall) {
    for (const bool withAlpha : {false, true}) {
        Rgba img = sectionImage(203, 77);  // odd sizes: partial MCUs and a short last strip
        if (!withAlpha)
            for (std::size_t i = 3; i < img.px.size(); i += 4) img.px[i] = 255;
        EncodeOptions o;
        o.jpegQuality = 85;
        o.matte[0] = 10, o.matte[1] = 200, o.matte[2] = 90;
        auto ours = encodeImage(img.px, img.width, img.height, ImageFormat::Jpeg, o);
        ASSERT_TRUE(ours.ok()) << ours.error().message;
        std::vector<std::uint8_t> rgb(std::size_t(img.width) * img.height * 3);
        for (std::size_t i = 0; i * 3 < rgb.size(); ++i) {
            const unsigned a = img.px[4 * i + 3];
            for (int c = 0; c < 3; ++c)
                rgb[3 * i + c] = std::uint8_t((img.px[4 * i + c] * a + o.matte[c] * (255 - a) + 127) / 255);
        }
        tjhandle tj = tjInitCompress();
        unsigned char* out = nullptr;
        unsigned long size = 0;
        ASSERT_EQ(tjCompress2(tj, rgb.data(), img.width, img.width * 3, img.height, TJPF_RGB, &out, &size, TJSAMP_420,
                              o.jpegQuality, TJFLAG_FASTDCT),
                  0)
            << tjGetErrorStr2(tj);
        const std::vector<std::uint8_t> theirs(out, out + size);
        tjFree(out);
        tjDestroy(tj);
        EXPECT_EQ(*ours, theirs) << (withAlpha ? "with transparency" : "opaque");
    }
}

// A set cancel flag stops every encoder with DeadlineExceeded (PNG and JPEG read it per
// 16 rows, WebP in its progress hook, which libwebp calls before the colour pass).
TEST(ImageEncode, ACancelledEncodeIsDeadlineExceeded) {
    const Rgba img = sectionImage(256, 256);
    std::atomic<bool> cancel{true};
    for (ImageFormat f : {ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Webp}) {
        EncodeOptions o;
        o.cancel = &cancel;
        auto r = encodeImage(img.px, img.width, img.height, f, o);
        ASSERT_FALSE(r.ok()) << extension(f);
        EXPECT_EQ(r.error().code, ErrorCode::DeadlineExceeded) << extension(f) << ": " << r.error().message;
        EXPECT_NE(r.error().message.find("cancelled"), std::string::npos) << r.error().message;
        o.cancel = nullptr;
        EXPECT_TRUE(encodeImage(img.px, img.width, img.height, f, o).ok()) << extension(f);
    }
}

TEST(ImageEncode, WebpLossyKeepsAlphaAndColourWithinTolerance) {
    const Rgba img = sectionImage();
    EncodeOptions o;
    o.webpQuality = 95;
    auto bytes = encodeImage(img.px, img.width, img.height, ImageFormat::Webp, o);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    const Rgba back = decodeWebp(*bytes);
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    // Alpha of a two-level (0/255) mask is coded losslessly by default (alpha_quality 100).
    for (std::size_t i = 3; i < img.px.size(); i += 4) ASSERT_EQ(back.px[i], img.px[i]) << "pixel " << i / 4;
    // Lossy VP8 is 4:2:0 YUV like JPEG, with method 0 (the fastest): same kind of bounds.
    const Diff d = rgbDiff(img, back);
    EXPECT_LE(d.meanAbs, 4.0);
    EXPECT_LE(d.maxAbs, 110);
}

TEST(ImageEncode, WebpLosslessIsExactWhereOpaque) {
    const Rgba img = sectionImage();
    EncodeOptions o;
    o.webpLossless = true;
    auto bytes = encodeImage(img.px, img.width, img.height, ImageFormat::Webp, o);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    const Rgba back = decodeWebp(*bytes);
    for (std::size_t i = 3; i < img.px.size(); i += 4) ASSERT_EQ(back.px[i], img.px[i]);
    EXPECT_EQ(rgbDiff(img, back).maxAbs, 0);
}

TEST(ImageEncode, BadSizesAndOptionsAreErrors) {
    const Rgba img = sectionImage(16, 16);
    for (ImageFormat f : {ImageFormat::Png, ImageFormat::Jpeg, ImageFormat::Webp}) {
        for (auto [w, h] : {std::pair{0, 16}, std::pair{16, 0}, std::pair{-4, 16}}) {
            auto r = encodeImage(img.px.data(), w, h, f);
            ASSERT_FALSE(r.ok());
            EXPECT_EQ(r.error().code, ErrorCode::InvalidArgument);
        }
        auto tooFew = encodeImage(img.px, 16, 17, f);
        ASSERT_FALSE(tooFew.ok());
        EXPECT_NE(tooFew.error().message.find("16x17"), std::string::npos) << tooFew.error().message;
        EXPECT_FALSE(encodeImage(nullptr, 16, 16, f).ok());
        // One side past the format's limit, checked before any pixel is read.
        auto huge = encodeImage(img.px.data(), maxImageSide(f) + 1, 1, f);
        ASSERT_FALSE(huge.ok());
        EXPECT_EQ(huge.error().code, ErrorCode::InvalidArgument);
    }
    EncodeOptions o;
    o.jpegQuality = 0;
    EXPECT_FALSE(encodeImage(img.px, 16, 16, ImageFormat::Jpeg, o).ok());
    o = {};
    o.pngLevel = 10;
    EXPECT_FALSE(encodeImage(img.px, 16, 16, ImageFormat::Png, o).ok());
    o = {};
    o.webpMethod = 7;
    EXPECT_FALSE(encodeImage(img.px, 16, 16, ImageFormat::Webp, o).ok());
    o = {};
    o.webpQuality = -1;
    EXPECT_FALSE(encodeImage(img.px, 16, 16, ImageFormat::Webp, o).ok());
}

TEST(ImageEncode, FormatsFromNamesAndPaths) {
    EXPECT_EQ(imageFormatFromName("JPG").value(), ImageFormat::Jpeg);
    EXPECT_EQ(imageFormatFromName(".jpeg").value(), ImageFormat::Jpeg);
    EXPECT_EQ(imageFormatFromName("png").value(), ImageFormat::Png);
    EXPECT_EQ(imageFormatFromName("WebP").value(), ImageFormat::Webp);
    EXPECT_FALSE(imageFormatFromName("tiff").ok());
    EXPECT_FALSE(imageFormatFromName("").ok());
    EXPECT_EQ(imageFormatFromPath("/a/b.c/section.PNG").value(), ImageFormat::Png);
    EXPECT_EQ(imageFormatFromPath("x.webp").value(), ImageFormat::Webp);
    auto noExt = imageFormatFromPath("/tmp/dir.d/section");
    ASSERT_FALSE(noExt.ok());
    EXPECT_NE(noExt.error().message.find("/tmp/dir.d/section"), std::string::npos);
    EXPECT_STREQ(mimeType(ImageFormat::Jpeg), "image/jpeg");
    EXPECT_STREQ(mimeType(ImageFormat::Webp), "image/webp");
    EXPECT_STREQ(extension(ImageFormat::Png), "png");
}

TEST(ImageEncode, WriteImageChoosesTheCodecByExtensionAndReportsIoErrors) {
    const Rgba img = sectionImage(24, 24);
    const std::string dir = testing::TempDir();
    const std::pair<const char*, std::vector<std::uint8_t>> magic[] = {
        {"x.jpg", {0xFF, 0xD8, 0xFF}}, {"x.png", {0x89, 'P', 'N', 'G'}}, {"x.webp", {'R', 'I', 'F', 'F'}}};
    for (const auto& [name, head] : magic) {
        const std::string path = dir + "geoslice_write_" + name;
        ASSERT_TRUE(writeImage(path, img.px.data(), 24, 24).ok()) << path;
        std::ifstream f(path, std::ios::binary);
        std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        ASSERT_GE(bytes.size(), head.size());
        EXPECT_TRUE(std::equal(head.begin(), head.end(), bytes.begin())) << name;
        std::remove(path.c_str());
    }
    auto io = writeImage(dir + "no_such_dir/x.png", img.px.data(), 24, 24);
    ASSERT_FALSE(io.ok());
    EXPECT_EQ(io.error().code, ErrorCode::IoError);
    auto ext = writeImage(dir + "x.bmp", img.px.data(), 24, 24);
    ASSERT_FALSE(ext.ok());
    EXPECT_EQ(ext.error().code, ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace geoslice

namespace geoslice {
namespace {

// 16-bit ids: decoded by libpng's simplified reader as 16-bit linear gray, exactly.
TEST(ImageEncode, Gray16PngKeepsValuesExactlyAndRejectsWideOnes) {
    const int w = 37, h = 11;
    std::vector<std::uint32_t> v(std::size_t(w) * h);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t((i * 2654435761u) & 0xffff);
    auto bytes = encodeGray16Png(v.data(), w, h);
    ASSERT_TRUE(bytes.ok()) << bytes.error().message;
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_memory(&image, bytes->data(), bytes->size())) << image.message;
    EXPECT_EQ(int(image.width), w);
    EXPECT_EQ(image.format & PNG_FORMAT_FLAG_LINEAR, PNG_FORMAT_FLAG_LINEAR);  // 16-bit stays 16-bit
    image.format = PNG_FORMAT_LINEAR_Y;
    std::vector<std::uint16_t> back(v.size());
    ASSERT_TRUE(png_image_finish_read(&image, nullptr, back.data(), 0, nullptr)) << image.message;
    for (std::size_t i = 0; i < v.size(); ++i) ASSERT_EQ(back[i], v[i]) << "pixel " << i;
    v[5] = 70000;
    auto wide = encodeGray16Png(v.data(), w, h);
    ASSERT_FALSE(wide.ok());
    EXPECT_EQ(wide.error().code, ErrorCode::OutOfRange);
    EXPECT_NE(wide.error().message.find("70000"), std::string::npos);
    EXPECT_FALSE(encodeGray16Png(v.data(), 0, h).ok());
    EXPECT_FALSE(encodeGray16Png(nullptr, w, h).ok());
}

}  // namespace
}  // namespace geoslice
