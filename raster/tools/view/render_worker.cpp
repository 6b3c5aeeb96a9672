#include "render_worker.hpp"

namespace raster::tools {
namespace {

bool sameScene(const SceneOptions& a, const SceneOptions& b) {
    const auto same_camera = [](const std::optional<SceneCamera>& x, const std::optional<SceneCamera>& y) {
        return x.has_value() == y.has_value() && (!x || (x->eye == y->eye && x->target == y->target));
    };
    return a.width == b.width && a.height == b.height && same_camera(a.camera, b.camera);
}

}  // namespace

RenderWorker::RenderWorker(std::string sceneName, const ContextOptions& options,
                           std::function<void()> finished)
    : scene_name_(std::move(sceneName)),
      context_options_(options),
      finished_callback_(std::move(finished)),
      thread_([this] { loop(); }) {}

RenderWorker::~RenderWorker() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

uint64_t RenderWorker::request(RenderRequest request) {
    uint64_t id;
    {
        std::lock_guard lock(mutex_);
        id = next_id_++;
        pending_id_ = id;
        pending_ = std::move(request);
    }
    wake_.notify_one();
    return id;
}

std::shared_ptr<RenderedFrame> RenderWorker::takeFinished() {
    std::lock_guard lock(mutex_);
    return std::move(finished_);
}

double RenderWorker::runningSeconds() const {
    std::lock_guard lock(mutex_);
    if (!running_) return -1.0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - running_since_).count();
}

void RenderWorker::loop() {
    // The Context (and its thread pool) lives and dies on this thread.
    Context context(context_options_);
    for (;;) {
        uint64_t id;
        RenderRequest request;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || pending_id_ != 0; });
            if (stop_) return;
            id = pending_id_;
            request = std::move(pending_);
            pending_id_ = 0;
            running_ = true;
            running_since_ = std::chrono::steady_clock::now();
        }
        std::shared_ptr<RenderedFrame> frame = render(context, id, std::move(request));
        {
            std::lock_guard lock(mutex_);
            running_ = false;
            if (!finished_ || finished_->id < frame->id) finished_ = std::move(frame);
        }
        if (finished_callback_) finished_callback_();
    }
}

std::shared_ptr<RenderedFrame> RenderWorker::render(Context& context, uint64_t id, RenderRequest request) {
    auto frame = std::make_shared<RenderedFrame>();
    frame->id = id;
    try {
        if (!scene_ || !sameScene(scene_options_, request.scene)) {
            scene_.reset();
            scene_ = makeScene(scene_name_, request.scene);
            scene_options_ = request.scene;
        }
        frame->color = RenderTarget(request.scene.width, request.scene.height);
        frame->depth = DepthTarget(request.scene.width, request.scene.height);
        context.resetFrameStatistics();
        context.setStepLimit(request.limit);
        if (request.trace.any()) {
            TraceOptions options;
            options.geometry = request.trace.geometry;
            options.maxGeometryRecords = request.trace.geometry ? kViewerGeometryRecords : 0;
            if (request.trace.pixel)
                options.pixels = {request.trace.x, request.trace.y, request.trace.x, request.trace.y};
            frame->trace = std::make_unique<Trace>(options);
        }
        context.setTrace(frame->trace.get());
        const auto t0 = std::chrono::steady_clock::now();
        try {
            scene_->render(context, frame->color, frame->depth);
        } catch (...) {
            context.setTrace(nullptr);
            throw;
        }
        context.setTrace(nullptr);
        frame->milliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        frame->viewport = context.viewport();
        frame->drawLog = context.drawStatisticsLog();
        frame->frameStatistics = context.frameStatistics();
        frame->drawCount = context.drawCount();
    } catch (const std::exception& e) {  // raster::Error, or running out of memory for a huge window
        frame->error = e.what();
    }
    frame->request = std::move(request);
    return frame;
}

}  // namespace raster::tools
