// bench_section [--sizes L1,L4] [--planes 50] [--size 1024] [--tile 256] [--leaf 64] [--oracle 256]:
// the exact section engine. For each model size: generate + validate, build the section
// index (BVH + welds), then for `planes` random planes through the model time separately
// the BVH query, the cut (segments), contour assembly (first, with nothing of the plane in
// the caches: the previous plane's brute-force cut has read the whole model since), the
// full-frame fill (colour + ID),
// a tile straight from the BVH, the whole section image end to end, and the brute-force
// cut of every triangle (the paper's "CPU geometric intersection" baseline); then 4 x
// `planes` vertical boreholes, `planes` 3-point polyline sections (W x W/2 image) and the
// reserves of every body (whole, and on one side of a plane). Prints JSON
// with medians (ms) and the per-size build figures. --oracle N also compares an N x N ID
// buffer per plane with the Embree oracle (section/rays/classify.hpp) at every pixel centre.
// --leaf-order 1 (default) puts the model in the BVH's leaf order first, as a baked package
// stores it (section/index/leaf_order.hpp), and times the cut on a generator-ordered copy beside
// it, plane by plane (leaf_order_vs_generator_order); --leaf-order 0 skips both.
// --exits-only 1 (default) times the cut and assembly steps with closed bodies' exit points
// only (PlaneCut::exitsOnly), 0 with both points of every segment; either way computeSection
// is timed both ways plane by plane, alternating (exits_only_vs_both_points), and the two
// sections must be equal bit for bit.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench/bench_util.hpp"
#include "model/mesh/validate.hpp"
#include "model/synthetic/synthetic.hpp"
#include "section/cut/contours.hpp"
#include "section/cut/plane_cut.hpp"
#include "section/cut/polyline.hpp"
#include "section/fill/raster.hpp"
#include "section/index/leaf_order.hpp"
#include "section/index/section_index.hpp"
#include "section/rays/borehole.hpp"
#include "section/rays/classify.hpp"
#include "section/volumes/reserves.hpp"
#include "tests/common/random_plane.hpp"

using namespace geoslice;
using json = nlohmann::ordered_json;

