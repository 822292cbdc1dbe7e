// Direct codec calls rather than OpenImageIO: OIIO's ImageOutput takes the pixels through
// its own ImageSpec/format-conversion layer and writes to an IOProxy, which costs an extra
// copy and a per-call plugin lookup, and OIIO 2.4 does not expose libwebp's `method`, the
// setting that makes WebP fast enough for a hot path (figures in bench/encode.cpp). The
// libraries are the ones OIIO would call.
#include "image/image_encode.hpp"

#include <png.h>
// jpeglib.h needs FILE and size_t declared first.
#include <jerror.h>
#include <jpeglib.h>
#include <webp/encode.h>
#include <cstddef>
#include <cstdio>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

namespace geoslice {
namespace {

constexpr int kMaxJpegSide = 65500;   // JPEG_MAX_DIMENSION
constexpr int kMaxPngSide = 1000000;  // libpng's default user width/height limit
constexpr int kMaxWebpSide = WEBP_MAX_DIMENSION;

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

bool allOpaque(const std::uint8_t* rgba, std::size_t pixels) {
    for (std::size_t i = 0; i < pixels; ++i)
        if (rgba[4 * i + 3] != 255) return false;
    return true;
}

// libjpeg reports errors through error_exit, which must not return: it longjmps back
// like libpng's handler. Everything with a destructor lives in encodeJpeg; the frames
// between setjmp and the handler hold only trivial locals.
struct JpegErrorState {
    jpeg_error_mgr manager;  // first, so that the codec's pointer to it is a pointer to us
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
};
void jpegErrorExit(j_common_ptr codec) {
    auto* st = reinterpret_cast<JpegErrorState*>(codec->err);
    (*codec->err->format_message)(codec, st->message);
    std::longjmp(st->jump, 1);
}
void jpegNoMessage(j_common_ptr, int) {}  // warnings and traces: nothing on stderr

// libjpeg's own memory destination hands its buffer back only when compression finishes,
// so a cancelled or failed encode would lose (or free twice) what it had written: the
// bytes go into the caller's vector instead, a chunk at a time, like the PNG writer's.
struct JpegVectorDestination {
    jpeg_destination_mgr manager;  // first, so that the codec's pointer to it is a pointer to us
    std::vector<std::uint8_t>* bytes = nullptr;
    std::uint8_t* chunk = nullptr;
    std::size_t chunkSize = 0;
};
void jpegDestinationInit(j_compress_ptr codec) {
    auto* d = reinterpret_cast<JpegVectorDestination*>(codec->dest);
    d->manager.next_output_byte = d->chunk;
    d->manager.free_in_buffer = d->chunkSize;
}
void jpegAppend(j_compress_ptr codec, std::size_t n) {
    auto* d = reinterpret_cast<JpegVectorDestination*>(codec->dest);
    try {
        d->bytes->insert(d->bytes->end(), d->chunk, d->chunk + n);
    } catch (...) {
        codec->err->msg_code = JERR_OUT_OF_MEMORY;
        (*codec->err->error_exit)(reinterpret_cast<j_common_ptr>(codec));
    }
}
boolean jpegDestinationFull(j_compress_ptr codec) {
    auto* d = reinterpret_cast<JpegVectorDestination*>(codec->dest);
    jpegAppend(codec, d->chunkSize);
    jpegDestinationInit(codec);
    return TRUE;
}
void jpegDestinationEnd(j_compress_ptr codec) {
    auto* d = reinterpret_cast<JpegVectorDestination*>(codec->dest);
    jpegAppend(codec, d->chunkSize - d->manager.free_in_buffer);
}

// The composited rows of one strip: straight alpha over the matte, RGB.
void flattenRows(const std::uint8_t* rgba, int width, int y0, int rows, const std::uint8_t matte[3],
                 std::uint8_t* out) {
    const std::size_t n = std::size_t(width) * std::size_t(rows);
    const std::uint8_t* src = rgba + std::size_t(y0) * std::size_t(width) * 4;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* p = &src[4 * i];
        std::uint8_t* q = &out[3 * i];
        const unsigned a = p[3];
        if (a == 255) {
            q[0] = p[0], q[1] = p[1], q[2] = p[2];
        } else if (a == 0) {
            q[0] = matte[0], q[1] = matte[1], q[2] = matte[2];
        } else {
            for (int c = 0; c < 3; ++c) q[c] = static_cast<std::uint8_t>((p[c] * a + matte[c] * (255 - a) + 127) / 255);
        }
    }
}

constexpr int kJpegStripRows = 16;  // one 4:2:0 MCU row: the cancel flag is read per strip

// Returns 1 done, 0 codec error (st.message), -1 cancelled. `strip` holds kJpegStripRows
// RGB rows when the frame is not opaque; `destination` appends to the caller's bytes.
int jpegEncodeRaw(const std::uint8_t* rgba, int width, int height, bool opaque, const EncodeOptions& o,
                  std::uint8_t* strip, JpegErrorState& st, JpegVectorDestination& destination) {
    jpeg_compress_struct codec;
    codec.err = jpeg_std_error(&st.manager);
    st.manager.error_exit = jpegErrorExit;
    st.manager.emit_message = jpegNoMessage;
    if (setjmp(st.jump)) {
        jpeg_destroy_compress(&codec);
        return 0;
    }
    jpeg_create_compress(&codec);
    destination.manager.init_destination = jpegDestinationInit;
    destination.manager.empty_output_buffer = jpegDestinationFull;
    destination.manager.term_destination = jpegDestinationEnd;
    codec.dest = &destination.manager;
    codec.image_width = JDIMENSION(width);
    codec.image_height = JDIMENSION(height);
    codec.input_components = opaque ? 4 : 3;
    codec.in_color_space = opaque ? JCS_EXT_RGBX : JCS_RGB;
    jpeg_set_defaults(&codec);
    jpeg_set_quality(&codec, o.jpegQuality, TRUE);
    codec.dct_method = JDCT_FASTEST;
    // 4:2:0: luma at full resolution, chroma halved both ways.
    codec.comp_info[0].h_samp_factor = codec.comp_info[0].v_samp_factor = 2;
    for (int c = 1; c < 3; ++c) codec.comp_info[c].h_samp_factor = codec.comp_info[c].v_samp_factor = 1;
    jpeg_start_compress(&codec, TRUE);
    JSAMPROW rows[kJpegStripRows];
    while (codec.next_scanline < codec.image_height) {
        if (o.cancel && o.cancel->load(std::memory_order_relaxed)) {
            jpeg_destroy_compress(&codec);
            return -1;
        }
        const int y0 = int(codec.next_scanline);
        const int n = std::min(kJpegStripRows, height - y0);
        if (opaque) {
            for (int r = 0; r < n; ++r)
                rows[r] = const_cast<JSAMPROW>(rgba + std::size_t(y0 + r) * std::size_t(width) * 4);
        } else {
            flattenRows(rgba, width, y0, n, o.matte, strip);
            for (int r = 0; r < n; ++r) rows[r] = strip + std::size_t(r) * std::size_t(width) * 3;
        }
        for (int done = 0; done < n;) done += int(jpeg_write_scanlines(&codec, rows + done, JDIMENSION(n - done)));
    }
    jpeg_finish_compress(&codec);
    jpeg_destroy_compress(&codec);
    return 1;
}

Result<std::vector<std::uint8_t>> encodeJpeg(const std::uint8_t* rgba, int width, int height, const EncodeOptions& o) {
    if (o.jpegQuality < 1 || o.jpegQuality > 100)
        return makeError(ErrorCode::InvalidArgument,
                         "JPEG quality " + std::to_string(o.jpegQuality) + " is outside 1..100");
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    // JPEG has no alpha: straight alpha is composited over the matte, a strip at a time.
    // Opaque frames (the common case with a coloured background) go to the codec as RGBX.
    const bool opaque = allOpaque(rgba, pixels);
    std::vector<std::uint8_t> strip(opaque ? 0 : std::size_t(width) * 3 * kJpegStripRows);
    JpegErrorState st;
    std::vector<std::uint8_t> bytes;
    bytes.reserve(pixels / 8);
    std::vector<std::uint8_t> chunk(std::size_t(1) << 16);
    JpegVectorDestination destination;
    destination.bytes = &bytes;
    destination.chunk = chunk.data();
    destination.chunkSize = chunk.size();
    const int rc = jpegEncodeRaw(rgba, width, height, opaque, o, strip.data(), st, destination);
    if (rc < 0) return makeError(ErrorCode::DeadlineExceeded, "cancelled while encoding JPEG");
    if (rc == 0) return makeError(ErrorCode::Internal, std::string("JPEG encoding failed: ") + st.message);
    return bytes;
}

// libpng reports errors by longjmp: everything with a destructor lives in the caller, the
// frames between setjmp and the error handler hold only trivial locals.
struct PngWriteState {
    std::vector<std::uint8_t>* bytes = nullptr;
    char message[256] = {};
    bool cancelled = false;
};

void pngWrite(png_structp png, png_bytep data, png_size_t length) {
    auto* st = static_cast<PngWriteState*>(png_get_io_ptr(png));
    try {
        st->bytes->insert(st->bytes->end(), data, data + length);
    } catch (...) {
        png_error(png, "out of memory");
    }
}
void pngFlush(png_structp) {}
void pngError(png_structp png, png_const_charp msg) {
    auto* st = static_cast<PngWriteState*>(png_get_error_ptr(png));
    std::snprintf(st->message, sizeof st->message, "%s", msg);
    png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

// Returns false with st.message set on a codec error. `rows`: height rows of `stride`
// bytes in PNG sample order (16-bit samples big-endian).
bool pngEncodeRaw(const std::uint8_t* rows, std::size_t stride, int width, int height, int bitDepth, int colourType,
                  const EncodeOptions& o, PngWriteState& st) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &st, pngError, pngWarning);
    if (!png) {
        std::snprintf(st.message, sizeof st.message, "png_create_write_struct failed");
        return false;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        if (!info) std::snprintf(st.message, sizeof st.message, "png_create_info_struct failed");
        png_destroy_write_struct(&png, info ? &info : nullptr);
        return false;
    }
    png_set_write_fn(png, &st, pngWrite, pngFlush);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bitDepth, colourType, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, o.pngLevel);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, o.pngFilter == PngFilter::Sub ? PNG_FILTER_SUB : PNG_FILTER_NONE);
    png_set_compression_buffer_size(png, 1 << 17);
    png_write_info(png, info);
    for (int y = 0; y < height; ++y) {
        if ((y & 15) == 0 && o.cancel && o.cancel->load(std::memory_order_relaxed)) {
            st.cancelled = true;
            std::snprintf(st.message, sizeof st.message, "cancelled");
            png_destroy_write_struct(&png, &info);
            return false;
        }
        png_write_row(png, const_cast<png_bytep>(rows + std::size_t(y) * stride));
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

Result<std::vector<std::uint8_t>> encodePng(const std::uint8_t* rgba, int width, int height, const EncodeOptions& o) {
    if (o.pngLevel < 0 || o.pngLevel > 9)
        return makeError(ErrorCode::InvalidArgument,
                         "PNG zlib level " + std::to_string(o.pngLevel) + " is outside 0..9");
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::vector<std::uint8_t> rgb;
    if (!o.keepAlpha) {
        rgb.resize(pixels * 3);
        for (std::size_t i = 0; i < pixels; ++i) std::memcpy(&rgb[3 * i], &rgba[4 * i], 3);
    }
    std::vector<std::uint8_t> bytes;
    bytes.reserve(pixels / 2);
    PngWriteState st;
    st.bytes = &bytes;
    const bool ok = o.keepAlpha
                        ? pngEncodeRaw(rgba, std::size_t(width) * 4, width, height, 8, PNG_COLOR_TYPE_RGB_ALPHA, o, st)
                        : pngEncodeRaw(rgb.data(), std::size_t(width) * 3, width, height, 8, PNG_COLOR_TYPE_RGB, o, st);
    if (st.cancelled) return makeError(ErrorCode::DeadlineExceeded, "cancelled while encoding PNG");
    if (!ok) return makeError(ErrorCode::Internal, std::string("PNG encoding failed: ") + st.message);
    return bytes;
}

const char* webpErrorText(WebPEncodingError e) {
    switch (e) {
        case VP8_ENC_ERROR_OUT_OF_MEMORY:
            return "out of memory";
        case VP8_ENC_ERROR_BITSTREAM_OUT_OF_MEMORY:
            return "bitstream out of memory";
        case VP8_ENC_ERROR_BAD_DIMENSION:
            return "bad dimension";
        case VP8_ENC_ERROR_PARTITION0_OVERFLOW:
            return "partition 0 overflow";
        case VP8_ENC_ERROR_PARTITION_OVERFLOW:
            return "partition overflow";
        case VP8_ENC_ERROR_BAD_WRITE:
            return "bad write";
        case VP8_ENC_ERROR_FILE_TOO_BIG:
            return "file too big";
        default:
            return "error";
    }
}

Result<std::vector<std::uint8_t>> encodeWebp(const std::uint8_t* rgba, int width, int height, const EncodeOptions& o) {
    if (o.webpQuality < 0 || o.webpQuality > 100)
        return makeError(ErrorCode::InvalidArgument,
                         "WebP quality " + std::to_string(o.webpQuality) + " is outside 0..100");
    if (o.webpMethod < 0 || o.webpMethod > 6)
        return makeError(ErrorCode::InvalidArgument,
                         "WebP method " + std::to_string(o.webpMethod) + " is outside 0..6");
    WebPConfig config;
    if (!WebPConfigInit(&config)) return makeError(ErrorCode::Internal, "WebP: library version mismatch");
    config.quality = float(o.webpQuality);
    config.method = o.webpMethod;
    config.lossless = o.webpLossless ? 1 : 0;
    if (!WebPValidateConfig(&config)) return makeError(ErrorCode::Internal, "WebP: invalid configuration");
    WebPPicture pic;
    if (!WebPPictureInit(&pic)) return makeError(ErrorCode::Internal, "WebP: library version mismatch");
    pic.use_argb = o.webpLossless ? 1 : 0;
    pic.width = width;
    pic.height = height;
    struct PicGuard {
        WebPPicture* p;
        WebPMemoryWriter* w;
        ~PicGuard() {
            WebPPictureFree(p);
            WebPMemoryWriterClear(w);
        }
    };
    WebPMemoryWriter writer;
    WebPMemoryWriterInit(&writer);
    PicGuard guard{&pic, &writer};
    const int imported =
        o.keepAlpha ? WebPPictureImportRGBA(&pic, rgba, width * 4) : WebPPictureImportRGBX(&pic, rgba, width * 4);
    if (!imported) return makeError(ErrorCode::Internal, "WebP: cannot import " + sizeText(width, height) + " pixels");
    pic.writer = WebPMemoryWrite;
    pic.custom_ptr = &writer;
    pic.user_data = const_cast<std::atomic<bool>*>(o.cancel);
    pic.progress_hook = [](int, const WebPPicture* p) -> int {
        const auto* cancel = static_cast<const std::atomic<bool>*>(p->user_data);
        return cancel && cancel->load(std::memory_order_relaxed) ? 0 : 1;  // 0 aborts
    };
    if (!WebPEncode(&config, &pic)) {
        if (pic.error_code == VP8_ENC_ERROR_USER_ABORT)
            return makeError(ErrorCode::DeadlineExceeded, "cancelled while encoding WebP");
        return makeError(ErrorCode::Internal, std::string("WebP encoding failed: ") + webpErrorText(pic.error_code));
    }
    return std::vector<std::uint8_t>(writer.mem, writer.mem + writer.size);
}

// PNG reading for goldens; same longjmp discipline as the writer.
struct PngReadState {
    std::FILE* file = nullptr;
    char message[256] = {};
};
void pngReadError(png_structp png, png_const_charp msg) {
    auto* st = static_cast<PngReadState*>(png_get_error_ptr(png));
    std::snprintf(st->message, sizeof st->message, "%s", msg);
    png_longjmp(png, 1);
}

// Two passes through the same png struct: header (sizes out) then rows into `out`, which
// the caller sizes. Trivial locals only between setjmp and the handler.
bool pngDecodeRaw(PngReadState& st, int& width, int& height, std::vector<std::uint8_t>& out) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &st, pngReadError, pngWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    png_bytep* volatile rowPointers = nullptr;  // volatile: read after longjmp
    if (!info || setjmp(png_jmpbuf(png))) {
        std::free(rowPointers);
        png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        return false;
    }
    png_init_io(png, st.file);
    png_read_info(png, info);
    png_set_expand(png);
    png_set_strip_16(png);
    png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
    png_read_update_info(png, info);
    width = int(png_get_image_width(png, info));
    height = int(png_get_image_height(png, info));
    if (png_get_rowbytes(png, info) != std::size_t(width) * 4) png_error(png, "unexpected row size after expansion");
    if (std::size_t(width) * std::size_t(height) > (std::size_t(1) << 28)) png_error(png, "image too large");
    out.resize(std::size_t(width) * std::size_t(height) * 4);  // bad_alloc impossible at this cap in practice
    rowPointers = static_cast<png_bytep*>(std::malloc(sizeof(png_bytep) * std::size_t(height)));
    if (!rowPointers) png_error(png, "out of memory");
    for (int y = 0; y < height; ++y) rowPointers[y] = out.data() + std::size_t(y) * std::size_t(width) * 4;
    png_read_image(png, rowPointers);
    png_read_end(png, nullptr);
    std::free(rowPointers);
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

}  // namespace

