// The point classifier: classify(point) -> the record the exact section engine shows at
// that point, or kNoRecord. Every accuracy figure of geoslice is measured against it, and
// the HTTP ray query of profile views answers with it.
//
// Rule (the section engine's, section/fill/raster.hpp): of the closed bodies that contain the
// point, the one with the greatest nesting depth (validation's), and of equal depths the
// one latest in Model::bodies. Nested bodies win over their hosts; where neighbours overlap
// (real models overlap or leave gaps of centimetres) the later body wins, as it is painted
// last in the section's ID buffer.
//
// Method (Embree, one ray per point, in the model's shared RayScene; open surfaces ignored): all hits along a fixed
// generic direction; a body contains the point when the ray crosses it an odd number of times (ray parity per body,
// valid for closed shells however they overlap their neighbours). A ray that grazes an
// edge or vertex, or runs nearly parallel to a hit triangle, is re-cast in another
// direction. An earlier version took the nearest exit against the nearest entry and
// answered "no geology" 82 m to 1.3 km inside a body when a neighbour overlapped it by
// more than its tie tolerance; parity per body has no tie to break.
//
// Tolerance: rays run in the model's local float32 frame (world - origin), so a body's
// faces move by up to half a float32 ulp of the local coordinates. The answer equals the
// exact section engine's for every point farther than tolerance() = 1e-6 x (largest local
// coordinate) + 0.1 mm from every boundary (3.1 mm for a model reaching 3 km from its
// origin; float32's relative step is 6e-8, so this leaves a factor of ~16 for Embree's
// own rounding). Nearer than that, either side may be answered.
// Cost: a full traversal per point (every hit); figures in the README (bench_classify).
// Thread-safety: build once; classify*() may be called from any number of threads.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"
#include "section/rays/ray_scene.hpp"

namespace geoslice {

class Classifier {
public:
    // Builds an Embree scene over the model (section/rays/ray_scene.hpp), or uses `scene`, built for
    // this model and shared with other ray queries. The model must have been validated
    // (loaders and generateSynthetic + validate do so) for closed flags and nesting depths.
    static Result<std::unique_ptr<Classifier>> build(const Model& model);
    static Result<std::unique_ptr<Classifier>> build(const Model& model, std::shared_ptr<const RayScene> scene);
    ~Classifier();
    Classifier(const Classifier&) = delete;
    Classifier& operator=(const Classifier&) = delete;

    // World coordinates (x east, y north, z up, metres).
    RecordId classify(const glm::dvec3& world) const;
    int classifyBody(const glm::dvec3& world) const;  // index into Model::bodies, or -1
    // Splits the batch over `threads` threads (0 = hardware concurrency).
    void classifyBatch(const glm::dvec3* world, std::size_t n, RecordId* out, unsigned threads = 0) const;

    std::size_t triangleCount() const { return triangles_; }
    // Metres: answers equal the exact section engine's for points farther than this from
    // every boundary (see above).
    double tolerance() const;

private:
    Classifier() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::size_t triangles_ = 0;
};

}  // namespace geoslice
