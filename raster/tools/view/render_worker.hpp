// Renders the viewer's frames on a thread of their own, so that the window keeps answering while a
// frame takes seconds. One request is pending at most: a new one replaces a pending one, and a
// running render is let finish (a scene cannot be interrupted mid-draw); its result is newer than
// what is shown, so it is shown until the latest one arrives.
//
// A request may ask for the pipeline trace (raster/pipeline/include/raster/trace.hpp), which the trace views
// need; frames nobody asked to trace render untraced, at full speed. It may also ask for the
// solution (the viewer's --solution): a second scene rendered beside the frame, at the same size,
// camera and step, which the viewer compares the frame with.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

// What a frame's trace must hold; nothing asked: no trace.
struct TraceRequest {
    bool counts = false;    // overdraw and non-finite counts (kept by every trace)
    bool geometry = false;  // IA/VS/GS/setup records (TraceOptions::geometry)
    bool pixel = false;     // the fragments of pixel (x, y)
    int32_t x = 0, y = 0;

    bool any() const { return counts || geometry || pixel; }
    // A trace made for this request has everything `need` asks for.
    bool covers(const TraceRequest& need) const {
        return (any() || !need.any()) && (geometry || !need.geometry) &&
               (!need.pixel || (pixel && x == need.x && y == need.y));
    }
};

// Geometry records the viewer keeps per draw and kind (TraceOptions::maxGeometryRecords): all of
// the default particles scene's 10000 particles' 40000 GS output vertices, with room to spare.
constexpr uint32_t kViewerGeometryRecords = 1u << 17;

// The scene a worker renders as the solution: another scene, or the same one under other context
// options (the reference pipeline).
struct SolutionRender {
    std::string scene;
    ContextOptions context;
};

struct RenderRequest {
    // Only size, camera and time may change between requests of one worker. time: an animated
    // scene's clock for this frame (unset: the scene's own start); a later time advances the kept
    // scene, an earlier one rebuilds it (the frame is the same bits either way).
    SceneOptions scene;
    Context::StepLimit limit;
    std::string stepLabel;  // what the overlay says about the step position
    TraceRequest trace;
    bool solution = false;  // also render the worker's SolutionRender (if it has one)
};

struct RenderedFrame {
    uint64_t id = 0;  // 1, 2, ... in request order
    RenderRequest request;
    RenderTarget color;
    DepthTarget depth;
    std::vector<PipelineStatistics> drawLog;  // Context::drawStatisticsLog of this frame
    PipelineStatistics frameStatistics;
    uint32_t drawCount = 0;        // draws the scene issued, run or skipped
    double milliseconds = 0;       // the scene's render call
    std::string error;             // what a raster::Error said, if the render threw
    Viewport viewport;             // the context's viewport after the scene's render (for clip → screen)
    bool animated = false;         // the scene's Scene::animated()
    double sceneTime = 0;          // its clock when it rendered this frame (Scene::time())
    std::unique_ptr<Trace> trace;  // when request.trace.any()
    std::optional<PixelMarch> march;  // when request.trace.pixel in a media scene: its ray march
    // When request.solution: the solution scene at the frame's size, camera (the frame's scene's
    // own when request.scene.camera is unset) and step limit, never traced.
    std::optional<RenderTarget> solution;
    double solutionMilliseconds = 0;
    uint32_t solutionDrawCount = 0;  // draws the solution scene issued (for the next render's progress)
    std::string solutionError;       // what its render threw; the frame itself is still good
};

// The render running now, as the HUD tells it.
struct RunningRender {
    double seconds = 0;                 // since the request started rendering (its solution included)
    bool solution = false;              // rendering the solution, the frame itself done
    RenderProgress::Snapshot progress;  // of the frame, or of the solution when `solution`
};

// The HUD's line about it: "rendering... 1.3 s  draw 2 of 2, 45% of its tiles". `drawTotal` is the
// draws the scene issues (known from an earlier frame's shape; 0: unknown, and then "draw 2").
std::string progressText(const RunningRender& running, uint32_t drawTotal);

class RenderWorker {
  public:
    // `finished` is called on the worker thread after each render (e.g. to wake an event loop).
    RenderWorker(std::string sceneName, const ContextOptions& options, std::function<void()> finished,
                 std::optional<SolutionRender> solution = std::nullopt);
    ~RenderWorker();
    RenderWorker(const RenderWorker&) = delete;
    RenderWorker& operator=(const RenderWorker&) = delete;

    // Returns the request's id.
    uint64_t request(RenderRequest request);
    // The newest frame finished since the last call, or null.
    std::shared_ptr<RenderedFrame> takeFinished();
    // The render running now; none when the worker waits.
    std::optional<RunningRender> running() const;

  private:
    // A scene kept between renders, rebuilt when the size or the camera changes, or when an
    // animated scene is asked for an earlier time than its clock's (advanced for a later one).
    struct CachedScene {
        std::unique_ptr<Scene> scene;
        SceneOptions options;
        Scene& get(const std::string& name, const SceneOptions& wanted);
    };

    void loop();
    std::shared_ptr<RenderedFrame> render(Context& context, uint64_t id, RenderRequest request);
    void renderSolution(Context& context, RenderedFrame& frame);

    const std::string scene_name_;
    const ContextOptions context_options_;
    const std::function<void()> finished_callback_;
    const std::optional<SolutionRender> solution_;
    // Worker thread only.
    CachedScene scene_, solution_scene_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    uint64_t next_id_ = 1;
    uint64_t pending_id_ = 0;  // 0: nothing pending
    RenderRequest pending_;
    std::shared_ptr<RenderedFrame> finished_;
    bool running_ = false;
    bool running_solution_ = false;
    std::chrono::steady_clock::time_point running_since_;
    // The worker thread's Contexts report into it; reset before the frame and before its solution.
    RenderProgress progress_;
    std::thread thread_;  // last: starts once everything above is constructed
};

}  // namespace raster::tools
