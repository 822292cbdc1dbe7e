// The OpenAPI 3 description of the REST API. The server registers exactly the routes of
// apiRoutes(); a test fetches /openapi.json and checks both lists are the same.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace geoslice::api {

struct RouteSpec {
    std::string method;  // "GET", "POST"
    std::string path;    // OpenAPI template, e.g. "/v1/models/{id}/section.{format}"
};

const std::vector<RouteSpec>& apiRoutes();
nlohmann::ordered_json openApiDocument(const std::string& serverVersion);

}  // namespace geoslice::api
