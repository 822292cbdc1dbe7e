// A model's ray queries (the point classifier and the borehole tracer over one shared
// RayScene), built on a background thread so that a server answers sections, tiles and
// profile queries while Embree builds (issue 13 item 4: the build was 2.9 of the 3.3 CPU
// seconds of a baked L4's start). A query that needs rays waits for the build until its own
// deadline (or its cancellation) and then gets exactly the answer it would have got later:
// the scene does not depend on when it was built.
//
// Life cycle: create() (nothing runs) -> start() (one thread builds) -> Ready or Failed;
// destroying the object cancels a build under way (Embree's progress monitor, polled by its
// build threads) and joins the thread, so a server that stops during a build exits cleanly.
// The model must outlive this object and must not change while it lives.
//
// Thread-safety: start() once, from one thread; wait(), state(), describe() from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "model/model.hpp"
#include "model/result.hpp"
#include "section/rays/borehole.hpp"
#include "section/rays/classify.hpp"
#include "section/rays/ray_scene.hpp"

namespace geoslice {

class RayQueries {
public:
    using Clock = std::chrono::steady_clock;
    enum class State { NotStarted, Building, Ready, Failed };
    struct Engines {
        const Classifier* classifier = nullptr;
        const BoreholeTracer* tracer = nullptr;
    };

    static std::unique_ptr<RayQueries> create(const Model& model, RaySceneOptions options = {});
    ~RayQueries();
    RayQueries(const RayQueries&) = delete;
    RayQueries& operator=(const RayQueries&) = delete;

    // Starts the build on a thread of its own (a second call does nothing).
    void start();

    // The engines once built. Waits while the build is under way (or not yet started) until
    // `deadline` passes or `*cancel` turns true (polled every 10 ms): then DeadlineExceeded
    // saying the model's ray scene is still being built. A failed build: its error (Internal).
    Result<Engines> wait(Clock::time_point deadline = Clock::time_point::max(),
                         const std::atomic<bool>* cancel = nullptr) const;

    State state() const;
    static const char* stateName(State s);
    // Seconds the build took (Ready or Failed), or has taken so far (Building); 0 before it started.
    double buildSeconds() const;
    // The build's error message (Failed), else empty.
    std::string error() const;

private:
    RayQueries() = default;
    void run();

    const Model* model_ = nullptr;
    RaySceneOptions options_;
    std::atomic<bool> cancel_{false};
    mutable std::mutex mutex_;
    mutable std::condition_variable done_;
    State state_ = State::NotStarted;  // guarded by mutex_
    Clock::time_point started_{}, finished_{};
    std::string error_;
    std::unique_ptr<Classifier> classifier_;
    std::unique_ptr<BoreholeTracer> tracer_;
    std::thread thread_;
};

}  // namespace geoslice