Result<ImageFormat> imageFormatFromName(std::string_view name) {
    std::string n(name);
    if (!n.empty() && n.front() == '.') n.erase(0, 1);
    for (char& c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (n == "jpg" || n == "jpeg") return ImageFormat::Jpeg;
    if (n == "png") return ImageFormat::Png;
    if (n == "webp") return ImageFormat::Webp;
    return makeError(ErrorCode::InvalidArgument,
                     "image format '" + std::string(name) + "' is not one of jpg, jpeg, png, webp");
}

Result<ImageFormat> imageFormatFromPath(std::string_view path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash))
        return makeError(ErrorCode::InvalidArgument,
                         "image path '" + std::string(path) + "' has no extension (expected .jpg, .png or .webp)");
    auto f = imageFormatFromName(path.substr(dot + 1));
    if (!f) return makeError(ErrorCode::InvalidArgument, std::string(path) + ": " + f.error().message);
    return f;
}

const char* mimeType(ImageFormat format) {
    switch (format) {
        case ImageFormat::Jpeg:
            return "image/jpeg";
        case ImageFormat::Png:
            return "image/png";
        case ImageFormat::Webp:
            return "image/webp";
    }
    return "application/octet-stream";
}

const char* extension(ImageFormat format) {
    switch (format) {
        case ImageFormat::Jpeg:
            return "jpg";
        case ImageFormat::Png:
            return "png";
        case ImageFormat::Webp:
            return "webp";
    }
    return "bin";
}

