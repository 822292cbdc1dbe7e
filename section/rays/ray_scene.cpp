#include "section/rays/ray_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace geoslice {

RayScene::~RayScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

Result<std::shared_ptr<const RayScene>> RayScene::build(const Model& model, const RaySceneOptions& options) {
    std::shared_ptr<RayScene> rs(new RayScene());
    rs->model_ = &model;
    rs->origin_ = model.origin;
    rs->device_ = rtcNewDevice("verbose=0");
    if (!rs->device_)
        return makeError(ErrorCode::Internal,
                         "Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    rs->scene_ = rtcNewScene(rs->device_);
    rtcSetSceneFlags(rs->scene_, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                               (options.compact ? RTC_SCENE_FLAG_COMPACT : 0)));
    rtcSetSceneBuildQuality(rs->scene_, options.quality);
    if (options.cancel)
        rtcSetSceneProgressMonitorFunction(
            rs->scene_, [](void* flag, double) { return !static_cast<const std::atomic<bool>*>(flag)->load(); },
            const_cast<std::atomic<bool>*>(options.cancel));
    constexpr float kInf = std::numeric_limits<float>::infinity();
    rs->boxes_.assign(model.bodies.size(), {glm::vec3(kInf), glm::vec3(-kInf)});
    auto attach = [&](const Part& part, int tag) {
        if (part.mesh.triangleCount() == 0) return;
        const std::size_t n = part.mesh.positions.size();
        auto& verts = rs->vertices_.emplace_back(new glm::vec4[n]);
        glm::vec3 lo(kInf), hi(-kInf);
        float maxAbs = 0.0f;
        for (std::size_t i = 0; i < n; ++i) {
            const glm::vec3 v(part.mesh.positions[i] - model.origin);
            verts[i] = glm::vec4(v, 0.0f);
            if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) {
                maxAbs = std::max({maxAbs, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
                lo = glm::min(lo, v);
                hi = glm::max(hi, v);
            }
        }
        rs->maxLocalAll_ = std::max(rs->maxLocalAll_, maxAbs);
        if (tag >= 0) {
            rs->maxLocalBodies_ = std::max(rs->maxLocalBodies_, maxAbs);
            rs->boxes_[static_cast<std::size_t>(tag)] = {lo, hi};
            rs->bodyTriangles_ += part.mesh.triangleCount();
        }
        RTCGeometry g = rtcNewGeometry(rs->device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, verts.get(), 0, sizeof(glm::vec4),
                                   n);
        rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, part.mesh.indices.data(), 0,
                                   3 * sizeof(std::uint32_t), part.mesh.triangleCount());
        rtcCommitGeometry(g);
        const unsigned id = rtcAttachGeometry(rs->scene_, g);
        rtcReleaseGeometry(g);
        if (rs->geomToPart_.size() <= id) rs->geomToPart_.resize(id + 1, 0);
        rs->geomToPart_[id] = tag;
    };
    for (std::size_t b = 0; b < model.bodies.size(); ++b)
        if (model.bodies[b].report.closed) attach(model.bodies[b], static_cast<int>(b));
    for (std::size_t s = 0; s < model.surfaces.size(); ++s) attach(model.surfaces[s], -static_cast<int>(s) - 1);
    if (options.cancel && options.cancel->load())
        return makeError(ErrorCode::DeadlineExceeded, "Embree: the scene build was cancelled");
    rtcCommitScene(rs->scene_);
    if (RTCError e = rtcGetDeviceError(rs->device_); e == RTC_ERROR_CANCELLED)
        return makeError(ErrorCode::DeadlineExceeded, "Embree: the scene build was cancelled");
    else if (e != RTC_ERROR_NONE)
        return makeError(ErrorCode::Internal, "Embree: scene build failed (error " + std::to_string(e) + ")");
    return std::shared_ptr<const RayScene>(std::move(rs));
}

}  // namespace geoslice
