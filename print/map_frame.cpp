#include "print/map_frame.hpp"

#include <algorithm>
#include <cmath>

#include "print/map_scale.hpp"
#include "print/round_numbers.hpp"
#include "print/ticks.hpp"
#include "view/view_limits.hpp"

namespace geoslice::print {
namespace {

// Grows [lo, hi] to whole multiples of a fifth (a quarter for 2 x 10^k) of the tick step,
// when the grown range still fits `maxMetres`: the frame ends on a round number without
// the empty band a whole step could add.
void snap(double& lo, double& hi, double tick, double maxMetres) {
    const double mantissa = tick / std::pow(10.0, std::floor(std::log10(tick) + 1e-9));
    const double step = tick / (std::abs(mantissa - 2.0) < 1e-6 ? 4.0 : 5.0);
    const double a = std::floor(lo / step + 1e-9) * step, b = std::ceil(hi / step - 1e-9) * step;
    if (b - a <= maxMetres * (1.0 + 1e-12)) lo = a, hi = b;
}

}  // namespace

Result<MapFrame> fitMapFrame(const FitRequest& r) {
    const double w = r.extent.u1 - r.extent.u0, h = r.extent.v1 - r.extent.v0;
    GS_ASSERT(r.exaggeration > 0.0 && r.area.width > 0.0 && r.area.height > 0.0, "fitMapFrame: empty area");
    if (!(w > 0.0) || !(h > 0.0) || !std::isfinite(w) || !std::isfinite(h))
        return makeError(ErrorCode::InvalidArgument, "the frame u " + limitNumber(r.extent.u0) + ".." +
                                                         limitNumber(r.extent.u1) + ", v " + limitNumber(r.extent.v0) +
                                                         ".." + limitNumber(r.extent.v1) + " is empty or not finite");
    // The smallest S at which w * 1000 / S <= area width and h * k * 1000 / S <= area height.
    const double needed = std::max(w * 1000.0 / r.area.width, h * r.exaggeration * 1000.0 / r.area.height);
    MapFrame f;
    f.exaggeration = r.exaggeration;
    if (r.scale) {
        if (Status s = checkScale(*r.scale); !s)
            return makeError(s.error().code, r.scaleName + ": " + s.error().message);
        if (*r.scale < needed * (1.0 - 1e-9)) {
            const double fits = roundScaleAtLeast(needed);
            return makeError(
                ErrorCode::OutOfRange,
                r.scaleName + ": at " + formatScale(*r.scale) + " the section (" + formatGrouped(w, 0, 1e4) + " m x " +
                    formatGrouped(h, 0, 1e4) + " m" +
                    (r.exaggeration != 1.0 ? ", vertical exaggeration " + formatGrouped(r.exaggeration, 2) : "") +
                    ") needs " + formatGrouped(paperMm(w, *r.scale), 0) + " x " +
                    formatGrouped(paperMm(h * r.exaggeration, *r.scale), 0) + " mm, more than the " +
                    formatGrouped(r.area.width, 0) + " x " + formatGrouped(r.area.height, 0) + " mm map area of " +
                    r.areaName + "; the largest round scale that fits is " + formatScale(fits) +
                    ", or use a larger paper");
        }
        f.scale = *r.scale;
    } else {
        if (needed > kMaxScale)
            return makeError(ErrorCode::OutOfRange, "the frame (" + limitNumber(w) + " m x " + limitNumber(h) +
                                                        " m) does not fit " + r.areaName +
                                                        " at any scale up to 1:100,000,000");
        f.scale = roundScaleAtLeast(needed);
    }
    f.shown = r.extent;
    const double maxU = r.area.width / f.mmPerMetreX(), maxV = r.area.height / f.mmPerMetreY();
    if (r.snapU) snap(f.shown.u0, f.shown.u1, tickStep(1.0 / f.mmPerMetreX(), kMinTickSpacingMm), maxU);
    if (r.snapV) snap(f.shown.v0, f.shown.v1, tickStep(1.0 / f.mmPerMetreY(), kMinTickSpacingMm), maxV);
    f.box.width = (f.shown.u1 - f.shown.u0) * f.mmPerMetreX();
    f.box.height = (f.shown.v1 - f.shown.v0) * f.mmPerMetreY();
    f.box.x = r.area.x + 0.5 * (r.area.width - f.box.width);
    f.box.y = r.area.y + 0.5 * (r.area.height - f.box.height);
    return f;
}

}  // namespace geoslice::print
