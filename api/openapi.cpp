#include "api/openapi.hpp"

#include <map>
#include <string>

#include "view/view_limits.hpp"

namespace geoslice::api {
namespace {

using J = nlohmann::ordered_json;

J queryParam(const char* name, const char* type, const std::string& description, bool required = false) {
    return J{{"name", name},
             {"in", "query"},
             {"required", required},
             {"description", description},
             {"schema", {{"type", type}}}};
}
J pathParam(const char* name, const char* description, J schema = J{{"type", "string"}}) {
    return J{{"name", name}, {"in", "path"}, {"required", true}, {"description", description}, {"schema", schema}};
}

J viewParams() {
    return J::array({
        queryParam("plane", "string",
                   "a,b,c,d: world plane, keeps a*x+b*y+c*z+d >= 0 (x easting, y northing, z up, m); repeated up "
                   "to 6 times for a cut-out of a perspective view (with 'cut')"),
        queryParam("planes", "string",
                   "a,b,c,d;a,b,c,d;...: 2..6 planes of a cut-out of a perspective view, the same as repeated "
                   "'plane' (not both)"),
        queryParam("cut", "string",
                   "with 2..6 planes, required: union (remove the union of the planes' removed sides a*x+b*y+c*z+d "
                   "< 0: keep what is on the kept side of every plane) or intersection (remove what is on the "
                   "removed side of every plane: a wedge, octant or box taken out)"),
        queryParam("line", "string", "x1,y1,x2,y2[,...]: vertical section along a map polyline (2..256 vertices)"),
        queryParam("elevation", "number", "horizontal slice (plan map) at this elevation, m"),
        queryParam("coords", "string",
                   "world (default) or lonlat: units of 'line' (degrees lon,lat on the model CRS's own datum); "
                   "with 'plane' or 'elevation' a 400 (world coordinates, always)"),
        queryParam("view", "string", "profile (default, exact CPU engine) or perspective (GL renderer)"),
        queryParam("frame", "string", "u0,u1,v0,v1: plane u/v metres shown in a profile (default: model bounds)"),
        queryParam("eye", "string", "x,y,z: perspective camera position, world m"),
        queryParam("target", "string", "x,y,z: perspective look-at point, world m"),
        queryParam("up", "string", "x,y,z: perspective up vector (default 0,0,1)"),
        // The limits as view/view_limits.hpp states them (the CLI checks the same ones).
        queryParam("fov", "number",
                   "perspective vertical field of view, degrees " + limitNumber(kMinFovDeg) + ".." +
                       limitNumber(kMaxFovDeg) + " (default 45)"),
        queryParam("size", "string",
                   "WxH pixels, each 1.." + std::to_string(kMaxImageSide) + ", at most " +
                       std::to_string(kMaxImagePixels) + " pixels (default 1024x1024)"),
        queryParam("vx", "number",
                   "vertical exaggeration " + limitNumber(kMinExaggeration) + ".." + limitNumber(kMaxExaggeration) +
                       " (default 1): elevation stretched vx times about the centre elevation of the model's bounds "
                       "(a plane's v axis by sqrt(nz^2 + vx^2 (1 - nz^2)))"),
        queryParam("bg", "string", "transparent (default) or #rrggbb[aa]"),
        queryParam("colour", "string",
                   "a block property (the model's block model): the clipping bodies coloured by its class at "
                   "each cell's exact piece; profile views, tiles, GeoJSON and SVG"),
        queryParam("breaks", "string", "b1,b2,...: increasing class breaks of 'colour' (default: 5 equal classes)"),
        queryParam("ramp", "string", "colour ramp of 'colour': viridis (default), magma, greys, spectral"),
        queryParam("labels", "string",
                   "0|1: profile views, unit codes inside their polygons (default: on in print sheets, off in "
                   "images and SVG)"),
        queryParam("patterns", "string",
                   "0|1: profile views, lithology fill patterns (default: on in SVG and print sheets, off in images)"),
        queryParam("hide", "string",
                   "r1,r2,...: perspective views, record ids left out (the model drawn without those bodies and "
                   "surfaces; a shown body nested in a hidden one is capped by its nearest shown container); pixel "
                   "queries answer the same picture"),
        queryParam("isolate", "string", "r1,r2,...: perspective views, the only record ids drawn (not with hide)"),
        queryParam("holes", "number",
                   "drillholes within this many metres of the section drawn on profile views, 0..100000 (default "
                   "50; 0: none)"),
        queryParam("holecolour", "string",
                   "an interval column (or TABLE.COLUMN) of the model's drillholes: intervals coloured by category "
                   "or class"),
        queryParam("holebreaks", "string", "b1,b2,...: class breaks of a number 'holecolour' column"),
        queryParam("holeramp", "string", "colour ramp of 'holecolour': viridis (default), magma, greys, spectral"),
    });
}

J problem(const char* description) {
    return J{{"description", description},
             {"content", {{"application/problem+json", {{"schema", {{"$ref", "#/components/schemas/Problem"}}}}}}}};
}

J imageResponse() {
    return J{{"description", "the image; ETag and Cache-Control set, If-None-Match gives 304"},
             {"content", {{"image/jpeg", J::object()}, {"image/png", J::object()}, {"image/webp", J::object()}}}};
}

// A JSON answer described by components/schemas/<schema>.
J jsonResponse(const char* description, const char* schema) {
    return J{
        {"description", description},
        {"content", {{"application/json", {{"schema", {{"$ref", std::string("#/components/schemas/") + schema}}}}}}}};
}

// JSON Schema helpers for the answers' schemas (OpenAPI 3.0's subset).
const J kNum = {{"type", "number"}}, kInt = {{"type", "integer"}}, kStr = {{"type", "string"}},
        kBool = {{"type", "boolean"}}, kObj = {{"type", "object"}};
J arrayOf(J items) { return J{{"type", "array"}, {"items", std::move(items)}}; }
J nullable(J s) {
    s["nullable"] = true;
    return s;
}
J ref(const char* name) { return J{{"$ref", std::string("#/components/schemas/") + name}}; }
// An object with these properties, all required unless listed in `optional`; more allowed.
J object(J properties, std::initializer_list<const char*> optional = {}) {
    J required = J::array();
    for (const auto& [k, v] : properties.items()) {
        bool opt = false;
        for (const char* o : optional) opt = opt || k == o;
        if (!opt) required.push_back(k);
    }
    J o = {{"type", "object"}, {"properties", std::move(properties)}};
    if (!required.empty()) o["required"] = std::move(required);
    return o;
}

// The schemas of the JSON answers (checked against real answers by tests/web/openapi_test.mjs).
J answerSchemas() {
    const J xyz = J{{"type", "array"}, {"items", kNum}, {"minItems", 3}, {"maxItems", 3}};
    const J bounds = object({{"min", xyz}, {"max", xyz}});
    J s;
    s["Health"] = object({{"status", kStr}, {"version", kStr}});
    s["Readiness"] =
        object({{"ready", kBool}, {"models", kObj}, {"workers", kInt}, {"renders", kObj}, {"memory", kObj}},
               {"workers", "renders", "memory"});
    s["Crs"] =
        object({{"id", kStr}, {"name", kStr}, {"axes", arrayOf(kStr)}, {"units", kStr}}, {"name", "axes", "units"});
    s["ModelSummary"] = object({{"id", kStr},
                                {"version", kStr},
                                {"name", kStr},
                                {"crs", ref("Crs")},
                                {"bounds", bounds},
                                {"lonlatBounds", kObj},
                                {"triangles", kInt},
                                {"bodies", kInt},
                                {"surfaces", kInt},
                                {"legend", arrayOf(ref("LegendEntry"))}},
                               {"lonlatBounds", "legend", "name"});
    s["LegendEntry"] = object({{"id", kInt}, {"name", kStr}, {"colour", kStr}}, {});
    s["ModelList"] = object({{"models", arrayOf(ref("ModelSummary"))}, {"loading", kBool}}, {"loading"});
    s["QueryAnswer"] = object({{"model", kStr},
                               {"version", kStr},
                               {"pixel", object({{"x", kInt}, {"y", kInt}}, {})},
                               {"hit", kBool},
                               {"record", nullable(kObj)},
                               {"body", nullable(kStr)},
                               {"world", ref("WorldPoint")}},
                              {"record", "body", "world"});
    s["QueryBatch"] = object({{"results", arrayOf(ref("QueryAnswer"))}});
    s["Borehole"] = object(
        {{"model", kStr},
         {"version", kStr},
         {"origin", xyz},
         {"direction", xyz},
         {"intervals",
          arrayOf(object(
              {{"from_m", kNum}, {"to_m", kNum}, {"body", kStr}, {"record", kInt}, {"attributes", nullable(kObj)}},
              {"attributes"}))}},
        {"version"});
    s["Reserves"] = object({{"model", kStr},
                            {"plane", nullable(arrayOf(kNum))},
                            {"bodies", arrayOf(object({{"body", kStr},
                                                       {"record", kInt},
                                                       {"gross_volume_m3", kNum},
                                                       {"net_volume_m3", kNum},
                                                       {"tonnage_t", nullable(kNum)}},
                                                      {"tonnage_t"}))}},
                           {"plane"});
    s["DrillholeCheck"] = object({{"model", kStr},
                                  {"table", kStr},
                                  {"column", kStr},
                                  {"summary", object({{"holes", kInt},
                                                      {"holes_traced", kInt},
                                                      {"logged_m", kNum},
                                                      {"agreed_m", kNum},
                                                      {"share", nullable(kNum)}},
                                                     {})},
                                  {"codes", arrayOf(kObj)},
                                  {"holes", arrayOf(kObj)}});
    s["Drillholes"] = object(
        {{"model", kStr},
         {"version", kStr},
         {"crs", nullable(kStr)},
         {"columns", arrayOf(object({{"table", kStr}, {"column", kStr}, {"kind", kStr}, {"unit", nullable(kStr)}}))},
         {"holes", arrayOf(object({{"id", kStr},
                                   {"collar", xyz},
                                   {"depth", kNum},
                                   {"azimuth", kNum},
                                   {"dip", kNum},
                                   {"trace", arrayOf(xyz)}}))}});
    const J savedSection = object({{"id", kStr},
                                   {"number", nullable(kStr)},
                                   {"name", kStr},
                                   {"source", kStr},
                                   {"query", kStr},
                                   {"created", kStr}},
                                  {"created"});
    s["SavedSection"] = savedSection;
    s["ContextLayer"] = object({{"type", kStr}, {"features", arrayOf(kObj)}, {"geoslice", kObj}});
    s["SavedSections"] = object({{"model", kStr},
                                 {"version", kStr},
                                 {"saving", kBool},
                                 {"warnings", arrayOf(kStr)},
                                 {"sections", arrayOf(ref("SavedSection"))}});
    s["DrillholeLog"] = object(
        {{"hole", kStr}, {"version", kStr}, {"collar", xyz}, {"model", object({{"intervals", arrayOf(kObj)}}, {})}},
        {"version"});
    const J grid = object({{"tileSize", kInt},
                           {"minZoom", kInt},
                           {"maxZoom", kInt},
                           {"size0", kNum},
                           {"exaggeration", kNum},
                           {"origin", object({{"u", kNum}, {"v", kNum}})},
                           {"extent", object({{"u0", kNum}, {"u1", kNum}, {"v0", kNum}, {"v1", kNum}})}},
                          {});
    s["TileGrid"] = grid;
    s["SectionDefinition"] = object({{"sid", kStr},
                                     {"model", kStr},
                                     {"definition", kStr},
                                     {"grid", ref("TileGrid")},
                                     {"tiles", kStr},
                                     {"tilejson", kStr},
                                     {"ogcTiles", kStr}},
                                    {"tiles", "tilejson", "ogcTiles"});
    s["TileJson"] = object({{"tilejson", kStr},
                            {"tiles", J{{"type", "array"}, {"items", kStr}, {"minItems", 1}}},
                            {"minzoom", kInt},
                            {"maxzoom", kInt},
                            {"scheme", kStr},
                            {"name", kStr}},
                           {"name", "scheme"});
    s["Tileset3d"] = object({{"asset", object({{"version", kStr}, {"generator", kStr}}, {"generator"})},
                             {"geometricError", kNum},
                             {"root", object({{"transform", arrayOf(kNum)},
                                              {"boundingVolume", kObj},
                                              {"geometricError", kNum},
                                              {"refine", kStr},
                                              {"content", kObj},
                                              {"children", arrayOf(kObj)}},
                                             {"content", "children"})},
                             {"extras", kObj}},
                            {"extras"});
    s["OgcTileset"] = object({{"dataType", kStr},
                              {"crs", kObj},
                              {"tileMatrixSetURI", kStr},
                              {"links", arrayOf(object({{"rel", kStr}, {"href", kStr}}, {}))}},
                             {"tileMatrixSetURI"});
    s["TileMatrixSet"] = object({{"id", kStr},
                                 {"crs", kObj},
                                 {"tileMatrices", arrayOf(object({{"id", kStr},
                                                                  {"scaleDenominator", kNum},
                                                                  {"cellSize", kNum},
                                                                  {"pointOfOrigin", arrayOf(kNum)},
                                                                  {"tileWidth", kInt},
                                                                  {"tileHeight", kInt},
                                                                  {"matrixWidth", kInt},
                                                                  {"matrixHeight", kInt}}))}});
    s["FeatureCollection"] =
        object({{"type", J{{"type", "string"}, {"enum", {"FeatureCollection"}}}},
                {"features", arrayOf(object({{"type", kStr}, {"geometry", kObj}, {"properties", kObj}}))}});
    s["OpenApiDocument"] = object({{"openapi", kStr}, {"info", kObj}, {"paths", kObj}});
    return s;
}

J errors() {
    return J{{"400", problem("a bad parameter: the detail names it")},
             {"404", problem("unknown model, section or tile")},
             {"503", problem("the render queue is full (Retry-After) or the model is still loading")}};
}

J op(const char* summary, J parameters, J okResponse) {
    J responses = errors();
    responses["200"] = std::move(okResponse);
    return J{{"summary", summary}, {"parameters", std::move(parameters)}, {"responses", std::move(responses)}};
}

J concat(J a, const J& b) {
    for (const auto& x : b) a.push_back(x);
    return a;
}

}  // namespace

const std::vector<RouteSpec>& apiRoutes() {
    static const std::vector<RouteSpec> routes = {
        {"GET", "/"},
        {"GET", "/web/{asset}"},
        {"GET", "/healthz"},
        {"GET", "/readyz"},
        {"GET", "/metrics"},
        {"GET", "/openapi.json"},
        {"GET", "/v1/models"},
        {"GET", "/v1/models/{id}"},
        {"GET", "/v1/models/{id}/legend.png"},
        {"GET", "/v1/models/{id}/context.geojson"},
        {"GET", "/v1/models/{id}/section.{format}"},
        {"GET", "/v1/models/{id}/query"},
        {"POST", "/v1/models/{id}/query"},
        {"GET", "/v1/models/{id}/borehole"},
        {"GET", "/v1/models/{id}/reserves"},
        {"GET", "/v1/models/{id}/reserves.csv"},
        {"GET", "/v1/models/{id}/drillholes"},
        {"GET", "/v1/models/{id}/drillholes/check"},
        {"GET", "/v1/models/{id}/drillholes/check.csv"},
        {"GET", "/v1/models/{id}/drillholes/{hole}/log"},
        {"GET", "/v1/models/{id}/saved-sections"},
        {"POST", "/v1/models/{id}/saved-sections"},
        {"GET", "/v1/models/{id}/saved-sections/{sid}"},
        {"DELETE", "/v1/models/{id}/saved-sections/{sid}"},
        {"POST", "/v1/models/{id}/sections"},
        {"GET", "/v1/sections/{sid}"},
        {"GET", "/v1/sections/{sid}/tiles/{z}/{x}/{y}.{format}"},
        {"GET", "/v1/sections/{sid}/tilejson.json"},
        {"GET", "/v1/sections/{sid}/tiles"},
        {"GET", "/v1/sections/{sid}/tilematrixset"},
        {"GET", "/v1/models/{id}/3dtiles/tileset.json"},
        {"GET", "/v1/models/{id}/3dtiles/tiles/{n}.glb"},
    };
    return routes;
}

namespace {

// The parameters shared by several operations.
J idParam() { return pathParam("id", "model id: [A-Za-z0-9][A-Za-z0-9._-]{0,63}"); }
J sidParam() { return pathParam("sid", "stateless section id from POST /v1/models/{id}/sections"); }
J tileFormatParam() {
    return pathParam("format", "image format", J{{"type", "string"}, {"enum", {"jpg", "png", "webp"}}});
}
void get(J& paths, const std::string& path, J operation) { paths[path]["get"] = std::move(operation); }
void post(J& paths, const std::string& path, J operation) { paths[path]["post"] = std::move(operation); }

// The operator's routes and the web client.
void addOpsPaths(J& paths) {
    get(paths, "/",
        op("the thin web client: plan map, sections as tiles, 3D view with a draggable plane, pixel queries, boreholes",
           J::array(), J{{"description", "HTML"}, {"content", {{"text/html", J::object()}}}}));
    get(paths, "/web/{asset}",
        op("the web client's scripts, styles and images (Leaflet from Debian's libjs-leaflet)",
           J::array({pathParam("asset", "asset path, e.g. app.js or leaflet/leaflet.css")}),
           J{{"description", "the asset; ETag, Cache-Control"},
             {"content", {{"text/javascript", J::object()}, {"text/css", J::object()}, {"image/png", J::object()}}}}));
    get(paths, "/healthz", op("liveness: the process answers", J::array(), jsonResponse("ok", "Health")));
    get(paths, "/readyz",
        op("readiness: models loaded (and, for perspective views, a GL device found); `rays` gives each "
           "model's ray scene (pending, building, ready, failed), which queries without a cached image, "
           "perspective queries and boreholes wait for up to their deadline (504 past it); "
           "models.failed (id, error), models.skipped (models-directory entries not loaded: entry, "
           "reason) and models.warnings (id, warning: e.g. a failed bake, the model served from memory) "
           "are reported, not a reason to be unready. While the server has API keys, models.failed, "
           "models.skipped, models.warnings and rays are counts and name no model",
           J::array(), jsonResponse("ready; 503 while loading", "Readiness")));
    get(paths, "/metrics",
        op("Prometheus text format: requests and latency per route, queue depth, cache hits, render times", J::array(),
           J{{"description", "metrics"}, {"content", {{"text/plain", J::object()}}}}));
    get(paths, "/openapi.json", op("this document", J::array(), jsonResponse("OpenAPI 3 document", "OpenApiDocument")));
}

// Models, section images and vectors, queries, boreholes.
void addModelPaths(J& paths) {
    const J id = idParam();
    const J sectionFormat =
        pathParam("format",
                  "image format, or vector: geojson (polygons and traces with attributes and areas), svg or dxf "
                  "(CAD: a layer per unit, polylines, hatches, labels), or pdf (a print-ready section sheet)",
                  J{{"type", "string"}, {"enum", {"jpg", "png", "webp", "geojson", "svg", "dxf", "pdf"}}});
    J sectionResponse = imageResponse();
    for (const char* type : {"image/svg+xml", "image/vnd.dxf", "application/pdf"})
        sectionResponse["content"][type] = J::object();
    sectionResponse["content"]["application/geo+json"] = {{"schema", ref("FeatureCollection")}};
    get(paths, "/v1/models",
        op("the loaded models with bounds, CRS, bodies and legend (with API keys: the models the "
           "request's key may read)",
           J::array(), jsonResponse("models", "ModelList")));
    get(paths, "/v1/models/{id}", op("one model", J::array({id}), jsonResponse("the model", "ModelSummary")));
    get(paths, "/v1/models/{id}/3dtiles/tileset.json",
        op("the model as an OGC 3D Tiles 1.1 tileset (CesiumJS: Cesium3DTileset.fromUrl): a root transform from "
           "east-north-up metres at the model's centre to WGS 84 Earth-fixed coordinates, every vertex placed "
           "through PROJ; levels of detail with geometric errors in metres; content URIs tiles/{n}.glb relative "
           "to it. 422 for a model that is not on the globe (no CRS, or no WGS 84 transformation)",
           J::array({id}), jsonResponse("the tileset", "Tileset3d")));
    get(paths, "/v1/models/{id}/3dtiles/tiles/{n}.glb",
        op("one tile of the 3D Tiles tileset: glTF 2.0 binary, a primitive per part with normals and a material "
           "in its unit's colour, EXT_mesh_features (a feature id per vertex) and EXT_structural_metadata (every "
           "attribute of the unit and its colour)",
           J::array({id, pathParam("n", "tile number, as tileset.json names it", J{{"type", "integer"}})}),
           J{{"description", "glTF 2.0 binary"}, {"content", {{"model/gltf-binary", J::object()}}}}));
    get(paths, "/v1/models/{id}/legend.png",
        op("the legend as an image: one swatch per body with its name", J::array({id}),
           J{{"description", "PNG"}, {"content", {{"image/png", J::object()}}}}));
    get(paths, "/v1/models/{id}/section.{format}",
        op("a section image: profile views from the exact CPU engine; perspective views from the GL renderer",
           concat(
               J::array(
                   {id, sectionFormat, queryParam("quality", "integer", "JPEG/WebP quality 1..100"),
                    queryParam(
                        "space", "string",
                        "geojson: world (default with a CRS: WGS 84 lon/lat, RFC 7946), projected (x, y, z in the "
                        "model's CRS, with a crs member) or plane (section u/v or chainage/elevation metres; "
                        "default without a CRS); dxf: plane (default: as drawn, hatched) or projected (3D "
                        "polylines in the model's CRS)"),
                    queryParam("layout", "string",
                               "svg: print = a section sheet (axes, scale, ends, legend, title block) as section.pdf"),
                    queryParam("decorate", "boolean", "jpg/png/webp: 1 = the section sheet as an image"),
                    queryParam("paper", "string", "sheets: A0..A5, letter, tabloid (default A3)"),
                    queryParam("orientation", "string", "sheets: landscape (default) or portrait"),
                    queryParam("scale", "number",
                               "sheets: scale denominator S of 1:S (vertical 1:S/vx); default: the smallest "
                               "round scale at which the section fits the paper"),
                    queryParam("dpi", "number", "decorated images: 50..600 (default 150)"),
                    queryParam("date", "string", "sheets: the title block's date YYYY-MM-DD (default today, UTC)")}),
               viewParams()),
           sectionResponse));
    get(paths, "/v1/models/{id}/query",
        op("what lies under one pixel of the view given by the same parameters: record and "
           "attributes, the world point, "
           "the distance along the section, and the point's coordinates (schema WorldPoint): "
           "projected (easting, northing; zone for CGCS2000 Gauss-Kruger), geodetic (lon, lat, "
           "height on the CRS's own datum) and WGS 84 with PROJ's stated accuracy. "
           "A pixel with no geology is a 200 answer with hit=false.",
           concat(J::array({id, queryParam("px", "integer", "pixel column, 0 = left", true),
                            queryParam("py", "integer", "pixel row, 0 = top", true)}),
                  viewParams()),
           jsonResponse("the answer", "QueryAnswer")));
    post(paths, "/v1/models/{id}/query",
         J{{"summary",
            "batch pixel query: {\"view\": {<view parameters as strings>}, \"pixels\": [[px, py], ...]} "
            "(at most 5000 pixels, 8 MiB of answer)"},
           {"parameters", J::array({id})},
           {"requestBody", {{"content", {{"application/json", J::object()}}}}},
           {"responses", errors()}});
    paths["/v1/models/{id}/query"]["post"]["responses"]["200"] =
        jsonResponse("{\"results\": [answer, ...]}", "QueryBatch");
    get(paths, "/v1/models/{id}/borehole",
        op("a virtual borehole at a map point: intervals (from/to metres below the collar, elevations, record, "
           "attributes) and the faults and surfaces crossed",
           J::array({id, queryParam("x", "number", "easting, world m"), queryParam("y", "number", "northing, world m"),
                     queryParam("lon", "number", "or longitude, degrees on the model CRS's own datum"),
                     queryParam("lat", "number", "and latitude, degrees on the model CRS's own datum")}),
           jsonResponse("the borehole", "Borehole")));
}

// Reserves and the model checked against its drillholes.
void addReservesAndDrillholePaths(J& paths) {
    const J id = idParam();
    {
        const char* what =
            "reserves: gross and net (nested bodies subtracted) volume m^3, density, tonnage t, grade and metal of "
            "every closed body, whole or on the kept side of a plane, and totals; the same document as `geoslice "
            "reserves --json` (api/reserves.hpp). A plane that misses the model keeps all of it or none of it, "
            "whichever side it lies on (volumes 0, not an error).";
        const J plane = queryParam("plane", "string",
                                   "a,b,c,d: count only the kept side a*x+b*y+c*z+d >= 0 (world m); default: the "
                                   "whole model");
        get(paths, "/v1/models/{id}/reserves",
            op(what,
               J::array(
                   {id, plane, queryParam("format", "string", "json (default) or csv (the same as reserves.csv)"),
                    queryParam("cutoffs", "string",
                               "c1,c2,...: grade-tonnage tables of the block model's clipping bodies (exact cell x "
                               "body volumes; with plane, of the kept side: cell x body x half-space); JSON adds "
                               "grade_tonnage, CSV becomes the table"),
                    queryParam("property", "string",
                               "the grade property of the table (default: the first not "
                               "named density)")}),
               J{{"description", "the reserves; ETag and Cache-Control set"},
                 {"content", {{"application/json", {{"schema", ref("Reserves")}}}, {"text/csv", J::object()}}}}));
        get(paths, "/v1/models/{id}/reserves.csv",
            op(what, J::array({id, plane}),
               J{{"description",
                  "CSV with a header row: one row per body, then a '(total)' row; empty cells where JSON has null"},
                 {"content", {{"text/csv", J::object()}}}}));
    }
    {
        const char* what =
            "the model checked against its drillholes (the <id>.drillholes.json sidecar beside the model): per hole "
            "and per unit the logged and agreeing length and their share; each logged contact's distance to the "
            "nearest model contact between the same units along the hole (model depth - logged depth, m; null: "
            "none); the codes and their units; warnings. The same document as `geoslice holes check --json` "
            "(api/drillhole_check.hpp). 404: the model has no drillholes; 409: its sidecar did not load.";
        const J rows = queryParam("rows", "string", "CSV only: units (default, rows per hole and unit) or contacts");
        get(paths, "/v1/models/{id}/drillholes/check",
            op(what, J::array({id, queryParam("format", "string", "json (default) or csv (as check.csv)"), rows}),
               J{{"description", "the check; ETag and Cache-Control set"},
                 {"content", {{"application/json", {{"schema", ref("DrillholeCheck")}}}, {"text/csv", J::object()}}}}));
        get(paths, "/v1/models/{id}/drillholes/check.csv",
            op(what, J::array({id, rows}),
               J{{"description",
                  "CSV with a header row: hole,unit,in_model,logged_m,agreed_m,share (hole * = all holes), or with "
                  "rows=contacts hole,depth_m,code_above,code_below,unit_above,unit_below,model_depth_m,distance_m"},
                 {"content", {{"text/csv", J::object()}}}}));
        get(paths, "/v1/models/{id}/drillholes",
            op("every drillhole for a map or a picker: id, collar, end depth, the collar's azimuth and dip (degrees, "
               "negative down), the desurveyed trace at its nodes (model CRS metres), and the interval columns "
               "sections can colour holes by (holecolour=). 404: the model has no drillholes; 409: its sidecar did "
               "not load.",
               J::array({id}), jsonResponse("the holes; ETag and Cache-Control set", "Drillholes")));
        get(paths, "/v1/models/{id}/drillholes/{hole}/log",
            op("one drillhole's strip log: collar, survey stations, desurveyed path, every interval table's "
               "intervals with their columns (code intervals with the unit they name), and the model's units along "
               "the same hole. 404 names an unknown hole.",
               J::array({id, pathParam("hole", "hole id, percent-encoded (%2F for /), at most 256 bytes")}),
               jsonResponse("the log", "DrillholeLog")));
    }
}

// Saved sections: the model's exploration lines and sections saved through the API; the
// plan's context layer.
void addSavedSectionPaths(J& paths) {
    const J id = idParam();
    get(paths, "/v1/models/{id}/context.geojson",
        op("the plan's context layer (leases, workings, faults drawn by hand): the <id>.context.geojson sidecar "
           "beside the model, its coordinates converted to the model's CRS (`geoslice` says how they were read). "
           "404: the model has none; 409: its sidecar did not load.",
           J::array({id}),
           J{{"description", "GeoJSON FeatureCollection in the model's CRS; ETag and Cache-Control set"},
             {"content", {{"application/geo+json", {{"schema", ref("ContextLayer")}}}}}}));
    const J sid = pathParam("sid", "saved section id: 16 hex digits");
    get(paths, "/v1/models/{id}/saved-sections",
        op("the model's own sections (its <id>.sections.json exploration lines) then those saved through the API, "
           "oldest first; `query` of each is the view parameters that draw it (section.{format}, query, POST "
           "/sections); `saving`: whether this server saves (serve --sections-dir). Never cached.",
           J::array({id}), jsonResponse("the saved sections", "SavedSections")));
    paths["/v1/models/{id}/saved-sections"]["post"] =
        J{{"summary",
           "save a section by name: {\"name\": \"Line 12\", \"number\": \"12\", \"vertices\": [[x, y], ...] | "
           "\"line\": \"x1,y1,...\" | \"plane\": \"a,b,c,d\" | \"elevation\": z, \"vx\": k}, checked as a section "
           "request is and against the model. Its id is a hash of model, definition, number and name: the same "
           "section saved again (on any replica) is the same id, answered 200 as first stored. 501: the server "
           "keeps no saved sections (no --sections-dir); 409: the model has 2,000 saved sections; 507: the disk is "
           "full."},
          {"parameters", J::array({id})},
          {"requestBody", {{"content", {{"application/json", J::object()}}}}},
          {"responses", J{{"201", jsonResponse("saved (Location: the section's URL)", "SavedSection")},
                          {"200", jsonResponse("saved before under the same id", "SavedSection")},
                          {"400", problem("a bad field (named) or a section that misses the model")},
                          {"404", problem("no such model")},
                          {"409", problem("the model has the most saved sections kept")},
                          {"501", problem("this server keeps no saved sections (serve --sections-dir)")},
                          {"507", problem("the disk holding the saved sections is full")}}}};
    get(paths, "/v1/models/{id}/saved-sections/{sid}",
        op("one saved section (the model's own, or one saved through the API); 404 for an unknown id",
           J::array({id, sid}), jsonResponse("the saved section", "SavedSection")));
    paths["/v1/models/{id}/saved-sections/{sid}"]["delete"] =
        J{{"summary", "delete a section saved through the API; 409 for one of the model's own (edit its sidecar)"},
          {"parameters", J::array({id, sid})},
          {"responses", J{{"204", J{{"description", "deleted"}}},
                          {"404", problem("no such model or saved section")},
                          {"409", problem("one of the model's own sections")}}}};
}

// Stateless sections, their tiles and the tiles' standard descriptions.
void addSectionPaths(J& paths) {
    const J id = idParam(), sid = sidParam(), format = tileFormatParam();
    post(paths, "/v1/models/{id}/sections",
         J{{"summary",
            "define a section for tiles: {\"plane\": \"a,b,c,d\" | \"elevation\": z, \"vx\": k, \"bg\": c}. "
            "Returns a stateless section id (the canonical definition, base64url) that any replica can "
            "serve, the tile URL template and the tile grid."},
           {"parameters", J::array({id})},
           {"requestBody", {{"content", {{"application/json", J::object()}}}}},
           {"responses", errors()}});
    paths["/v1/models/{id}/sections"]["post"]["responses"]["201"] =
        jsonResponse("{sid, tiles, grid}", "SectionDefinition");
    get(paths, "/v1/sections/{sid}",
        op("a section's definition and tile grid", J::array({sid}), jsonResponse("grid", "SectionDefinition")));
    get(paths, "/v1/sections/{sid}/tiles/{z}/{x}/{y}.{format}",
        op("one 256x256 tile. Grid: zoom 0 is one tile covering size0 metres along u (size0/k along v) from the "
           "section extent's top-left corner (u0, v1); zoom z has 2^z x 2^z tiles; tile (z,x,y) covers "
           "u in [u0+x*s, u0+(x+1)*s], v in [v1-(y+1)*s/k, v1-y*s/k], s = size0/2^z, k = the grid's "
           "exaggeration (vx on a vertical plane, 1 on a horizontal one, sqrt(nz^2 + vx^2 (1 - nz^2)) for a unit "
           "normal n). In Leaflet use L.CRS.Simple with lng = (u-u0)*256/size0 and lat = (v-v1)*k*256/size0.",
           J::array({sid, pathParam("z", "zoom", J{{"type", "integer"}}),
                     pathParam("x", "column", J{{"type", "integer"}}),
                     pathParam("y", "row (0 = top)", J{{"type", "integer"}}), format}),
           imageResponse()));
    get(paths, "/v1/sections/{sid}/tilejson.json",
        op("the section's tiles as a TileJSON 3.0.0 layer (tiles, minzoom, maxzoom, scheme xyz; the grid under "
           "'geoslice'; no bounds: the tiles are in the section's plane, not on the globe)",
           J::array({sid}), jsonResponse("TileJSON", "TileJson")));
    get(paths, "/v1/sections/{sid}/tiles",
        op("OGC API - Tiles tileset metadata of the section (dataType map, item link template "
           "{tileMatrix}/{tileCol}/{tileRow}, tiling-scheme link)",
           J::array({sid}), jsonResponse("tileset", "OgcTileset")));
    get(paths, "/v1/sections/{sid}/tilematrixset",
        op("the section's OGC two-dimensional TileMatrixSet: a local engineering CRS (u, v times the grid's "
           "exaggeration, metres), matrix z of 2^z x 2^z tiles of 256 cells",
           J::array({sid}), jsonResponse("TileMatrixSet", "TileMatrixSet")));
}

// What every operation has besides its own success answer: an operationId, the statuses the
// server may send, a schema for every content, and the API keys it takes.
void completeOperations(J& paths) {
    // Operation ids for generated clients, and what every operation may answer besides 200.
    static const std::map<std::string, std::string> kOperationIds = {
        {"get /", "getWebClient"},
        {"get /web/{asset}", "getWebAsset"},
        {"get /healthz", "getHealth"},
        {"get /readyz", "getReadiness"},
        {"get /metrics", "getMetrics"},
        {"get /openapi.json", "getOpenApi"},
        {"get /v1/models", "listModels"},
        {"get /v1/models/{id}", "getModel"},
        {"get /v1/models/{id}/legend.png", "getLegendImage"},
        {"get /v1/models/{id}/context.geojson", "getContextLayer"},
        {"get /v1/models/{id}/section.{format}", "getSection"},
        {"get /v1/models/{id}/query", "queryPixel"},
        {"post /v1/models/{id}/query", "queryPixels"},
        {"get /v1/models/{id}/borehole", "getVirtualBorehole"},
        {"get /v1/models/{id}/reserves", "getReserves"},
        {"get /v1/models/{id}/reserves.csv", "getReservesCsv"},
        {"get /v1/models/{id}/drillholes", "listDrillholes"},
        {"get /v1/models/{id}/saved-sections", "listSavedSections"},
        {"post /v1/models/{id}/saved-sections", "saveSection"},
        {"get /v1/models/{id}/saved-sections/{sid}", "getSavedSection"},
        {"delete /v1/models/{id}/saved-sections/{sid}", "deleteSavedSection"},
        {"get /v1/models/{id}/drillholes/check", "checkDrillholes"},
        {"get /v1/models/{id}/drillholes/check.csv", "checkDrillholesCsv"},
        {"get /v1/models/{id}/drillholes/{hole}/log", "getDrillholeLog"},
        {"post /v1/models/{id}/sections", "defineSection"},
        {"get /v1/sections/{sid}", "getSectionDefinition"},
        {"get /v1/sections/{sid}/tiles/{z}/{x}/{y}.{format}", "getSectionTile"},
        {"get /v1/sections/{sid}/tilejson.json", "getSectionTileJson"},
        {"get /v1/sections/{sid}/tiles", "getSectionTileset"},
        {"get /v1/sections/{sid}/tilematrixset", "getSectionTileMatrixSet"},
        {"get /v1/models/{id}/3dtiles/tileset.json", "getModelTileset3d"},
        {"get /v1/models/{id}/3dtiles/tiles/{n}.glb", "getModelTile3d"},
    };
    for (auto& [path, ops] : paths.items())
        for (auto& [method, operation] : ops.items()) {
            const auto named = kOperationIds.find(method + " " + path);
            if (named != kOperationIds.end()) operation["operationId"] = named->second;
            if (path.rfind("/v1/models/{id}", 0) == 0 || path.rfind("/v1/sections/{sid}", 0) == 0) {
                if (!operation.contains("parameters")) operation["parameters"] = J::array();
                operation["parameters"].push_back(queryParam(
                    "version", "string",
                    "the model's content version (`version` of GET /v1/models/{id}): the answer never changes and "
                    "is cacheable for a year (immutable); another version than the one served is a 404 "
                    "(model_version); without it answers are cacheable for 60 s"));
            }
            J& r = operation["responses"];
            r["500"] = problem("a bug: the detail says what failed (logged)");
            if (method == "get") {
                r["304"] = J{{"description", "If-None-Match names the current ETag (weak comparison)"}};
                r["405"] = problem("a known path with another method; Allow lists the methods");
            } else if (method == "post") {
                r["413"] = problem("the body is larger than the server's --max-body");
                r["415"] = problem("the body is not application/json");
            }
            if (path.rfind("/v1/", 0) == 0) {
                r["422"] = problem(
                    "a valid request geoslice does not serve (tiles of a polyline section, vectors of a perspective "
                    "view, a colouring the model cannot draw, WGS 84 where PROJ has no operation)");
                r["504"] = problem("the render passed the server's deadline");
            }
        }
    paths["/v1/models/{id}/section.{format}"]["get"]["responses"]["206"] =
        J{{"description", "PDF only: the byte range asked for (Range: bytes=a-b), with Content-Range"},
          {"content", {{"application/pdf", J::object()}}}};
    paths["/v1/models/{id}/section.{format}"]["get"]["responses"]["416"] =
        problem("PDF only: the Range starts past the end of the document");
    paths["/v1/models/{id}/drillholes/check"]["get"]["responses"]["409"] =
        problem("the model's drillhole sidecar did not load");
    paths["/v1/models/{id}/drillholes/check.csv"]["get"]["responses"]["409"] =
        problem("the model's drillhole sidecar did not load");

    // Every success content has a schema: the JSON answers their own (above), text a string,
    // everything else bytes.
    for (auto& [path, ops] : paths.items())
        for (auto& [method, operation] : ops.items())
            for (auto& [status, response] : operation["responses"].items()) {
                if (status.empty() || status[0] != '2' || !response.contains("content")) continue;
                for (auto& [type, media] : response["content"].items()) {
                    if (media.contains("schema")) continue;
                    const bool text = type.rfind("text/", 0) == 0 || type == "image/svg+xml" || type == "image/vnd.dxf";
                    media["schema"] = text ? kStr : J{{"type", "string"}, {"format", "binary"}};
                }
            }

    // API keys (geoslice serve --keys, api/access_keys.hpp): every /v1 route takes one when
    // the server has keys (none: open); the web client, health, metrics and this document
    // never need one.
    for (auto& [path, ops] : paths.items())
        for (auto& [method, operation] : ops.items()) {
            if (path.rfind("/v1/", 0) != 0) {
                operation["security"] = J::array();
                continue;
            }
            operation["security"] = J::array({J{{"bearer", J::array()}}, J{{"apiKey", J::array()}}, J::object()});
            operation["responses"]["401"] = problem(
                "the server has API keys and the request sent none, or one it does not know "
                "(WWW-Authenticate: Bearer)");
            operation["responses"]["403"] =
                problem("the API key may not read this model (whether or not the model exists)");
        }
}

}  // namespace

J openApiDocument(const std::string& serverVersion) {
    J paths = J::object();
    addOpsPaths(paths);
    addModelPaths(paths);
    addReservesAndDrillholePaths(paths);
    addSavedSectionPaths(paths);
    addSectionPaths(paths);
    completeOperations(paths);
    J doc;
    doc["openapi"] = "3.0.3";
    // Relative: the API is served from wherever this document was fetched.
    doc["servers"] = J::array({J{{"url", "/"}, {"description", "this server"}}});
    doc["info"] = {{"title", "geoslice"},
                   {"version", serverVersion},
                   {"license", {{"name", "MIT"}, {"url", "https://opensource.org/license/mit"}}},
                   {"description",
                    "Sections of 3D geological models: images, tiles and pixel queries with geodetic coordinates. "
                    "World coordinates: x easting, y northing, z elevation, metres, in the model's CRS."}};
    doc["paths"] = std::move(paths);
    const J num = {{"type", "number"}}, str = {{"type", "string"}};
    doc["components"]["schemas"]["WorldPoint"] = {
        {"type", "object"},
        {"description",
         "A point in every coordinate system the model's CRS leads to. Axis order is always easting, northing "
         "(projected) and lon, lat (geographic), whatever EPSG lists. CRS ids are \"EPSG:<code>\", \"local\" or, "
         "for a CRS no EPSG code matches, its WKT."},
        {"properties",
         {{"x", num},
          {"y", num},
          {"z", num},
          {"crs", str},
          {"axes", {{"type", "array"}, {"items", str}}},
          {"projected",
           {{"type", "object"},
            {"description",
             "projected CRSs: crs, name, easting, northing (metres), axisOrder; CGCS2000 Gauss-Kruger CRSs also "
             "zone, zoneWidthDeg, centralMeridianDeg"}}},
          {"geodetic",
           {{"type", "object"},
            {"description",
             "lon, lat (degrees) and height (the model's elevation) on the CRS's own datum (crs: its geographic "
             "CRS, e.g. EPSG:4490 for CGCS2000, EPSG:4267 for NAD27, EPSG:4150 for CH1903+)"}}},
          {"wgs84",
           {{"type", "object"},
            {"description",
             "lon, lat on WGS 84 (EPSG:4326) through the one PROJ operation chosen for the model's extent: "
             "operation (its name), accuracyM (PROJ's stated accuracy, metres; null with accuracyNote when PROJ "
             "states none). Absent when PROJ has no operation or only a ballpark one; then wgs84Note says why"}}},
          {"wgs84Note", str},
          {"projectedNote",
           {{"type", "string"}, {"description", "local models: no projected or geodetic coordinates"}}}}}};
    const J answers = answerSchemas();  // named: items() of a temporary would dangle
    for (const auto& [name, schema] : answers.items()) doc["components"]["schemas"][name] = schema;
    doc["components"]["securitySchemes"] = {
        {"bearer",
         {{"type", "http"},
          {"scheme", "bearer"},
          {"description", "an API key of the server's keys file as a bearer token: Authorization: Bearer KEY"}}},
        {"apiKey", {{"type", "apiKey"}, {"in", "header"}, {"name", "X-Api-Key"}}}};
    doc["components"]["schemas"]["Problem"] = {{"type", "object"},
                                               {"description", "RFC 9457 problem details"},
                                               {"properties",
                                                {{"type", {{"type", "string"}}},
                                                 {"title", {{"type", "string"}}},
                                                 {"status", {{"type", "integer"}}},
                                                 {"detail", {{"type", "string"}}},
                                                 {"instance", {{"type", "string"}}},
                                                 {"code", {{"type", "string"}}}}}};

    return doc;
}

}  // namespace geoslice::api
