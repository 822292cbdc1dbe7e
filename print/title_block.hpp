// The title block of a sheet: a ruled box of labelled rows (model, version, CRS, section,
// ends, scale, paper, date, ...), drawn from the bottom of a column upwards, long values
// cut with an ellipsis to the column's width. Page millimetres. Any thread.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "print/sheet.hpp"

namespace geoslice::print {

struct TitleRow {
    std::string key, value;
};

// Appends the block at the bottom of `column` and returns its height (mm).
double drawTitleBlock(Sheet& sheet, const PageRect& column, const std::string& heading,
                      const std::vector<TitleRow>& rows);

}  // namespace geoslice::print
