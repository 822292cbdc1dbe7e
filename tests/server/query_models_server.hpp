// A suite's server that serves tests/data/queries/models/ (the models of the pixel-query
// cases, tests/data/queries/README.md), read only: no bake directory. Derive a suite from it.
#pragma once

#include "tests/common/query_case.hpp"
#include "tests/server/server_fixture.hpp"

namespace geoslice::server {

class QueryModelsServer : public InProcessServer {
protected:
    static void SetUpTestSuite() {
        ServerConfig c = loopbackConfig();
        c.modelsDir = test::queryCaseDir() + "/models";
        startServer(c);
    }
    static void TearDownTestSuite() { stopServer(); }
};

}  // namespace geoslice::server