int maxImageSide(ImageFormat format) {
    switch (format) {
        case ImageFormat::Jpeg:
            return kMaxJpegSide;
        case ImageFormat::Png:
            return kMaxPngSide;
        case ImageFormat::Webp:
            return kMaxWebpSide;
    }
    return 0;
}

Result<std::vector<std::uint8_t>> encodeImage(const std::uint8_t* rgba, int width, int height, ImageFormat format,
                                              const EncodeOptions& options) {
    if (width <= 0 || height <= 0)
        return makeError(ErrorCode::InvalidArgument, "cannot encode a " + sizeText(width, height) + " image");
    if (width > maxImageSide(format) || height > maxImageSide(format))
        return makeError(ErrorCode::InvalidArgument, std::string(extension(format)) + " cannot hold a " +
                                                         sizeText(width, height) + " image (at most " +
                                                         std::to_string(maxImageSide(format)) + " per side)");
    if (!rgba) return makeError(ErrorCode::InvalidArgument, "no pixels to encode (null buffer)");
    switch (format) {
        case ImageFormat::Jpeg:
            return encodeJpeg(rgba, width, height, options);
        case ImageFormat::Png:
            return encodePng(rgba, width, height, options);
        case ImageFormat::Webp:
            return encodeWebp(rgba, width, height, options);
    }
    return makeError(ErrorCode::InvalidArgument, "unknown image format");
}

