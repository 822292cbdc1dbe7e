// The routes, one family per file (OSRM's shape): each add*Routes registers its routes
// with the router; the handlers parse with api/, render through the render cache and
// answer with server/respond.hpp. api/openapi.cpp documents every route.
//
//   web.cpp        GET /, /web/{asset}                          the embedded web client
//   ops.cpp        GET /healthz, /readyz, /metrics, /openapi.json
//   models.cpp     GET /v1/models, /v1/models/{id}, /v1/models/{id}/legend.png
//   section.cpp    GET /v1/models/{id}/section.{jpg,png,webp}   profile and perspective images
//   vectors.cpp        ... section.{geojson,svg}                 (from section.cpp)
//   print.cpp          ... section.pdf, ?layout=print, ?decorate=1 print sheets (from section.cpp)
//   query.cpp      GET and POST /v1/models/{id}/query           pixel queries
//   borehole.cpp   GET /v1/models/{id}/borehole
//   reserves.cpp   GET /v1/models/{id}/reserves[.csv]
//   drillholes.cpp GET /v1/models/{id}/drillholes, .../drillholes/check[.csv], .../drillholes/{hole}/log
//   saved_sections.cpp GET, POST /v1/models/{id}/saved-sections, GET, DELETE .../saved-sections/{sid}
//   tiles.cpp      POST /v1/models/{id}/sections, GET /v1/sections/{sid}[/tiles/{z}/{x}/{y}.{fmt}]
//   tiles3d.cpp    GET /v1/models/{id}/3dtiles/tileset.json, .../3dtiles/tiles/{n}.glb   3D Tiles 1.1
//
// Threads: handlers run on transport handler threads and never render: renders go to the
// render workers through ServerState::cache.
#pragma once

#include <string>

#include "api/catalog.hpp"
#include "api/sheet.hpp"
#include "server/router.hpp"
#include "server/server_state.hpp"

namespace geoslice::server {

void addWebRoutes(Router& router, ServerState& state);
void addOpsRoutes(Router& router, ServerState& state);
void addModelRoutes(Router& router, ServerState& state);
void addSectionRoutes(Router& router, ServerState& state);
void addQueryRoutes(Router& router, ServerState& state);
void addBoreholeRoutes(Router& router, ServerState& state);
void addReservesRoutes(Router& router, ServerState& state);
void addDrillholeRoutes(Router& router, ServerState& state);
void addSavedSectionRoutes(Router& router, ServerState& state);
void addTileRoutes(Router& router, ServerState& state);
void addTiles3dRoutes(Router& router, ServerState& state);

// section.{format} hands these on (section.cpp decides which one answers).
// ext: geojson, svg or dxf.
void sectionVector(ServerState& state, const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m,
                   const std::string& ext);
void sectionSheet(ServerState& state, const HttpRequest& req, HttpResponse& res, const api::CatalogModel& m,
                  api::SheetFormat format, const std::string& ext);

// Everything, in the order routes are matched.
inline void addAllRoutes(Router& router, ServerState& state) {
    addWebRoutes(router, state);
    addOpsRoutes(router, state);
    addModelRoutes(router, state);
    addSectionRoutes(router, state);
    addQueryRoutes(router, state);
    addBoreholeRoutes(router, state);
    addReservesRoutes(router, state);
    addDrillholeRoutes(router, state);
    addSavedSectionRoutes(router, state);
    addTileRoutes(router, state);
    addTiles3dRoutes(router, state);
}

}  // namespace geoslice::server
