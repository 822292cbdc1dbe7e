// The legend of a printed section: one entry per geological unit the section shows, with
// its colour and the record's name, lithology and age (model/attributes.hpp), bodies cut
// first (in the model's body order, which is the loaders' stratigraphic order), then the
// surfaces traced (faults, horizons), drawn as lines; with a block-property colouring, then
// the property (name, unit, ramp) and one swatch per class with its range
// (PropertyClasses::label, the same text as legend.png and blockLegend JSON).
// Pure functions, any thread.
#pragma once

#include <string>
#include <vector>

#include "print/sheet.hpp"
#include "section/blocks/block_section.hpp"
#include "section/fill/vector_export.hpp"
#include "section/index/section_index.hpp"

namespace geoslice::print {

struct LegendEntry {
    RecordId record = kNoRecord;
    Rgba8 colour;
    std::string name;                     // the record's name, else the part's
    std::string lithology;                // may be empty
    std::string age;                      // may be empty
    bool line = false;                    // a surface's trace (drawn as a line swatch), not a body
    Lithology pattern = Lithology::None;  // drawn over the swatch's colour (section/fill/patterns.hpp)
};

// Entries for the parts `source` shows; one per record (parts sharing a record share an entry).
std::vector<LegendEntry> sectionLegend(const SectionIndex& index, const VectorSource& source);

// The ramp of a block-property colouring: a title ("grade (g/t Au), viridis classes") and
// one (colour, range) per class, lowest first.
struct LegendRamp {
    std::string title;
    std::vector<std::pair<Rgba8, std::string>> classes;
};
LegendRamp legendRamp(const BlockModel& blocks, const PropertyClasses& classes);

// Rows drawLegend needs for `entries` and `ramp` (its title row and a row per class).
std::size_t legendRows(const std::vector<LegendEntry>& entries, const LegendRamp* ramp);

// Appends a "Legend" heading and a row per entry (swatch, name, lithology and age) from the
// top of `area`, then the ramp's title and a swatch row per class; the ramp is drawn whole
// (units that do not fit above it are counted in a "... and N more" line). Returns the
// height used (mm).
double drawLegend(Sheet& sheet, const PageRect& area, const std::vector<LegendEntry>& entries,
                  const LegendRamp* ramp = nullptr);

}  // namespace geoslice::print