Result<std::vector<std::uint8_t>> encodeImage(const std::vector<std::uint8_t>& rgba, int width, int height,
                                              ImageFormat format, const EncodeOptions& options) {
    if (width <= 0 || height <= 0)
        return makeError(ErrorCode::InvalidArgument, "cannot encode a " + sizeText(width, height) + " image");
    if (rgba.size() != std::size_t(width) * std::size_t(height) * 4)
        return makeError(ErrorCode::InvalidArgument, "RGBA buffer of " + std::to_string(rgba.size()) +
                                                         " bytes does not match " + sizeText(width, height) +
                                                         " (expected width*height*4)");
    return encodeImage(rgba.data(), width, height, format, options);
}

Result<std::vector<std::uint8_t>> encodeGray16Png(const std::uint32_t* values, int width, int height,
                                                  const EncodeOptions& options) {
    if (width <= 0 || height <= 0 || width > kMaxPngSide || height > kMaxPngSide)
        return makeError(ErrorCode::InvalidArgument, "cannot encode a " + sizeText(width, height) + " 16-bit PNG");
    if (!values) return makeError(ErrorCode::InvalidArgument, "no values to encode (null buffer)");
    if (options.pngLevel < 0 || options.pngLevel > 9)
        return makeError(ErrorCode::InvalidArgument,
                         "PNG zlib level " + std::to_string(options.pngLevel) + " is outside 0..9");
    const std::size_t n = std::size_t(width) * std::size_t(height);
    std::vector<std::uint8_t> samples(n * 2);
    for (std::size_t i = 0; i < n; ++i) {
        if (values[i] > 0xffff)
            return makeError(ErrorCode::OutOfRange, "value " + std::to_string(values[i]) + " at pixel " +
                                                        std::to_string(i) + " does not fit a 16-bit PNG");
        samples[2 * i] = std::uint8_t(values[i] >> 8);
        samples[2 * i + 1] = std::uint8_t(values[i] & 0xff);
    }
    std::vector<std::uint8_t> bytes;
    PngWriteState st;
    st.bytes = &bytes;
    if (!pngEncodeRaw(samples.data(), std::size_t(width) * 2, width, height, 16, PNG_COLOR_TYPE_GRAY, options, st))
        return makeError(ErrorCode::Internal, std::string("PNG encoding failed: ") + st.message);
    return bytes;
}

