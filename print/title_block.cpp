#include "print/title_block.hpp"

#include <algorithm>

#include "print/text_metrics.hpp"

namespace geoslice::print {

double drawTitleBlock(Sheet& sheet, const PageRect& column, const std::string& heading,
                      const std::vector<TitleRow>& rows) {
    constexpr double kHeadingMm = 9.0, kKeyPt = 6.0, kValuePt = 7.2, kPad = 1.6, kKeyWidth = 17.0;
    constexpr double kLineMm = kValuePt * kMmPerPoint * 1.25, kRowPadMm = 2.4;
    const Rgba8 ink{0, 0, 0, 255};
    const double valueX = column.x + kPad + kKeyWidth, valueW = column.right() - kPad - valueX;
    std::vector<std::vector<std::string>> values;
    double height = kHeadingMm;
    for (const TitleRow& r : rows) {
        values.push_back(wrapText(r.value, valueW, kValuePt, 3));
        height += double(values.back().size()) * kLineMm + kRowPadMm;
    }
    const double top = column.bottom() - height;

    PathItem box;
    box.subpaths = {
        {{column.x, top}, {column.right(), top}, {column.right(), column.bottom()}, {column.x, column.bottom()}}};
    box.stroke = ink;
    box.strokeMm = 0.35;
    sheet.add(std::move(box));
    TextItem head{
        {column.x + kPad, top + 0.5 * kHeadingMm}, fitText(heading, column.width - 2 * kPad, 10.0, true), 10.0, true};
    head.baseline = TextBaseline::Middle;
    sheet.add(std::move(head));

    PathItem rules;
    rules.closed = false;
    rules.stroke = ink;
    rules.strokeMm = 0.15;
    double y = top + kHeadingMm;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        rules.subpaths.push_back({{column.x, y}, {column.right(), y}});
        const double first = y + 0.5 * kRowPadMm + 0.5 * kLineMm;  // middle of the first line
        TextItem key{{column.x + kPad, first}, rows[i].key, kKeyPt};
        key.baseline = TextBaseline::Middle;
        key.colour = Rgba8{90, 90, 90, 255};
        sheet.add(std::move(key));
        for (std::size_t k = 0; k < values[i].size(); ++k) {
            TextItem value{{valueX, first + double(k) * kLineMm}, values[i][k], kValuePt};
            value.baseline = TextBaseline::Middle;
            sheet.add(std::move(value));
        }
        y += double(values[i].size()) * kLineMm + kRowPadMm;
    }
    rules.subpaths.push_back({{valueX - 1.0, top + kHeadingMm}, {valueX - 1.0, column.bottom()}});
    sheet.add(std::move(rules));
    return height;
}

}  // namespace geoslice::print
