// Reserves as documents: the one JSON form (`geoslice reserves --json` and
// GET /v1/models/{id}/reserves) and its CSV twin, and the HTTP parameters of the route.
// The figures come from section/volumes/reserves.hpp (computeReserves); this file only lays them out.
//
// JSON: {"model", "plane": [a,b,c,d] (unit normal) | null, "method", "bodies": [...],
//        "totals": {...}, "skipped_open_bodies"}; one body per closed body, Model::bodies
//        order, with body (part name), record, record_name, lithology, gross_volume_m3,
//        net_volume_m3, density_t_per_m3, tonnage_t, grade, grade_unit, metal, metal_unit
//        (null where the attribute record has no density or grade).
// totals: bodies; net_volume_m3 (the sum of net volumes: nested bodies are counted once,
//        gross volumes are not summed because a lens would count twice); tonnage_t (the sum
//        over bodies with a density, null when none has one); bodies_with_tonnage; metal:
//        [{unit, amount}] one entry per metal unit (units are never added across).
// CSV (RFC 4180, header row, '\n' line ends): one row per body with the body fields above,
//        numbers as the shortest text that reads back to the same double, empty where JSON has
//        null; then one row whose body is "(total)" with the totals (record empty; metal only
//        when every body with metal has the same unit).
// Pure functions, any thread.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "api/params.hpp"
#include "model/model.hpp"
#include "section/blocks/block_reserves.hpp"
#include "section/volumes/reserves.hpp"

namespace geoslice::api {

// The JSON document; `modelLabel` is what the caller named the model by (the CLI: the file
// as given; HTTP: the model id).
nlohmann::ordered_json reservesJson(const Model& model, const Reserves& reserves, const std::string& modelLabel);
// The CSV document.
std::string reservesCsv(const Model& model, const Reserves& reserves);

// GET /v1/models/{id}/reserves parameters: `plane=a,b,c,d` (optional; parsed and checked
// exactly as a section's plane, errors name 'plane') and `format=json|csv` (optional; the
// path reserves.csv means csv, and format=json there is a conflict). Any other parameter
// is an InvalidArgument naming it.
//
// With a block model (model/blocks/block_model.hpp): `cutoffs=c1,c2,...` (increasing, at most 64)
// and `property=NAME` (default: the first block property not named density) ask for
// grade-tonnage tables (section/blocks/block_reserves.hpp); JSON then carries "grade_tonnage"
// (gradeTonnageJson) beside the bodies, and CSV is the grade-tonnage table
// (gradeTonnageCsv) instead of the body table. With `plane` too, the tables are of the
// kept side only (cell ∩ body ∩ half-space volumes).
struct ReservesRequest {
    std::optional<Plane> plane;
    bool csv = false;
    std::optional<std::vector<double>> cutoffs;
    std::string property;  // empty: the default
    // Cache key part: "whole" or the normalised plane's four numbers, then the format.
    std::string canonical() const;
};
Result<ReservesRequest> parseReservesRequest(const Params& params, bool csvPath);

// The grade property a request names, or the default (first not named "density"; the
// first property when all are). Error when the model has no block model.
Result<std::string> gradeProperty(const Model& model, const std::string& requested);
// {"property", "unit", "cutoffs", "plane" ([a,b,c,d] | null), "method", "bodies": [{"body", "record", "volume_m3",
//  "volume_without_grade_m3", "density_source", "rows": [{"cutoff", "cells", "volume_m3",
//  "tonnage_t", "mean_grade", "metal", "metal_unit"}]}]} (null where there is no density).
nlohmann::ordered_json gradeTonnageJson(const Model& model, const GradeTonnage& table);
// CSV: body,record,cutoff,cells,volume_m3,tonnage_t,mean_grade,grade_unit,metal,metal_unit;
// one row per body and cut-off.
std::string gradeTonnageCsv(const Model& model, const GradeTonnage& table);

}  // namespace geoslice::api
