// What one view (an image, a tile, a 3D view) may ask for, in one place: image size, pixel
// size, coordinates, camera distance and field of view, vertical exaggeration, batch
// queries. Every entry point (HTTP parameters, the CLI's render/section/query, the section
// engine and the renderer) checks a view against these before any work, through the check*
// functions below, so the CLI refuses what HTTP refuses with the same reason (only the name
// of the parameter or flag differs: tests/server/view_limits_agree_test.cpp). Every raster
// loop is bounded by the pixel counts they allow, never by a ratio of user numbers. Pure
// constants and functions, any thread.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "model/limits.hpp"
#include "model/result.hpp"

namespace geoslice {

// Image size, pixels: each side 1..kMaxImageSide, at most kMaxImagePixels in all.
constexpr int kMaxImageSide = 8192;
constexpr std::size_t kMaxImagePixels = std::size_t(1) << 26;
// The smallest pixel along either frame axis, metres. A pixel must also span at least
// kMinPixelUlps steps of a double at the frame's coordinates, so that every pixel centre
// has its own coordinate (a frame 1e-300 m wide overflows the pixel scale to infinity).
constexpr double kMinPixelMetres = 1e-6;
constexpr double kMinPixelUlps = 64.0;
// Perspective cameras: eye-to-target distance and vertical field of view.
constexpr double kMinCameraDistanceMetres = 1e-3;
constexpr double kMinFovDeg = 1.0, kMaxFovDeg = 170.0;
// Vertical exaggeration factors (dimensionless; view/exaggeration.hpp).
constexpr double kMinExaggeration = 0.1, kMaxExaggeration = 100.0;
// Batch pixel queries (POST /query): pixels per batch and bytes of answer (a pixel's
// answer is about 1.1 kB of JSON).
constexpr std::size_t kMaxBatchPixels = 5000;
constexpr std::size_t kMaxBatchAnswerBytes = std::size_t(8) << 20;

// A number as %.6g, for messages (std::to_string prints 1e-300 as 0.000000).
inline std::string limitNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// OutOfRange naming `what` unless 1 <= width, height <= kMaxImageSide and
// width x height <= kMaxImagePixels.
inline Status checkImageSize(const std::string& what, long long width, long long height) {
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide ||
        static_cast<unsigned long long>(width) * static_cast<unsigned long long>(height) > kMaxImagePixels)
        return makeError(ErrorCode::OutOfRange, what + ": " + std::to_string(width) + "x" + std::to_string(height) +
                                                    " is outside 1.." + std::to_string(kMaxImageSide) +
                                                    " per side or above " + std::to_string(kMaxImagePixels) +
                                                    " pixels");
    return {};
}

// OutOfRange naming `what` unless kMinFovDeg <= deg <= kMaxFovDeg (vertical field of view).
inline Status checkFov(const std::string& what, double deg) {
    if (!(deg >= kMinFovDeg && deg <= kMaxFovDeg))
        return makeError(ErrorCode::OutOfRange, what + ": " + limitNumber(deg) + " is outside " +
                                                    limitNumber(kMinFovDeg) + ".." + limitNumber(kMaxFovDeg) +
                                                    " degrees");
    return {};
}

// OutOfRange naming `what` unless kMinExaggeration <= factor <= kMaxExaggeration.
inline Status checkExaggerationFactor(const std::string& what, double factor) {
    if (!(factor >= kMinExaggeration && factor <= kMaxExaggeration))
        return makeError(ErrorCode::OutOfRange, what + ": " + limitNumber(factor) + " is outside " +
                                                    limitNumber(kMinExaggeration) + ".." +
                                                    limitNumber(kMaxExaggeration));
    return {};
}

// InvalidArgument naming `what` (the eye and the target) unless they are at least
// kMinCameraDistanceMetres apart.
inline Status checkCameraDistance(const std::string& what, const glm::dvec3& eye, const glm::dvec3& target) {
    if (!(glm::length(target - eye) >= kMinCameraDistanceMetres))
        return makeError(ErrorCode::InvalidArgument, what + " coincide (closer than 1 mm)");
    return {};
}

// OutOfRange naming `what` unless `v` is finite and |v| <= kMaxCoordinateMetres.
inline Status checkCoordinate(const std::string& what, double v) {
    if (!std::isfinite(v) || std::abs(v) > kMaxCoordinateMetres)
        return makeError(ErrorCode::OutOfRange,
                         what + ": " + limitNumber(v) + " is not a finite coordinate within " + "+-1e8 m");
    return {};
}

// OutOfRange naming `what` unless an axis from `lo` to `hi` metres over `pixels` pixels
// gives pixels of at least kMinPixelMetres and kMinPixelUlps double steps (lo < hi, both
// finite and within kMaxCoordinateMetres, are checked by the caller).
inline Status checkPixelSize(const std::string& what, double lo, double hi, int pixels) {
    const double pixel = (hi - lo) / double(pixels);
    const double magnitude = std::max(std::abs(lo), std::abs(hi));
    const double ulp = std::nextafter(magnitude, INFINITY) - magnitude;
    if (!(pixel >= kMinPixelMetres) || !(pixel >= kMinPixelUlps * ulp))
        return makeError(ErrorCode::OutOfRange,
                         what + ": " + limitNumber(hi - lo) + " m over " + std::to_string(pixels) +
                             " pixels gives pixels of " + limitNumber(pixel) +
                             " m, below the smallest allowed pixel of 1e-6 m (or 64 steps of a double at this "
                             "coordinate)");
    return {};
}

}  // namespace geoslice
