// The one comparator of the pixel-query cases (MapLibre's query tests): a case is a folder
// tests/data/queries/<case>/ holding request.json (the model, the view as HTTP parameters,
// for a tile case the tile, and the pixels) and expected.json (per pixel the answer, and
// per quantity the tolerance and its reason), derived independently of geoslice by
// tests/data/queries/derive.py (see the README there). Every path that answers a query
// (GET and POST over HTTP, the CLI's `geoslice query`) is held to the same expected.json
// by compareAnswer, which returns what differs instead of failing, so that it can itself
// be tested on answers known to be wrong.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace geoslice::test {

inline std::string queryCaseDir() {
#ifdef GEOSLICE_QUERY_CASE_DIR
    return GEOSLICE_QUERY_CASE_DIR;
#else
    return std::string(GEOSLICE_TEST_DATA_DIR) + "/queries";
#endif
}

// Every folder of queryCaseDir() with a request.json, sorted (a parameterised suite's values).
inline std::vector<std::string> queryCases() {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(queryCaseDir(), ec))
        if (std::filesystem::exists(entry.path() / "request.json")) out.push_back(entry.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

struct QueryCase {
    std::string name;
    nlohmann::json request;   // request.json
    nlohmann::json expected;  // expected.json

    bool perspective() const { return request["view"].value("view", "") == "perspective"; }
    bool tile() const { return request.contains("tile"); }
    // The model file the case names (tests/data/queries/models/<model>.<ext>).
    std::string modelPath() const {
        const std::string model = request.value("model", "");
        for (const char* ext : {".obj", ".vtu"}) {
            const std::string p = queryCaseDir() + "/models/" + model + ext;
            if (std::filesystem::exists(p)) return p;
        }
        return queryCaseDir() + "/models/" + model;
    }
    // The view as HTTP parameters: request.view, and for a tile case the tile's frame (the
    // derived one, expected.tileFrame) at 256x256 pixels, as the web client queries tiles.
    std::map<std::string, std::string> view() const {
        std::map<std::string, std::string> v;
        for (const auto& [k, value] : request["view"].items()) v[k] = value.get<std::string>();
        if (tile()) {
            const auto& f = expected["tileFrame"];
            std::ostringstream s;
            s.precision(17);
            s << f[0].get<double>() << ',' << f[1].get<double>() << ',' << f[2].get<double>() << ','
              << f[3].get<double>();
            v["frame"] = s.str();
            v["size"] = "256x256";
        }
        return v;
    }
    // expected.tolerances.<name>.value (a missing tolerance is reported by loadQueryCase).
    double tolerance(const std::string& quantity) const {
        return expected["tolerances"].value(quantity, nlohmann::json::object()).value("value", 0.0);
    }
    std::string reason(const std::string& quantity) const {
        return expected["tolerances"].value(quantity, nlohmann::json::object()).value("reason", "");
    }
};

inline nlohmann::json readJsonFile(const std::string& path) {
    std::ifstream f(path);
    nlohmann::json j = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
    EXPECT_TRUE(j.is_object()) << path << " is not a JSON object";
    return j.is_object() ? j : nlohmann::json::object();
}

// Reads a case; a malformed case (pixels of request and expected differ, a tolerance
// without its reason) is a test failure.
inline QueryCase loadQueryCase(const std::string& name) {
    QueryCase c;
    c.name = name;
    c.request = readJsonFile(queryCaseDir() + "/" + name + "/request.json");
    c.expected = readJsonFile(queryCaseDir() + "/" + name + "/expected.json");
    EXPECT_TRUE(c.request.contains("view") && c.request["view"].is_object()) << name << ": request.json has no view";
    const auto& pixels = c.request.value("pixels", nlohmann::json::array());
    const auto& answers = c.expected.value("pixels", nlohmann::json::array());
    EXPECT_EQ(pixels.size(), answers.size()) << name << ": request and expected pixels differ";
    for (std::size_t i = 0; i < std::min(pixels.size(), answers.size()); ++i)
        EXPECT_TRUE(pixels[i][0] == answers[i]["px"] && pixels[i][1] == answers[i]["py"])
            << name << ": pixel " << i << " differs between request.json and expected.json";
    const nlohmann::json tolerances = c.expected.value("tolerances", nlohmann::json::object());
    for (const auto& [k, t] : tolerances.items())
        EXPECT_FALSE(t.value("reason", "").empty()) << name << ": tolerance " << k << " states no reason";
    if (c.tile()) {
        EXPECT_TRUE(c.expected.contains("tileFrame")) << name << ": a tile case needs expected.tileFrame";
    }
    return c;
}

// What differs between `answer` (one answer object of GET /query, POST /query or
// `geoslice query`) and `want` (one entry of expected.json's pixels); empty when they agree
// within the case's tolerances. Checked: hit, the record's fields that `want` names, the
// body, the block cell and its grade, the world point, the section coordinates, lon/lat
// (null: the answer must have none) and, for perspective views, the distance from the eye.
inline std::vector<std::string> compareAnswer(const QueryCase& c, const nlohmann::json& want,
                                              const nlohmann::json& answer) {
    std::vector<std::string> diffs;
    auto differs = [&](const std::string& field, const nlohmann::json& w, const nlohmann::json& a,
                       const std::string& note = "") {
        diffs.push_back(field + ": expected " + w.dump() + ", got " + a.dump() + note);
    };
    auto near = [&](const std::string& field, const nlohmann::json& w, const nlohmann::json& a,
                    const std::string& tol) {
        const double t = c.tolerance(tol);
        if (!a.is_number() || !(std::abs(a.get<double>() - w.get<double>()) <= t))
            differs(field, w, a, " (tolerance " + tol + " " + nlohmann::json(t).dump() + ": " + c.reason(tol) + ")");
    };
    if (!answer.is_object()) return {"the answer is not a JSON object: " + answer.dump()};
    if (answer.value("hit", !want["hit"].get<bool>()) != want["hit"].get<bool>())
        differs("hit", want["hit"], answer.value("hit", nlohmann::json()));
    const nlohmann::json& record = answer.contains("record") ? answer["record"] : nlohmann::json();
    if (want["record"].is_null()) {
        if (!record.is_null()) differs("record", want["record"], record);
    } else {
        for (const auto& [k, v] : want["record"].items())
            if (!record.is_object() || record.value(k, nlohmann::json()) != v)
                differs("record." + k, v, record.is_object() ? record.value(k, nlohmann::json()) : record);
    }
    if (want.contains("body") && answer.value("body", nlohmann::json()) != want["body"])
        differs("body", want["body"], answer.value("body", nlohmann::json()));
    if (want.contains("block")) {
        const nlohmann::json& block = answer.contains("block") ? answer["block"] : nlohmann::json("(absent)");
        if (want["block"].is_null()) {
            if (!block.is_null()) differs("block", want["block"], block);
        } else if (!block.is_object()) {
            differs("block", want["block"], block);
        } else {
            if (block.value("cell", nlohmann::json()) != want["block"]["cell"])
                differs("block.cell", want["block"]["cell"], block.value("cell", nlohmann::json()));
            for (const auto& [k, v] : want["block"]["properties"].items())
                near("block.properties." + k, v, block["properties"].value(k, nlohmann::json()), k);
        }
    }
    const nlohmann::json& world = answer.contains("world") ? answer["world"] : nlohmann::json("(absent)");
    if (want["world"].is_null()) {
        if (!world.is_null()) differs("world", want["world"], world);
    } else if (!world.is_object()) {
        differs("world", want["world"], world);
    } else {
        const char* axes[] = {"x", "y", "z"};
        for (int i = 0; i < 3; ++i)
            near(std::string("world.") + axes[i], want["world"][i], world.value(axes[i], nlohmann::json()), "world_m");
        const nlohmann::json& geo = world.contains("geodetic") ? world["geodetic"] : nlohmann::json();
        if (want.contains("lonlat") && want["lonlat"].is_null()) {
            if (!geo.is_null()) differs("world.geodetic", nullptr, geo, " (a model with no CRS has no lon/lat)");
        } else if (want.contains("lonlat")) {
            near("world.geodetic.lon", want["lonlat"][0], geo.is_object() ? geo.value("lon", nlohmann::json()) : geo,
                 "lonlat_deg");
            near("world.geodetic.lat", want["lonlat"][1], geo.is_object() ? geo.value("lat", nlohmann::json()) : geo,
                 "lonlat_deg");
        }
    }
    if (want.contains("section")) {
        const nlohmann::json& section = answer.contains("section") ? answer["section"] : nlohmann::json::object();
        for (const auto& [k, v] : want["section"].items())
            near("section." + k, v, section.value(k, nlohmann::json()), "section_m");
    }
    if (want.contains("distanceFromEye") && !want["distanceFromEye"].is_null())
        near("distanceFromEye", want["distanceFromEye"], answer.value("distanceFromEye", nlohmann::json()), "eye_m");
    return diffs;
}

// compareAnswer as a test expectation naming the case, the path that answered and the pixel.
inline void expectAnswer(const QueryCase& c, const std::string& path, std::size_t i, const nlohmann::json& answer) {
    const nlohmann::json& want = c.expected["pixels"][i];
    const auto diffs = compareAnswer(c, want, answer);
    std::string all;
    for (const std::string& d : diffs) all += "\n  " + d;
    EXPECT_TRUE(diffs.empty()) << c.name << " via " << path << ", pixel (" << want["px"] << ", " << want["py"]
                               << "):" << all;
}

}  // namespace geoslice::test