namespace {

double ms(double t0) { return (bench::nowSeconds() - t0) * 1000.0; }

// Bit for bit: the same bodies, rings (point by point), areas and traces.
bool sameSection(const Section& a, const Section& b) {
    if (a.bodies.size() != b.bodies.size() || a.traces.size() != b.traces.size()) return false;
    for (std::size_t i = 0; i < a.bodies.size(); ++i) {
        const BodySection &x = a.bodies[i], &y = b.bodies[i];
        if (x.part != y.part || x.area != y.area || x.openChains != y.openChains ||
            x.polygons.size() != y.polygons.size())
            return false;
        for (std::size_t j = 0; j < x.polygons.size(); ++j)
            if (x.polygons[j].outer != y.polygons[j].outer || x.polygons[j].holes != y.polygons[j].holes) return false;
    }
    for (std::size_t i = 0; i < a.traces.size(); ++i)
        if (a.traces[i].part != b.traces[i].part || a.traces[i].points != b.traces[i].points ||
            a.traces[i].closed != b.traces[i].closed)
            return false;
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string sizes = "L1,L4";
    int planes = 50, side = 1024, tileSide = 256;
    unsigned leaf = BvhOptions{}.maxLeafSize;
    int oracleSide = 0;
    bool leafOrder = true, exitsOnly = true;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--sizes"))
            sizes = argv[i + 1];
        else if (!std::strcmp(argv[i], "--planes"))
            planes = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--size"))
            side = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--tile"))
            tileSide = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--oracle"))
            oracleSide = std::stoi(argv[i + 1]);
        else if (!std::strcmp(argv[i], "--leaf"))
            leaf = static_cast<unsigned>(std::stoul(argv[i + 1]));
        else if (!std::strcmp(argv[i], "--leaf-order"))
            leafOrder = std::stoi(argv[i + 1]) != 0;
        else if (!std::strcmp(argv[i], "--exits-only"))
            exitsOnly = std::stoi(argv[i + 1]) != 0;
    }
    json results = json::array();
    std::stringstream list(sizes);
    std::string size;
    while (std::getline(list, size, ',')) {
        SyntheticOptions so;
        so.triangles = bench::triangleCountFor(size);
        so.crs = Crs::fromEpsg(4523).value();
        double t = bench::nowSeconds();
        auto model = generateSynthetic(so);
        if (!model) {
            std::fprintf(stderr, "%s\n", model.error().message.c_str());
            return 1;
        }
        validate(model.value());
        const double genS = bench::nowSeconds() - t;
        // A baked package stores its mesh in the section BVH's leaf order (section/index/leaf_order.hpp).
        double reorderS = 0.0;
        std::optional<Model> plain;  // generator order, for the interleaved comparison
        if (leafOrder) {
            plain = model.value();
            t = bench::nowSeconds();
            if (auto s = reorderForSection(model.value()); !s) {
                std::fprintf(stderr, "%s\n", s.error().message.c_str());
                return 1;
            }
            reorderS = bench::nowSeconds() - t;
        }
        const double rssBefore = bench::currentRssMiB();
        bench::resetPeakRss();
        BvhOptions bo;
        bo.maxLeafSize = leaf;
        t = bench::nowSeconds();
        const double cpu0 = bench::processCpuSeconds();
        auto index = buildSectionIndex(model.value(), bo);
        const double buildS = bench::nowSeconds() - t;
        const double buildCpuS = bench::processCpuSeconds() - cpu0;
        if (!index) {
            std::fprintf(stderr, "%s\n", index.error().message.c_str());
            return 1;
        }
        const double rssAfter = bench::currentRssMiB();
        const double rssPeakBuild = bench::peakRssSinceResetMiB();
        const SectionIndex& idx = *index.value();
        std::unique_ptr<SectionIndex> plainIndex;
        if (plain) {
            auto pi = buildSectionIndex(*plain, bo);
            if (!pi) {
                std::fprintf(stderr, "%s\n", pi.error().message.c_str());
                return 1;
            }
            plainIndex = std::move(pi).value();
        }
        std::vector<double> abPlain, abLeaf, abRatio;
        std::vector<double> ewBothCpu, ewExitsCpu, ewRatio, ewBothWall, ewExitsWall, ewBoth2, ewExits2;
        std::size_t ewDiffer = 0;

        std::vector<double> cSection1, cSection2, tSection1;
        std::vector<double> tQueryTris, tContours2, tEnd2, cCut, cAssemble, cFill, cEnd, nodesVisited, trisTested,
            tFillReused, tFillIds, tFillColour, tSection, tQuery, tCut, tAssemble, tContours, tFill, tTile, tEnd,
            tBrute, crossing, segments;
        std::mt19937_64 rng(7);
        const Aabb bounds = model->bounds();
        std::size_t openChains = 0, oraclePixels = 0, oracleDiffer = 0;
        std::unique_ptr<Classifier> oracle;
        if (oracleSide > 0) {
            auto c = Classifier::build(model.value());
            if (!c) {
                std::fprintf(stderr, "%s\n", c.error().message.c_str());
                return 1;
            }
            oracle = std::move(c).value();
        }
        std::vector<glm::dvec3> oraclePts;
        std::vector<RecordId> oracleIds;
        std::vector<std::uint32_t> tris;
        PlaneCut cut, brute;
        SectionImage reused;
        for (int k = 0; k < planes; ++k) {
            const Plane p = test::randomPlane(bounds, rng, k);
            // The section path first, while nothing of this plane is in the caches: leaves
            // (traversal only), then their triangles cut, then assembly, timed one by one.
            beginCut(idx, p, cut, exitsOnly);
            CutStats cs;
            double c = bench::threadCpuSeconds();
            cutWithBvh(idx, nullptr, cut, 1, &cs);
            cCut.push_back(1000.0 * (bench::threadCpuSeconds() - c));
            tQuery.push_back(cs.queryMs);
            tCut.push_back(cs.cutMs);
            nodesVisited.push_back(double(cs.nodesVisited));
            trisTested.push_back(double(cs.trianglesTested));
            Section section;
            section.plane = p;
            c = bench::threadCpuSeconds();
            double s = bench::nowSeconds();
            assembleContours(idx, cut, section);
            tAssemble.push_back(ms(s));
            cAssemble.push_back(1000.0 * (bench::threadCpuSeconds() - c));
            tContours.push_back(tQuery.back() + tCut.back() + tAssemble.back());
            segments.push_back(double(cut.segments));
            // The crossing triangles themselves (queryPlane tests each leaf triangle).
            tris.clear();
            BvhQueryStats qs;
            s = bench::nowSeconds();
            queryPlane(idx.bvh, idx.meshes.data(), toLocal(p, idx.origin), tris, &qs);
            tQueryTris.push_back(ms(s));
            crossing.push_back(double(tris.size()));
            // The same with the cut on two threads.
            {
                SectionOptions two;
                two.threads = 2;
                const double pc = bench::processCpuSeconds();
                s = bench::nowSeconds();
                auto sec2 = computeSection(idx, p, two);
                tContours2.push_back(ms(s));
                cSection2.push_back(1000.0 * (bench::processCpuSeconds() - pc));
                if (sec2) {
                    RasterOptions ro;
                    auto img2 =
                        rasterizeSection(idx, sec2.value(), fitFrame(sec2.value(), side, side), side, side, ro, reused);
                    (void)img2;
                }
                tEnd2.push_back(ms(s));
                // The same on one thread, timed the same way (wall and process CPU).
                const double pc1 = bench::processCpuSeconds();
                s = bench::nowSeconds();
                auto sec1 = computeSection(idx, p);
                tSection1.push_back(ms(s));
                cSection1.push_back(1000.0 * (bench::processCpuSeconds() - pc1));
                (void)sec1;
            }
            for (const auto& b : section.bodies) openChains += b.openChains;
            // computeSection with closed bodies' exit points only and with both points of every
            // segment, alternating which goes first (thread CPU and wall), then the same on two
            // threads; the sections must be equal bit for bit.
            {
                double cpu[2], wall[2];
                Section got[2];
                for (int j = 0; j < 2; ++j) {
                    const bool exitsNow = ((k & 1) != 0) == (j == 0);
                    SectionOptions o;
                    o.exitsOnly = exitsNow;
                    const double c0 = bench::threadCpuSeconds(), w0 = bench::nowSeconds();
                    auto sec = computeSection(idx, p, o);
                    wall[exitsNow] = ms(w0);
                    cpu[exitsNow] = 1000.0 * (bench::threadCpuSeconds() - c0);
                    if (sec) got[exitsNow] = std::move(sec).value();
                }
                ewBothCpu.push_back(cpu[0]);
                ewExitsCpu.push_back(cpu[1]);
                ewRatio.push_back(cpu[1] / cpu[0]);
                ewBothWall.push_back(wall[0]);
                ewExitsWall.push_back(wall[1]);
                ewDiffer += !sameSection(got[0], got[1]);
                for (int j = 0; j < 2; ++j) {
                    const bool exitsNow = ((k & 1) != 0) == (j == 0);
                    SectionOptions o;
                    o.exitsOnly = exitsNow;
                    o.threads = 2;
                    const double w0 = bench::nowSeconds();
                    auto sec = computeSection(idx, p, o);
                    (exitsNow ? ewExits2 : ewBoth2).push_back(ms(w0));
                    ewDiffer += !sec || !sameSection(sec.value(), got[exitsNow]);
                }
            }
            // The same cut on the generator-ordered copy and on the leaf-ordered model,
            // alternating which goes first (thread CPU: the machine may be shared).
            if (plainIndex) {
                double cpu[2];
                for (int j = 0; j < 2; ++j) {
                    const bool leafFirst = (k & 1) != 0;
                    const bool leafNow = leafFirst == (j == 0);
                    const SectionIndex& which = leafNow ? idx : *plainIndex;
                    PlaneCut ab;
                    beginCut(which, p, ab);
                    const double c0 = bench::threadCpuSeconds();
                    cutWithBvh(which, nullptr, ab, 1);
                    cpu[leafNow ? 1 : 0] = 1000.0 * (bench::threadCpuSeconds() - c0);
                    if (ab.segments != cut.segments) {
                        std::fprintf(stderr, "plane %d: leaf order changed the segment count\n", k);
                        return 1;
                    }
                }
                abPlain.push_back(cpu[0]);
                abLeaf.push_back(cpu[1]);
                abRatio.push_back(cpu[1] / cpu[0]);
            }

            const FrameRect full = fitFrame(section, side, side);
            // Fill into fresh buffers (allocation and page faults included).
            bool ok = true;
            if (oracle) {
                RasterOptions idsOnly;
                idsOnly.colour = false;
                auto oimg = rasterizeSection(idx, section, fitFrame(section, oracleSide, oracleSide), oracleSide,
                                             oracleSide, idsOnly);
                if (oimg) {
                    oraclePts.resize(oimg->ids.size());
                    oracleIds.resize(oimg->ids.size());
                    for (int j = 0; j < oracleSide; ++j)
                        for (int i = 0; i < oracleSide; ++i)
                            oraclePts[std::size_t(j) * std::size_t(oracleSide) + std::size_t(i)] =
                                oimg->frame.pixelCentreWorld(i, j);
                    oracle->classifyBatch(oraclePts.data(), oraclePts.size(), oracleIds.data());
                    for (std::size_t i = 0; i < oracleIds.size(); ++i) oracleDiffer += oracleIds[i] != oimg->ids[i];
                    oraclePixels += oracleIds.size();
                }
            }
            std::string why;
            {
                s = bench::nowSeconds();
                auto img = rasterizeSection(idx, section, full, side, side);
                tFill.push_back(ms(s));
                if (!img) ok = false, why = img.error().message;
            }
            // The same into buffers kept from the previous plane (a render worker's).
            c = bench::threadCpuSeconds();
            s = bench::nowSeconds();
            ok = rasterizeSection(idx, section, full, side, side, RasterOptions{}, reused).ok() && ok;
            tFillReused.push_back(ms(s));
            cFill.push_back(1000.0 * (bench::threadCpuSeconds() - c));
            // Its two parts alone: the ID buffer, then the anti-aliased colour.
            for (int part = 0; part < 2; ++part) {
                RasterOptions one;
                one.colour = part == 1;
                one.ids = part == 0;
                s = bench::nowSeconds();
                ok = rasterizeSection(idx, section, full, side, side, one, reused).ok() && ok;
                (part == 0 ? tFillIds : tFillColour).push_back(ms(s));
            }
            // A tile of tileSide pixels at the same scale, at the frame centre, from the BVH.
            const double pu = (full.u1 - full.u0) / side, pv = (full.v1 - full.v0) / side;
            const double cu = 0.5 * (full.u0 + full.u1), cv = 0.5 * (full.v0 + full.v1);
            const FrameRect tile{cu, cv, cu + tileSide * pu, cv + tileSide * pv};
            {
                s = bench::nowSeconds();
                auto timg = renderTile(idx, p, tile, tileSide, tileSide);
                tTile.push_back(ms(s));
                if (!timg) ok = false, why = timg.error().message;
            }
            // End to end: validated plane -> section -> colour + ID image (reused buffers).
            c = bench::threadCpuSeconds();
            s = bench::nowSeconds();
            auto sec = computeSection(idx, p);
            tSection.push_back(ms(s));
            if (sec)
                ok = rasterizeSection(idx, sec.value(), full, side, side, RasterOptions{}, reused).ok() && ok;
            else
                ok = false, why = sec.error().message;
            tEnd.push_back(ms(s));
            cEnd.push_back(1000.0 * (bench::threadCpuSeconds() - c));
            s = bench::nowSeconds();
            beginCut(idx, p, brute);
            cutAllTriangles(idx, brute);
            tBrute.push_back(ms(s));
            if (!ok || brute.segments != cut.segments) {
                std::fprintf(stderr, "plane %d: failure (%s)\n", k,
                             why.empty() ? "segment count mismatch" : why.c_str());
                return 1;
            }
        }
        // Virtual boreholes (all hits, Embree), polyline sections and reserves.
        t = bench::nowSeconds();
        auto tracer = BoreholeTracer::build(model.value());
        const double tracerBuildS = bench::nowSeconds() - t;
        if (!tracer) {
            std::fprintf(stderr, "%s\n", tracer.error().message.c_str());
            return 1;
        }
        std::vector<double> tHole, holeIntervals, tLine, tLineEnd;
        std::uniform_real_distribution<double> fx(0.05, 0.95);
        for (int k = 0; k < 4 * planes; ++k) {
            const double x = bounds.min.x + fx(rng) * (bounds.max.x - bounds.min.x);
            const double y = bounds.min.y + fx(rng) * (bounds.max.y - bounds.min.y);
            double s = bench::nowSeconds();
            auto hole = (*tracer)->traceVertical(x, y);
            tHole.push_back(1000.0 * ms(s));
            if (!hole) {
                std::fprintf(stderr, "borehole %d: %s\n", k, hole.error().message.c_str());
                return 1;
            }
            holeIntervals.push_back(double(hole->intervals.size()));
        }
        for (int k = 0; k < planes; ++k) {
            std::vector<glm::dvec2> line;
            for (int i = 0; i < 3; ++i)
                line.push_back({bounds.min.x + fx(rng) * (bounds.max.x - bounds.min.x),
                                bounds.min.y + fx(rng) * (bounds.max.y - bounds.min.y)});
            double s = bench::nowSeconds();
            auto ps = computePolylineSection(idx, line);
            tLine.push_back(ms(s));
            if (!ps) {
                std::fprintf(stderr, "line %d: %s\n", k, ps.error().message.c_str());
                return 1;
            }
            auto img =
                rasterizePolylineSection(idx, ps.value(), fitPolylineFrame(ps.value(), side, side / 2), side, side / 2);
            tLineEnd.push_back(ms(s));
            if (!img) {
                std::fprintf(stderr, "line %d: %s\n", k, img.error().message.c_str());
                return 1;
            }
        }
        t = bench::nowSeconds();
        auto whole = computeReserves(model.value());
        const double reservesMs = ms(t);
        t = bench::nowSeconds();
        auto clipped = computeReserves(model.value(), test::randomPlane(bounds, rng, 2));
        const double reservesPlaneMs = ms(t);
        if (!whole || !clipped) {
            std::fprintf(stderr, "reserves failed\n");
            return 1;
        }

        results.push_back({
            {"model", size},
            {"triangles", model->triangleCount()},
            {"generate_and_validate_s", genS},
            {"leaf_order", leafOrder},
            {"leaf_order_s", reorderS},
            {"index_build_s", buildS},
            {"index_build_cpu_s", buildCpuS},
            {"index_bytes_mib", double(idx.memoryBytes()) / (1024.0 * 1024.0)},
            {"bvh_nodes", idx.bvh.nodes.size()},
            {"bvh_leaf_size", leaf},
            {"rss_before_index_mib", rssBefore},
            {"rss_after_index_mib", rssAfter},
            {"index_build_peak_extra_mib", rssPeakBuild - rssBefore},
            {"planes", planes},
            {"median_triangles_crossing", bench::median(crossing)},
            {"median_segments", bench::median(segments)},
            {"open_chains_total", openChains},
            {"oracle_pixel_centres", oraclePixels},
            {"oracle_differ", oracleDiffer},
            {"median_ms",
             {{"bvh_query_crossing_triangles", bench::median(tQueryTris)},
              {"bvh_query", bench::median(tQuery)},
              {"cut", bench::median(tCut)},
              {"contour_assembly", bench::median(tAssemble)},
              {"contours_total", bench::median(tContours)},
              {"contours_total_2_threads", bench::median(tContours2)},
              {"compute_section_1_thread_next_to_2", bench::median(tSection1)},
              {"fill_" + std::to_string(side) + "_fresh_buffers", bench::median(tFill)},
              {"fill_" + std::to_string(side), bench::median(tFillReused)},
              {"fill_" + std::to_string(side) + "_ids_only", bench::median(tFillIds)},
              {"fill_" + std::to_string(side) + "_colour_only", bench::median(tFillColour)},
              {"tile_" + std::to_string(tileSide), bench::median(tTile)},
              {"compute_section", bench::median(tSection)},
              {"end_to_end_" + std::to_string(side), bench::median(tEnd)},
              {"end_to_end_" + std::to_string(side) + "_2_threads", bench::median(tEnd2)},
              {"brute_force_cut", bench::median(tBrute)}}},
            {"median_cpu_ms",
             {{"bvh_query_and_cut", bench::median(cCut)},
              {"compute_section_process_cpu_1_thread", bench::median(cSection1)},
              {"compute_section_process_cpu_2_threads", bench::median(cSection2)},
              {"contour_assembly", bench::median(cAssemble)},
              {"fill_" + std::to_string(side), bench::median(cFill)},
              {"end_to_end_" + std::to_string(side), bench::median(cEnd)}}},
            {"borehole",
             {{"tracer_build_s", tracerBuildS},
              {"holes", tHole.size()},
              {"median_us_per_vertical_hole", bench::median(tHole)},
              {"median_intervals", bench::median(holeIntervals)}}},
            {"polyline_3_points",
             {{"lines", tLine.size()},
              {"median_ms_section", bench::median(tLine)},
              {"median_ms_end_to_end_" + std::to_string(side) + "x" + std::to_string(side / 2),
               bench::median(tLineEnd)}}},
            {"reserves_ms", {{"whole_model", reservesMs}, {"kept_side_of_a_plane", reservesPlaneMs}}},
            {"leaf_order_vs_generator_order",
             {{"planes", abRatio.size()},
              {"cut_cpu_ms_generator_order", bench::median(abPlain)},
              {"cut_cpu_ms_leaf_order", bench::median(abLeaf)},
              {"median_ratio", bench::median(abRatio)}}},
            {"exits_only_vs_both_points",
             {{"planes", ewRatio.size()},
              {"sections_differing", ewDiffer},
              {"compute_section_cpu_ms_both_points", bench::median(ewBothCpu)},
              {"compute_section_cpu_ms_exits_only", bench::median(ewExitsCpu)},
              {"median_ratio_cpu", bench::median(ewRatio)},
              {"compute_section_ms_both_points", bench::median(ewBothWall)},
              {"compute_section_ms_exits_only", bench::median(ewExitsWall)},
              {"compute_section_2_threads_ms_both_points", bench::median(ewBoth2)},
              {"compute_section_2_threads_ms_exits_only", bench::median(ewExits2)}}},
            {"median_nodes_visited", bench::median(nodesVisited)},
            {"median_leaf_triangles_cut", bench::median(trisTested)},
        });
        std::fprintf(stderr, "%s done\n", size.c_str());
    }
    json out = {{"benchmark", "section"},
                {"cores", std::thread::hardware_concurrency()},
                {"image", std::to_string(side) + "x" + std::to_string(side)},
                {"results", results},
                {"peak_rss_mib", bench::peakRssMiB()}};
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
