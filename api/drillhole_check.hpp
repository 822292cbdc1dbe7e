// The model checked against its drillholes: what a geologist does before trusting a model.
// Each desurveyed hole is traced through the model's bodies with the section engine's rule
// (section/rays/borehole.hpp BoreholeTracer::tracePath, the virtual borehole's tracer along
// the hole's chords, boundaries moved onto the minimum-curvature arc), and the logged codes of
// one interval column are compared with the model's units along the same hole:
//  - per hole and per unit, the share of logged length where the model has the logged unit;
//  - per logged contact (two touching intervals of different units), the distance along the
//    hole to the nearest model contact between the same two units in the same order
//    (model depth - logged depth, metres; null when the hole has none).
//
// Codes and units: the sidecar's "units" (model/drillholes/drillholes.hpp DrillholeUnitMap)
// names the table, the column and a code -> unit map; without a map a code names a unit
// itself. A unit is named, case-insensitively, by a record's name, a body's name or the record
// id. A mapped unit that the model lacks is a warning, and its logged length counts as
// disagreeing; a code that names no unit is left out of the shares and listed with its length.
// Thread-safety: any thread (the tracer is thread-safe; nothing is shared).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/drillholes/drillholes.hpp"
#include "model/model.hpp"
#include "model/result.hpp"
#include "section/rays/borehole.hpp"

namespace geoslice::api {

// Logged and agreeing length of one unit (a model unit, or a mapped name the model lacks).
struct UnitAgreement {
    std::string unit;
    bool inModel = true;
    double logged = 0.0, agreed = 0.0;  // metres along the holes
};

struct ContactCheck {
    double depth = 0.0;  // the logged contact, metres along the hole
    std::string codeAbove, codeBelow, unitAbove, unitBelow;
    std::size_t rowAbove = 0, rowBelow = 0;  // the interval file's rows
    std::optional<double> modelDepth;        // the nearest model contact between the same units
    std::optional<double> distance;          // modelDepth - depth
};

struct HoleCheck {
    std::string hole;
    double logged = 0.0, agreed = 0.0;  // comparable logged length (codes that name a unit)
    double unmatched = 0.0;             // logged length whose code names no unit
    double tracedTo = 0.0;              // metres along the hole traced through the model
    std::vector<UnitAgreement> units;   // in order of first appearance down the hole
    std::vector<ContactCheck> contacts;
    Borehole model;     // the model's bodies along the hole (depths from the collar)
    std::string error;  // set when the hole could not be traced (then nothing else is)
};

struct CodeUse {
    std::string code;
    std::string unit;  // empty: the code names no unit
    bool inModel = false;
    std::size_t intervals = 0;
    double length = 0.0;
};

struct DrillholeCheck {
    std::string table, column;
    bool sidecarMap = false;
    std::vector<HoleCheck> holes;  // database order; holes without intervals in the table too
    std::vector<UnitAgreement> units;
    std::vector<CodeUse> codes;  // sorted by code
    std::vector<std::string> warnings;
    double sagitta = kHoleChordSagittaM;
};

// Which table and column hold the codes: DrillholeUnitMap's, else the first text column of an
// interval table named lith, lithology, litho, rock, rocktype, rockcode, unit, geology, geol,
// code, lithcode (compared without case, spaces or punctuation). Error (NotFound, naming the
// tables and their text columns) when there is none.
Result<std::pair<std::size_t, std::size_t>> findCodeColumn(const DrillholeDatabase& db);

// The model of one hole: its path as chords (holePolyline) down to the deepest of its total
// depth, its last node and the deepest interval of any table, traced.
Result<Borehole> traceHole(const BoreholeTracer& tracer, const DrillholeDatabase& db, const Drillhole& hole);

// Everything above, for every hole. Errors: findCodeColumn's; a hole that cannot be traced is
// an error on that hole only.
Result<DrillholeCheck> checkDrillholes(const Model& model, const DrillholeDatabase& db, const BoreholeTracer& tracer);

// One hole's strip log for a client drawing logged beside modelled: collar, total depth, the
// survey stations and desurveyed path nodes, every interval table's intervals with their
// columns (the code column's intervals carry the unit their code names, or null), and the
// model's units along the same hole (`trace`, from traceHole) and the open surfaces it crosses.
nlohmann::ordered_json drillholeLogJson(const Model& model, const DrillholeDatabase& db, const Drillhole& hole,
                                        const Borehole& trace);

// The JSON document (the CLI's --json and HTTP): model, drillholes, table, column, mapping,
// method, summary, units, codes, holes (with units and contacts), warnings.
nlohmann::ordered_json drillholeCheckJson(const DrillholeCheck& check, const std::string& modelLabel,
                                          const std::string& drillholesLabel);
// CSV: `contacts` false: hole,unit,in_model,logged_m,agreed_m,share (one row per hole and unit,
// then one per unit with hole "*" for all holes); true: hole,depth_m,code_above,code_below,
// unit_above,unit_below,model_depth_m,distance_m (empty when no model contact).
std::string drillholeCheckCsv(const DrillholeCheck& check, bool contacts);

}  // namespace geoslice::api
