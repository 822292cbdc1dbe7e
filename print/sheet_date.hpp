// The date a sheet states in its title block (and PDF metadata): a calendar date
// YYYY-MM-DD. Pure functions, any thread.
#pragma once

#include <string>
#include <string_view>

namespace geoslice::print {

// True for a valid proleptic Gregorian date written YYYY-MM-DD (2024-02-29 yes, 2023-02-29 no).
bool isCalendarDate(std::string_view text);

// Today in UTC as YYYY-MM-DD.
std::string todayUtc();

}  // namespace geoslice::print