Status writeFile(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return makeError(ErrorCode::IoError, "cannot open " + path + ": " + std::strerror(errno));
    const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
    if (std::fclose(f) != 0 || !ok) return makeError(ErrorCode::IoError, "cannot write " + path);
    return {};
}

Status writeImage(const std::string& path, const std::uint8_t* rgba, int width, int height,
                  const EncodeOptions& options) {
    auto format = imageFormatFromPath(path);
    if (!format) return format.error();
    auto bytes = encodeImage(rgba, width, height, *format, options);
    if (!bytes) return makeError(bytes.error().code, path + ": " + bytes.error().message);
    return writeFile(path, *bytes);
}

Result<DecodedImage> readPngRgba(const std::string& path) {
    PngReadState st;
    st.file = std::fopen(path.c_str(), "rb");
    if (!st.file) return makeError(ErrorCode::IoError, "cannot open " + path + ": " + std::strerror(errno));
    unsigned char sig[8] = {};
    const bool isPng = std::fread(sig, 1, 8, st.file) == 8 && png_sig_cmp(sig, 0, 8) == 0;
    if (!isPng) {
        std::fclose(st.file);
        return makeError(ErrorCode::ParseError, path + ": not a PNG file (bad signature)");
    }
    std::rewind(st.file);
    DecodedImage img;
    const bool ok = pngDecodeRaw(st, img.width, img.height, img.rgba);
    std::fclose(st.file);
    if (!ok) return makeError(ErrorCode::ParseError, path + ": " + (st.message[0] ? st.message : "libpng failed"));
    return img;
}

}  // namespace geoslice
