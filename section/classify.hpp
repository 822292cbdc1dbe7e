// The exact oracle: classify(point) -> the record of the innermost closed body that
// contains the point, or kNoRecord. Every accuracy figure of geoslice is measured
// against it.
//
// Method (Embree, one ray per point): from p, along a fixed generic direction, find the
// nearest hit that *exits* a body (ray . outward normal > 0) and the nearest hit that
// *enters* one. If the exit is nearest (or ties with an entry: coincident faces of two
// bodies that share a boundary), p lies in the exited body; if an entry is strictly
// nearer, p lies outside the entered body C, in C's container (validation's nesting
// parent), or in nothing. For closed, outward, non-intersecting shells this is exactly
// the ray-parity rule restricted to the innermost body. A ray that grazes an edge or
// vertex, or runs nearly parallel to a hit triangle, is re-cast in another direction;
// classifyByParity() (all hits, parity per body) is the slow reference the tests use.
//
// Precision: rays run in the model's local float32 frame (world - origin). Hits on the
// two sides of a shared face count as one when within 1e-6 x (model half-extent + hit
// distance) + 0.1 mm (3 mm for a 6 km model): points nearer than that to a boundary may
// fall either side, and a body thinner than that along the ray is not resolved.
// Thread-safety: build once; classify*() may be called from any number of threads.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

class Classifier {
public:
    // Builds an Embree scene over the model's closed bodies. The model must have been
    // validated (loaders and generateSynthetic + validate do so) for nesting parents.
    static Result<std::unique_ptr<Classifier>> build(const Model& model);
    ~Classifier();
    Classifier(const Classifier&) = delete;
    Classifier& operator=(const Classifier&) = delete;

    // World coordinates (x east, y north, z up, metres).
    RecordId classify(const glm::dvec3& world) const;
    int classifyBody(const glm::dvec3& world) const;  // index into Model::bodies, or -1
    int classifyBodyByParity(const glm::dvec3& world) const;
    // Splits the batch over `threads` threads (0 = hardware concurrency).
    void classifyBatch(const glm::dvec3* world, std::size_t n, RecordId* out, unsigned threads = 0) const;

    std::size_t triangleCount() const { return triangles_; }

private:
    Classifier() = default;
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::size_t triangles_ = 0;
};

}  // namespace geoslice
