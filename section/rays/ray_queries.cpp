#include "section/rays/ray_queries.hpp"

#include <algorithm>

namespace geoslice {

std::unique_ptr<RayQueries> RayQueries::create(const Model& model, RaySceneOptions options) {
    std::unique_ptr<RayQueries> q(new RayQueries());
    q->model_ = &model;
    q->options_ = options;
    q->options_.cancel = &q->cancel_;
    return q;
}

RayQueries::~RayQueries() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

void RayQueries::start() {
    {
        std::lock_guard lock(mutex_);
        if (state_ != State::NotStarted) return;
        state_ = State::Building;
        started_ = Clock::now();
    }
    thread_ = std::thread([this] { run(); });
}

void RayQueries::run() {
    std::string error;
    std::unique_ptr<Classifier> classifier;
    std::unique_ptr<BoreholeTracer> tracer;
    auto scene = RayScene::build(*model_, options_);
    if (!scene) {
        error = scene.error().message;
    } else {
        auto c = Classifier::build(*model_, scene.value());
        auto t = BoreholeTracer::build(*model_, std::move(scene.value()));
        if (!c)
            error = c.error().message;
        else if (!t)
            error = t.error().message;
        else {
            classifier = std::move(c.value());
            tracer = std::move(t.value());
        }
    }
    {
        std::lock_guard lock(mutex_);
        finished_ = Clock::now();
        error_ = std::move(error);
        classifier_ = std::move(classifier);
        tracer_ = std::move(tracer);
        state_ = error_.empty() ? State::Ready : State::Failed;
    }
    done_.notify_all();
}

Result<RayQueries::Engines> RayQueries::wait(Clock::time_point deadline, const std::atomic<bool>* cancel) const {
    std::unique_lock lock(mutex_);
    while (state_ == State::NotStarted || state_ == State::Building) {
        const Clock::time_point now = Clock::now();
        if (now >= deadline || (cancel && cancel->load())) {
            const double s = state_ == State::Building ? std::chrono::duration<double>(now - started_).count() : 0.0;
            return makeError(ErrorCode::DeadlineExceeded,
                             state_ == State::Building
                                 ? "the model's ray scene (classify, boreholes, perspective queries) is still being "
                                   "built (for " +
                                       std::to_string(int(s * 1000.0)) + " ms); retry shortly"
                                 : "the model's ray scene (classify, boreholes, perspective queries) has not started "
                                   "building yet; retry shortly");
        }
        done_.wait_until(lock, std::min(deadline, now + std::chrono::milliseconds(10)));
    }
    if (state_ == State::Failed)
        return makeError(ErrorCode::Internal, "the model's ray scene could not be built: " + error_);
    return Engines{classifier_.get(), tracer_.get()};
}

RayQueries::State RayQueries::state() const {
    std::lock_guard lock(mutex_);
    return state_;
}

const char* RayQueries::stateName(State s) {
    switch (s) {
        case State::NotStarted:
            return "pending";
        case State::Building:
            return "building";
        case State::Ready:
            return "ready";
        case State::Failed:
            return "failed";
    }
    return "unknown";
}

double RayQueries::buildSeconds() const {
    std::lock_guard lock(mutex_);
    switch (state_) {
        case State::NotStarted:
            return 0.0;
        case State::Building:
            return std::chrono::duration<double>(Clock::now() - started_).count();
        default:
            return std::chrono::duration<double>(finished_ - started_).count();
    }
}

std::string RayQueries::error() const {
    std::lock_guard lock(mutex_);
    return error_;
}

}  // namespace geoslice
