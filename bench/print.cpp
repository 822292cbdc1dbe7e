// bench_print [--size L4] [--runs 9] [--paper A3] [--dpi 150]: print sheets
// (print/section_sheet.hpp) of a synthetic model. Generates + validates + indexes the model
// once, then for `runs` vertical E-W planes at evenly spread northings times separately the
// exact cut, the sheet layout (axes, legend, title block), the PDF (cairo), the SVG
// (pugixml), and the decorated raster at --dpi (the engine's raster of the map box plus the
// cairo surface; PNG encoding not included), and a 3-point polyline sheet as PDF end to end.
// Prints JSON with medians (ms; the PDF end to end also as this thread's CPU time, which a
// loaded machine does not inflate), PDF sizes and the load average; not part of the tests.
#include <cstdio>
#include <cstring>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "print/cairo_output.hpp"
#include "print/paper.hpp"
#include "print/section_sheet.hpp"
#include "print/svg_output.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/polyline.hpp"
#include "section/index/section_index.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

double ms(double t0) { return (bench::nowSeconds() - t0) * 1000.0; }

std::string loadAverage() {
    char buf[128] = {0};
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (!std::fgets(buf, sizeof buf, f)) buf[0] = 0;
        std::fclose(f);
    }
    std::string s = buf;
    while (!s.empty() && s.back() == '\n') s.pop_back();
    return s;
}

int fail(const std::string& what) {
    std::fprintf(stderr, "bench_print: %s\n", what.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    std::string size = "L4", paperName = "A3";
    int runs = 9;
    double dpi = 150.0;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--size"))
            size = argv[i + 1];
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::max(1, std::stoi(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--paper"))
            paperName = argv[i + 1];
        else if (!std::strcmp(argv[i], "--dpi"))
            dpi = std::stod(argv[i + 1]);
        else
            return fail(std::string("unknown option ") + argv[i]);
    }
    const std::string loadBefore = loadAverage();
    auto paper = print::paperSize(paperName, print::Orientation::Landscape);
    if (!paper) return fail(paper.error().message);

    double t0 = bench::nowSeconds();
    SyntheticOptions so;
    so.triangles = bench::triangleCountFor(size);
    auto model = generateSynthetic(so);
    if (!model) return fail(model.error().message);
    validate(model.value());
    const double generateMs = ms(t0);
    t0 = bench::nowSeconds();
    auto index = buildSectionIndex(model.value());
    if (!index) return fail(index.error().message);
    const double indexMs = ms(t0);
    const SectionIndex& idx = *index.value();

    print::SheetInfo info;
    info.model = "synthetic-" + size;
    info.version = "bench";
    info.crs = "local metres (no CRS)";
    info.date = "2026-01-01";
    print::SheetOptions o;
    o.paper = paper.value();
    o.exaggeration = 2.0;

    std::vector<double> cut, layout, pdf, svg, rasterLayout, raster, total, totalCpu, line;
    std::size_t pdfBytes = 0, svgBytes = 0;
    int rasterW = 0, rasterH = 0;
    const Aabb& b = idx.bounds;
    for (int r = 0; r < runs; ++r) {
        const double y = b.min.y + (b.max.y - b.min.y) * (0.2 + 0.6 * (r + 0.5) / runs);
        info.definition = "plane=0,1,0," + std::to_string(-y) + "&vx=2";
        const double start = bench::nowSeconds(), startCpu = bench::threadCpuSeconds();
        t0 = start;
        auto section = computeSection(idx, Plane{{0.0, 1.0, 0.0}, -y});
        if (!section) return fail(section.error().message);
        cut.push_back(ms(t0));
        t0 = bench::nowSeconds();
        auto sheet = print::sectionSheet(idx, section.value(), o, info);
        if (!sheet) return fail(sheet.error().message);
        layout.push_back(ms(t0));
        t0 = bench::nowSeconds();
        auto doc = print::renderPdf(sheet.value());
        if (!doc) return fail(doc.error().message);
        pdf.push_back(ms(t0));
        total.push_back(ms(start));
        totalCpu.push_back((bench::threadCpuSeconds() - startCpu) * 1000.0);
        pdfBytes = doc.value().size();
        t0 = bench::nowSeconds();
        auto text = print::renderSvg(sheet.value());
        if (!text) return fail(text.error().message);
        svg.push_back(ms(t0));
        svgBytes = text.value().size();

        print::SheetOptions ro = o;
        ro.rasterGeometry = true;
        ro.dpi = dpi;
        t0 = bench::nowSeconds();
        auto decorated = print::sectionSheet(idx, section.value(), ro, info);
        if (!decorated) return fail(decorated.error().message);
        rasterLayout.push_back(ms(t0));
        t0 = bench::nowSeconds();
        auto pixels = print::renderRaster(decorated.value(), dpi);
        if (!pixels) return fail(pixels.error().message);
        raster.push_back(ms(t0));
        rasterW = pixels.value().width;
        rasterH = pixels.value().height;

        // A 3-point polyline sheet end to end (cut of both legs, layout, PDF).
        const double x0 = b.min.x + 0.1 * (b.max.x - b.min.x), x1 = b.max.x - 0.1 * (b.max.x - b.min.x);
        const std::vector<glm::dvec2> pts{{x0, y}, {0.5 * (x0 + x1), b.max.y - 0.1 * (b.max.y - b.min.y)}, {x1, y}};
        t0 = bench::nowSeconds();
        auto poly = computePolylineSection(idx, pts);
        if (!poly) return fail(poly.error().message);
        auto polySheet = print::sectionSheet(idx, poly.value(), o, info);
        if (!polySheet) return fail(polySheet.error().message);
        auto polyPdf = print::renderPdf(polySheet.value());
        if (!polyPdf) return fail(polyPdf.error().message);
        line.push_back(ms(t0));
    }
    json out;
    out["bench"] = "print";
    out["size"] = size;
    out["triangles"] = model.value().triangleCount();
    out["paper"] = paper.value().describe();
    out["runs"] = runs;
    out["generate_validate_ms"] = generateMs;
    out["index_ms"] = indexMs;
    out["medians_ms"] = {{"cut", bench::median(cut)},
                         {"layout", bench::median(layout)},
                         {"pdf", bench::median(pdf)},
                         {"pdf_end_to_end", bench::median(total)},
                         {"pdf_end_to_end_thread_cpu", bench::median(totalCpu)},
                         {"svg", bench::median(svg)},
                         {"decorated_layout_with_raster_fill", bench::median(rasterLayout)},
                         {"decorated_cairo_raster", bench::median(raster)},
                         {"polyline_3_points_pdf_end_to_end", bench::median(line)}};
    out["pdf_bytes"] = pdfBytes;
    out["svg_bytes"] = svgBytes;
    out["decorated_pixels"] = {rasterW, rasterH};
    out["dpi"] = dpi;
    out["loadavg_before"] = loadBefore;
    out["loadavg_after"] = loadAverage();
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
