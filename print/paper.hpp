// Paper: ISO 216 A sizes (A0..A5) and the US letter/tabloid sizes, in portrait or
// landscape. Millimetres. Pure functions, any thread.
#pragma once

#include <string>
#include <string_view>

#include "model/result.hpp"

namespace geoslice::print {

enum class Orientation { Landscape, Portrait };

struct Paper {
    std::string name = "A3";  // as given, upper case: "A3", "LETTER"
    Orientation orientation = Orientation::Landscape;
    double widthMm = 420.0, heightMm = 297.0;  // as oriented

    // "A3 landscape, 420 x 297 mm"
    std::string describe() const;
};

// `name`: A0..A5, letter, tabloid (any case). `orientation`: landscape or portrait.
// Errors: InvalidArgument naming the text and listing what is accepted (callers prefix
// the parameter or flag they came from).
Result<Paper> paperSize(std::string_view name, Orientation orientation);
Result<Orientation> parseOrientation(std::string_view text);

}  // namespace geoslice::print
