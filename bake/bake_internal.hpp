// What the files of the whole-model bake share; not part of bake/'s API (bake/bake.hpp is).
//
//   bake.cpp          bakeModel: the stages (charts, LSCM, packing, raster) on worker threads
//   rebake.cpp        rebakePart: one part again, into the free space of an existing bake
//   flatten.cpp       a part's charts, flattened (split while LSCM flips or a chart outgrows a
//                     page) and emitted into the output mesh at their placements
//   chart_raster.cpp  one placed chart's record ids into the texture (plain and field)
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string_view>
#include <thread>
#include <vector>

#include "bake/bake.hpp"
#include "bake/field.hpp"

namespace geoslice::bake::bake_detail {

inline double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Runs fn(i) for i in [0, n) on `threads` workers; the calling thread reports progress.
template <class Fn>
void parallelFor(std::size_t n, unsigned threads, std::string_view stage, const ProgressFn& progress, Fn&& fn) {
    std::atomic<std::size_t> next{0}, done{0};
    auto work = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < n;) {
            fn(i);
            done.fetch_add(1);
        }
    };
    if (progress) progress(stage, 0.0);
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads && t < n; ++t) pool.emplace_back(work);
    while (done.load() < n) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (progress) progress(stage, double(done.load()) / double(n));
    }
    for (auto& th : pool) th.join();
    if (progress) progress(stage, 1.0);
}

struct PartWork {
    const Part* part = nullptr;
    std::size_t source = 0;
    std::vector<std::uint32_t> indices;  // welded
    Charts charts;
};

struct Flattened {
    std::uint32_t part = 0;
    std::vector<std::uint32_t> triangles;
    ChartUv uv;
    DistortionSums distortion;
    glm::dvec2 extent{0.0};  // metres; uv starts at (0, 0)
    bool split = false;      // came from cutting a chart (flips or size)
};

// The options and parts a bake refuses, with the reason (bake.cpp).
Status checkOptions(const BakeOptions& o);
Status checkPart(const Part& p);
// Part `source` of the model: bodies, then surfaces; null past the end (bake.cpp).
const Part* sourcePart(const Model& model, std::size_t source);
// Utilisation, distortion, chart, vertex and triangle counts of a finished bake (bake.cpp).
void finishStats(BakedModel& b);

// Welds the part's vertices and builds its charts (flatten.cpp).
void chartPart(PartWork& w, const ChartOptions& options);
// The largest chart extent (metres) that fits a page at `density`.
double maxExtentAt(double density, const PackOptions& o);
// Flattens chart `chart` of a part; pieces are cut and flattened again while LSCM flips or
// collapses a triangle or the chart exceeds maxExtent. Appends to `out` in a fixed order.
void flattenChart(const PartWork& w, std::uint32_t partIndex, std::size_t chart, double maxExtent,
                  std::vector<Flattened>& out);
// Appends a chart's vertices to its part (positions in the local frame, UVs on the page) and
// points the chart's triangles at them.
void emitChart(const Flattened& f, const Placement& pl, const Mesh& mesh, const glm::dvec3& origin, double density,
               std::uint32_t width, std::uint32_t height, BakedPart& bp);

// Rasterizes one emitted chart into its cell rectangle plus one texel of padding. Rectangles
// are at least `margin` (>= 2) apart, so padded ones never overlap: charts may be written
// concurrently (chart_raster.cpp).
void rasterChart(const Flattened& f, const Placement& pl, const BakedPart& bp, std::uint32_t width,
                 std::uint32_t height, std::uint32_t* texels);
// The field variant of rasterChart: each covered cell's centre is mapped back onto its nearest
// triangle of the chart (texel space -> barycentric) and takes the id of that point: for a block
// field, of the block holding the world point; for a vertex property (column >= 0 of the part's
// mesh), of the class of the value interpolated with those barycentric weights. Padding cells
// copy the id of their first covered neighbour (row by row, left to right).
void rasterChartField(const Flattened& f, const Placement& pl, const BakedPart& bp, const Mesh& mesh,
                      const FieldIds& field, int column, std::uint32_t width, std::uint32_t height,
                      std::uint32_t* texels);

}  // namespace geoslice::bake::bake_detail
