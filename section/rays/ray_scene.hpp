// One Embree scene over a model's closed bodies and open surfaces, built once and shared by
// every ray query of the model: the point classifier (section/rays/classify.hpp, bodies only) and
// the borehole tracer (section/rays/borehole.hpp, bodies and surfaces). Building it costs more than
// anything else at start-up (an L4 model: about a third of a cold start when each engine built
// its own scene), so a server builds one per model.
//
// Geometry: one Embree triangle geometry per closed body (validation's `closed`) and per open
// surface with triangles, float32 in the model's local frame (world - Model::origin), 16-byte
// vertex stride. partOf(geomID) says which part a hit belongs to.
// Scene flags: RTC_SCENE_FLAG_ROBUST (no ray slips between the triangles of a shared edge) and
// RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION (each query brings its own all-hits filter); build
// quality: RaySceneOptions::quality.
//
// Thread-safety: build once; the scene is immutable afterwards and may be traversed from any
// number of threads. The model must outlive the scene (index buffers are shared with it).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "model/model.hpp"
#include "model/result.hpp"

namespace geoslice {

struct RaySceneOptions {
    // Embree's BVH build quality. MEDIUM (the default) builds an SAH tree with spatial splits
    // off; LOW is Morton-code based: faster to build, slower to traverse.
    RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
    // RTC_SCENE_FLAG_COMPACT: a smaller tree (less memory to allocate and zero), slower rays.
    bool compact = false;
    // When set and turned true during the build, Embree stops building (its progress monitor,
    // polled by the build threads) and build() returns DeadlineExceeded ("cancelled").
    const std::atomic<bool>* cancel = nullptr;
};

class RayScene {
public:
    static Result<std::shared_ptr<const RayScene>> build(const Model& model, const RaySceneOptions& options = {});
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    RTCScene scene() const { return scene_; }
    // Part of a geometry id: >= 0 index into Model::bodies, < 0 -(index into Model::surfaces + 1).
    int partOf(unsigned geomId) const { return geomToPart_[geomId]; }
    const std::vector<int>& geometryParts() const { return geomToPart_; }
    const Model& model() const { return *model_; }
    glm::dvec3 origin() const { return origin_; }
    // Largest |local coordinate| (m) over the closed bodies, and over every finite vertex of
    // the scene: the float32 tolerances of the classifier and the tracer come from them.
    float maxLocalCoordBodies() const { return maxLocalBodies_; }
    float maxLocalCoordAll() const { return maxLocalAll_; }
    // Local bounds of each body (an empty box for bodies not in the scene), by body index.
    const std::vector<std::array<glm::vec3, 2>>& bodyBoxes() const { return boxes_; }
    std::size_t bodyTriangles() const { return bodyTriangles_; }

private:
    RayScene() = default;
    const Model* model_ = nullptr;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    // Local frame, 16-byte stride for Embree; default-initialised (written once, never zeroed).
    std::vector<std::unique_ptr<glm::vec4[]>> vertices_;
    std::vector<int> geomToPart_;
    std::vector<std::array<glm::vec3, 2>> boxes_;
    glm::dvec3 origin_{0.0};
    float maxLocalBodies_ = 0.0f, maxLocalAll_ = 0.0f;
    std::size_t bodyTriangles_ = 0;
};

}  // namespace geoslice
