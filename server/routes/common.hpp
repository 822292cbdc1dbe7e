// What several route handlers share: the model of a request, a view checked before any
// cache is consulted, images encoded into cache entries, render memory estimates.
#pragma once

#include <atomic>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "api/catalog.hpp"
#include "api/plan.hpp"
#include "api/view.hpp"
#include "image/image_encode.hpp"
#include "model/result.hpp"
#include "server/http_message.hpp"
#include "server/render_cache.hpp"
#include "server/server_state.hpp"

namespace geoslice::server {

// Estimated peak memory of one render, for admission by memory (issue 11 item 4). Per
// pixel: the colour image and ID buffer kept until encoded (8), the fill's coverage and
// trace buffers (5), the encoder's working copies (WebP: YUVA planes and an ARGB copy, up
// to 12; PNG and JPEG less), and headroom for the allocator (7) = 32; GL views add their
// render targets (RGBA8, R32UI, depth-stencil: 12) and FXAA/read-back copies (8) = 52.
// An 8192^2 WebP was measured at about 2.1 GB (issue 11): 32 B/px gives 2.1 GiB.
constexpr std::size_t kExactBytesPerPixel = 32, kGlBytesPerPixel = 52;
constexpr std::size_t kVectorBytes = std::size_t(32) << 20;  // GeoJSON/SVG of one section
constexpr std::size_t kQueryAnswerBytes = 4096;              // one pixel's answer and scratch
inline std::size_t renderBytes(int width, int height, bool gl) {
    return std::size_t(width) * std::size_t(height) * (gl ? kGlBytesPerPixel : kExactBytesPerPixel);
}

// The model `id` names, or null after answering: 404 for an invalid id; 403 while API keys
// are on and the request's key (HttpRequest::key, set by the router) may not read `id`,
// decided before the catalog is consulted, so that a 403 says nothing about whether such a
// model exists; 404 for an unknown id, 503 + Retry-After while models are still loading.
// Every route that serves a model's data finds it here: the one place of the scope check.
std::shared_ptr<const api::CatalogModel> findModel(ServerState& state, const HttpRequest& req, const std::string& id,
                                                   HttpResponse& res);

// The content version a URL may name (`version=`, CatalogModel::version: the package checksum, so a
// re-bake makes new URLs). Absent: true (the answer is cacheable for a short while,
// sendEncoded). The served version: true (the answer never changes: cacheable for a year,
// immutable). Another: answers 404 naming both versions (code model_version) and returns
// false, so that an old URL never gets a new picture and a new one never an old picture (a
// replica still on the old version during a roll-out says so instead of answering).
bool versionPinHolds(const HttpRequest& req, const api::CatalogModel& m, HttpResponse& res);
// The query suffix that pins a URL to the model's version: "?version=<version>".
std::string versionQuery(const api::CatalogModel& m);

// True when the request may read model `id`: keys off, or its key's scope names `id`.
bool mayRead(const ServerState& state, const HttpRequest& req, std::string_view id);
// The 403 answer for a model the request's key may not read.
void forbidModel(HttpResponse& res, std::string_view id, const std::string& instance);

// How long a request handled on an HTTP thread waits for a model's ray scene (built after
// /readyz, api::CatalogModel::rays): the request deadline (config deadlineMs), or until its
// client goes away; then DeadlineExceeded (504).
api::RayWait rayWait(const ServerState& state, const HttpRequest& req);

// The request's query parameters (api::paramsFromQuery).
Result<api::Params> queryParams(const HttpRequest& req);

// Everything about a view that can be wrong, checked without rendering: for profile views
// the plane against the model and the frame's pixel size (api::profileMapping), for
// perspective views that GL is on. Errors name the parameter.
Status validateView(const ServerState& state, const api::CatalogModel& m, const api::ViewPlan& plan);

// An image encoded as a cache entry. Runs on a render worker.
Rendered encodeEntry(const api::ViewImage& v, ImageFormat format, int quality, const std::string& etag,
                     const std::atomic<bool>* cancel = nullptr);
// A text or binary document as a cache entry.
Rendered documentEntry(std::string body, std::string contentType, std::string etag);

std::vector<std::string_view> withNames(std::vector<std::string_view> names,
                                        std::initializer_list<std::string_view> more);

}  // namespace geoslice::server
