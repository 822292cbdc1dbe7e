// The legend of a printed section: one entry per geological unit the section shows, with
// its colour and the record's name, lithology and age (model/attributes.hpp), bodies cut
// first (in the model's body order, which is the loaders' stratigraphic order), then the
// surfaces traced (faults, horizons), drawn as lines. Pure functions, any thread.
#pragma once

#include <string>
#include <vector>

#include "print/sheet.hpp"
#include "section/section_index.hpp"
#include "section/vector_export.hpp"

namespace geoslice::print {

struct LegendEntry {
    RecordId record = kNoRecord;
    Rgba8 colour;
    std::string name;       // the record's name, else the part's
    std::string lithology;  // may be empty
    std::string age;        // may be empty
    bool line = false;      // a surface's trace (drawn as a line swatch), not a body
};

// Entries for the parts `source` shows; one per record (parts sharing a record share an entry).
std::vector<LegendEntry> sectionLegend(const SectionIndex& index, const VectorSource& source);

// Appends a "Legend" heading and a row per entry (swatch, name, lithology and age) from the
// top of `area`; entries that do not fit are counted in a last "... and N more" line.
// Returns the height used (mm).
double drawLegend(Sheet& sheet, const PageRect& area, const std::vector<LegendEntry>& entries);

}  // namespace geoslice::print
