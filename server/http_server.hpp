// The HTTP section server: start-up, the model loader, the GL probe and graceful shutdown.
// Routes live in server/routes/ (one family per file, registered with server/router.hpp;
// api/openapi.hpp documents them); renders go through server/render_cache.hpp to the render
// workers (workers/). HTTP/1.1 (keep-alive, pipelining, deadlines, connection cap) through
// server/http_transport.hpp (Boost.Beast); gzip for JSON when the client accepts it; errors
// as RFC 9457 problem details (server/respond.hpp).
//
// Threads: HTTP handler threads parse, look up caches and answer queries (no GL); image
// and tile renders go to the render pool, whose workers own any GL context. Models load on
// a background thread after start(); /readyz says when they are in.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "api/catalog.hpp"
#include "model/result.hpp"
#include "server/config.hpp"

namespace geoslice::server {

class SectionServer {
public:
    explicit SectionServer(ServerConfig config);
    ~SectionServer();  // stops (gracefully) if running
    SectionServer(const SectionServer&) = delete;
    SectionServer& operator=(const SectionServer&) = delete;

    // Binds host:port (port 0 = any free port), starts serving on a background thread and
    // loading models on another. Returns the bound port. Errors: the address in use...
    Result<int> start();
    // Blocks until stop() has finished.
    void wait();
    // Graceful shutdown: new requests get 503, in-flight requests finish, then the
    // listener and the workers stop. Idempotent; any thread (not a handler).
    void stop();

    // Blocks until the first pass of the model loader is done and every served model's ray
    // scene is built or failed, as /readyz waits for (tests). True when every model loaded.
    bool waitUntilLoaded();
    int port() const { return port_; }
    const ServerConfig& config() const { return config_; }
    api::Catalog& catalog();

private:
    struct Impl;
    ServerConfig config_;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
};

}  // namespace geoslice::server
