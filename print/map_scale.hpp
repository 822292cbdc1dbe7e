// Map scale 1:S of a printed sheet: S metres of ground per metre of paper, so one
// metre of ground is 1000 / S millimetres on paper. With vertical exaggeration k the
// vertical scale is 1:(S / k). Pure functions, any thread.
#pragma once

#include <string>

#include "model/result.hpp"

namespace geoslice::print {

constexpr double kMinScale = 1.0;  // 1:1
constexpr double kMaxScale = 1e8;  // 1:100,000,000

// OutOfRange unless S is finite and within [kMinScale, kMaxScale]; the message gives the value.
Status checkScale(double denominator);

// The smallest round scale (1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 7.5 x 10^k: 1:1,000, 1:1,250,
// 1:1,500, 1:2,000, 1:2,500, 1:3,000, 1:4,000, 1:5,000, 1:7,500, 1:10,000, ...) that is at
// least `denominator`: what auto-fit picks so the section fits its frame. Neighbours differ
// by at most a third, so a fitted section fills at least three quarters of its area.
double roundScaleAtLeast(double denominator);

// "1:5,000" (digits grouped from 1,000; a scale that is not whole keeps up to 3 decimals).
std::string formatScale(double denominator);

// Paper millimetres of `metres` of ground at 1:S.
inline double paperMm(double metres, double denominator) { return metres * 1000.0 / denominator; }

}  // namespace geoslice::print
