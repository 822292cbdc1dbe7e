// Round numbers for a printed sheet: the smallest "nice" value at least x from a mantissa
// series (1-2-5 for tick steps, 1-2-2.5-5 for map scales), and number text with digit
// grouping. Pure functions, any thread.
#pragma once

#include <initializer_list>
#include <string>

namespace geoslice::print {

// The smallest m x 10^k (m from `mantissas`, ascending within [1, 10)) that is >= x,
// allowing x to exceed it by a relative 1e-9 (so 5000.0000001 gives 5000). x > 0, finite.
double niceAtLeast(double x, std::initializer_list<double> mantissas);

// The largest m x 10^k (m from 1, 2, 5) that is <= x (within a relative 1e-9). x > 0, finite.
double niceAtMost125(double x);

// `value` with `decimals` digits after the point; the integer part grouped by thousands
// with ',' when |value| >= `groupFrom` ("35,502,000", "1200", "-12.5"). -0 prints as 0.
std::string formatGrouped(double value, int decimals, double groupFrom = 10000.0);

// Decimals that a multiple of `step` needs to print exactly (0 for steps >= 1; 1 for 0.5...).
int decimalsFor(double step);

}  // namespace geoslice::print
