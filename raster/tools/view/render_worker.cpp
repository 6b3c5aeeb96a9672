#include "render_worker.hpp"

#include <algorithm>
#include <cstdio>

namespace raster::tools {
namespace {

bool sameScene(const SceneOptions& a, const SceneOptions& b) {
    const auto same_camera = [](const std::optional<SceneCamera>& x, const std::optional<SceneCamera>& y) {
        return x.has_value() == y.has_value() && (!x || (x->eye == y->eye && x->target == y->target));
    };
    return a.width == b.width && a.height == b.height && same_camera(a.camera, b.camera);
}

}  // namespace

std::string progressText(const RunningRender& running, uint32_t drawTotal) {
    const RenderProgress::Snapshot& p = running.progress;
    char text[128];
    int n = std::snprintf(text, sizeof text, "rendering%s... %.1f s", running.solution ? " solution" : "",
                          std::max(running.seconds, 0.0));
    if (p.drawsStarted > 0) {
        // A total below the draws seen is stale (another scene's): better none than a wrong one.
        if (drawTotal >= p.drawsStarted)
            n += std::snprintf(text + n, sizeof text - n, "  draw %u of %u", p.drawsStarted, drawTotal);
        else
            n += std::snprintf(text + n, sizeof text - n, "  draw %u", p.drawsStarted);
        if (!p.drawRunning())
            std::snprintf(text + n, sizeof text - n, " done");
        else if (p.tilesInDraw == 0)  // its vertex and geometry stages, before any tile
            std::snprintf(text + n, sizeof text - n, ", geometry");
        else  // rounded down: 100% only once every tile is done
            std::snprintf(text + n, sizeof text - n, ", %u%% of its tiles",
                          unsigned(uint64_t(p.tilesFinished) * 100 / p.tilesInDraw));
    }
    return text;
}

Scene& RenderWorker::CachedScene::get(const std::string& name, const SceneOptions& wanted) {
    // Clocks within this of each other are the same frame: well under a step (1/60 s), above the
    // rounding of a sum of steps.
    constexpr double kSameTime = 1e-9;
    const bool earlier =
        scene && scene->animated() && wanted.time && *wanted.time < scene->time() - kSameTime;
    if (!scene || !sameScene(options, wanted) || earlier) {
        scene.reset();  // first: a big scene's buffers are not held twice
        scene = makeScene(name, wanted);
        options = wanted;
    } else if (scene->animated() && wanted.time && *wanted.time > scene->time() + kSameTime) {
        scene->advance(*wanted.time - scene->time());
    }
    return *scene;
}

RenderWorker::RenderWorker(std::string sceneName, const ContextOptions& options,
                           std::function<void()> finished, std::optional<SolutionRender> solution)
    : scene_name_(std::move(sceneName)),
      context_options_(options),
      finished_callback_(std::move(finished)),
      solution_(std::move(solution)),
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

std::optional<RunningRender> RenderWorker::running() const {
    std::lock_guard lock(mutex_);
    if (!running_) return std::nullopt;
    RunningRender r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - running_since_).count();
    r.solution = running_solution_;
    r.progress = progress_.snapshot();  // under the lock: of the render running_solution_ names
    return r;
}

void RenderWorker::loop() {
    // The Contexts (and their thread pools) live and die on this thread. A solution under other
    // options (the reference pipeline) gets its own, once asked for; another scene shares this one.
    Context context(context_options_);
    context.setProgress(&progress_);
    std::unique_ptr<Context> solution_context;
    const bool own_solution_context =
        solution_ && (solution_->context.reference != context_options_.reference ||
                      solution_->context.plain != context_options_.plain ||
                      solution_->context.threads != context_options_.threads);
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
            running_solution_ = false;
            running_since_ = std::chrono::steady_clock::now();
            progress_.reset();
        }
        std::shared_ptr<RenderedFrame> frame = render(context, id, std::move(request));
        if (frame->request.solution && solution_ && frame->error.empty()) {
            if (own_solution_context && !solution_context) {
                solution_context = std::make_unique<Context>(solution_->context);
                solution_context->setProgress(&progress_);
            }
            {
                std::lock_guard lock(mutex_);
                running_solution_ = true;
                progress_.reset();
            }
            renderSolution(own_solution_context ? *solution_context : context, *frame);
        }
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
        Scene& scene = scene_.get(scene_name_, request.scene);
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
            scene.render(context, frame->color, frame->depth);
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
        frame->animated = scene.animated();
        frame->sceneTime = scene.time();
        const TraceRequest& t = request.trace;
        if (t.pixel && t.x >= 0 && t.y >= 0 && uint32_t(t.x) < request.scene.width && uint32_t(t.y) < request.scene.height)
            frame->march = scene.pixelMarch(uint32_t(t.x), uint32_t(t.y), request.scene.width, request.scene.height);
    } catch (const std::exception& e) {  // raster::Error, or running out of memory for a huge window
        frame->error = e.what();
    }
    frame->request = std::move(request);
    return frame;
}

void RenderWorker::renderSolution(Context& context, RenderedFrame& frame) {
    try {
        SceneOptions options = frame.request.scene;
        // The frame's camera, also when it is its scene's own: another scene's own may differ.
        if (!options.camera) options.camera = defaultCamera(scene_name_);
        Scene& scene = solution_scene_.get(solution_->scene, options);
        RenderTarget color(options.width, options.height);
        DepthTarget depth(options.width, options.height);
        context.setTrace(nullptr);
        context.resetFrameStatistics();  // step limits count draws from here
        context.setStepLimit(frame.request.limit);
        const auto t0 = std::chrono::steady_clock::now();
        scene.render(context, color, depth);
        frame.solutionMilliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        frame.solution = std::move(color);
        frame.solutionDrawCount = context.drawCount();
    } catch (const std::exception& e) {
        frame.solutionError = e.what();
    }
}

}  // namespace raster::tools
