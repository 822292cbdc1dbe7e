// geoslice classify MODEL < points.txt: one "x y z" (world) per line -> one record id per line.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "model/io/loaders.hpp"
#include "section/rays/classify.hpp"

namespace geoslice::cli {
namespace {

bool parsePoint(const std::string& line, glm::dvec3& p) {
    const char* s = line.data();
    const char* end = s + line.size();
    double v[3];
    for (double& d : v) {
        while (s < end && (*s == ' ' || *s == '\t' || *s == ',' || *s == '\r')) ++s;
        auto [next, ec] = std::from_chars(s, end, d);
        if (ec != std::errc() || !std::isfinite(d)) return false;
        s = next;
    }
    while (s < end && (*s == ' ' || *s == '\t' || *s == '\r')) ++s;
    p = {v[0], v[1], v[2]};
    return s == end;
}

}  // namespace

void addClassify(CLI::App& app, int& exitCode) {
    auto path = std::make_shared<std::string>();
    auto threads = std::make_shared<unsigned>(0);
    auto load = std::make_shared<LoadOptions>();
    CLI::App* cmd = app.add_subcommand(
        "classify",
        "Print the record id of the innermost body containing each point read from stdin ('x y z' per line, "
        "world coordinates: easting northing elevation, metres); 0 = no body, * = unreadable line");
    cmd->add_option("MODEL", *path, "Model file")->required();
    cmd->add_option("--threads", *threads, "Worker threads (default: all cores)");
    addLoadOptions(cmd, *load);
    cmd->callback([path, threads, load, &exitCode] {
        auto model = loadModel(*path, *load);
        if (!model) {
            std::fprintf(stderr, "geoslice classify: %s\n", model.error().message.c_str());
            exitCode = 1;
            return;
        }
        auto classifier = Classifier::build(model.value());
        if (!classifier) {
            std::fprintf(stderr, "geoslice classify: %s\n", classifier.error().message.c_str());
            exitCode = 1;
            return;
        }
        std::vector<glm::dvec3> points;
        std::vector<char> good;
        std::string line;
        std::size_t lineNo = 0;
        while (std::getline(std::cin, line)) {
            ++lineNo;
            glm::dvec3 p(0.0);
            bool ok = parsePoint(line, p);
            if (!ok) {
                std::fprintf(stderr,
                             "geoslice classify: stdin line %zu: expected 'x y z' (three finite numbers), got \"%s\"\n",
                             lineNo, line.substr(0, 80).c_str());
                exitCode = 1;
            }
            points.push_back(p);
            good.push_back(ok ? 1 : 0);
        }
        std::vector<RecordId> ids(points.size());
        (*classifier)->classifyBatch(points.data(), points.size(), ids.data(), *threads);
        std::string out;
        out.reserve(points.size() * 3);
        for (std::size_t i = 0; i < ids.size(); ++i) {
            out += good[i] ? std::to_string(ids[i]) : std::string("*");
            out += '\n';
        }
        std::fwrite(out.data(), 1, out.size(), stdout);
    });
}

}  // namespace geoslice::cli
