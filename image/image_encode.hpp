// Image encoders for the hot path: JPEG (libjpeg-turbo), PNG (libpng, fast zlib settings)
// and WebP (libwebp). Input is straight-alpha RGBA8, rows top first, tightly packed.
// Pure functions, any thread, no GL.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "model/result.hpp"

namespace geoslice {

enum class ImageFormat { Png, Jpeg, Webp };

// PNG row filter: SUB (good on smooth sections) or NONE (fastest; flat fills compress
// well anyway). Adaptive filtering is what makes libpng's default 5-10x slower.
enum class PngFilter { Sub, None };

struct EncodeOptions {
    int jpegQuality = 85;  // 1..100
    int pngLevel = 1;      // zlib level 0..9; 1-2 with SUB/NONE filters is the fast path
    PngFilter pngFilter = PngFilter::Sub;
    int webpQuality = 80;  // 0..100 (lossy)
    int webpMethod = 0;    // 0 (fastest)..6
    bool webpLossless = false;
    bool keepAlpha = true;                    // PNG/WebP: keep alpha; JPEG always flattens on `matte`
    std::uint8_t matte[3] = {255, 255, 255};  // JPEG: background under transparent pixels
    // Cancellation (any thread may set it): PNG reads it every 16 rows, JPEG every 16-row
    // strip, WebP in its progress hook (each percent of the colour pass; libwebp's alpha
    // pass reports nothing and runs to its end); when set, encoding stops with
    // DeadlineExceeded. nullptr = never.
    const std::atomic<bool>* cancel = nullptr;
};

// "jpg"/"jpeg"/"png"/"webp" (case-insensitive, with or without a leading dot) -> format.
// Error InvalidArgument naming the extension otherwise.
Result<ImageFormat> imageFormatFromName(std::string_view name);
// The format of a file path from its extension.
Result<ImageFormat> imageFormatFromPath(std::string_view path);
// "image/jpeg", "image/png", "image/webp"; file extension "jpg", "png", "webp".
const char* mimeType(ImageFormat format);
const char* extension(ImageFormat format);

// Encodes width x height RGBA8 pixels. Errors: InvalidArgument (size <= 0, too few
// bytes), Internal (codec failure, with the codec's message).
Result<std::vector<std::uint8_t>> encodeImage(const std::uint8_t* rgba, int width, int height, ImageFormat format,
                                              const EncodeOptions& options = {});
// The same with the buffer's size checked: InvalidArgument unless rgba.size() == w*h*4.
Result<std::vector<std::uint8_t>> encodeImage(const std::vector<std::uint8_t>& rgba, int width, int height,
                                              ImageFormat format, const EncodeOptions& options = {});
// Largest side each format can hold (JPEG 65500, PNG 1,000,000 by libpng's default user
// limit, WebP 16383).
int maxImageSide(ImageFormat format);

// Values 0..65535 (e.g. record ids) as a 16-bit grayscale PNG with the fast settings of
// `options` (pngLevel, pngFilter). Errors: InvalidArgument (size), OutOfRange naming the
// first value above 65535, Internal (codec).
Result<std::vector<std::uint8_t>> encodeGray16Png(const std::uint32_t* values, int width, int height,
                                                  const EncodeOptions& options = {});
// Writes bytes to a file; IoError naming the path.
Status writeFile(const std::string& path, const std::vector<std::uint8_t>& bytes);

// Decodes a PNG file (8-bit gray/RGB/RGBA, palette expanded) to RGBA8, rows top first:
// the reader for golden images. Errors: IoError naming the path, ParseError for a file
// libpng rejects.
struct DecodedImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
};
Result<DecodedImage> readPngRgba(const std::string& path);

// Encodes by the path's extension and writes the file. Errors also: IoError naming the path.
Status writeImage(const std::string& path, const std::uint8_t* rgba, int width, int height,
                  const EncodeOptions& options = {});

}  // namespace geoslice
