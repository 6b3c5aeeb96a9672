// Renders the viewer's frames on a thread of their own, so that the window keeps answering while a
// frame takes seconds. One request is pending at most: a new one replaces a pending one, and a
// running render is let finish (a scene cannot be interrupted mid-draw); its result is newer than
// what is shown, so it is shown until the latest one arrives.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "raster/pipeline.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {

struct RenderRequest {
    SceneOptions scene;  // only size and camera may change between requests of one worker
    Context::StepLimit limit;
    std::string stepLabel;  // what the overlay says about the step position
};

struct RenderedFrame {
    uint64_t id = 0;  // 1, 2, ... in request order
    RenderRequest request;
    RenderTarget color;
    DepthTarget depth;
    std::vector<PipelineStatistics> drawLog;  // Context::drawStatisticsLog of this frame
    PipelineStatistics frameStatistics;
    uint32_t drawCount = 0;   // draws the scene issued, run or skipped
    double milliseconds = 0;  // the scene's render call
    std::string error;        // what a raster::Error said, if the render threw
};

class RenderWorker {
  public:
    // `finished` is called on the worker thread after each render (e.g. to wake an event loop).
    RenderWorker(std::string sceneName, const ContextOptions& options, std::function<void()> finished);
    ~RenderWorker();
    RenderWorker(const RenderWorker&) = delete;
    RenderWorker& operator=(const RenderWorker&) = delete;

    // Returns the request's id.
    uint64_t request(RenderRequest request);
    // The newest frame finished since the last call, or null.
    std::shared_ptr<RenderedFrame> takeFinished();
    // Seconds the current render has been running; negative when none is.
    double runningSeconds() const;

  private:
    void loop();
    std::shared_ptr<RenderedFrame> render(Context& context, uint64_t id, RenderRequest request);

    const std::string scene_name_;
    const ContextOptions context_options_;
    const std::function<void()> finished_callback_;
    // Worker thread only: the scene is rebuilt when the size or the camera changes.
    std::unique_ptr<Scene> scene_;
    SceneOptions scene_options_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    uint64_t next_id_ = 1;
    uint64_t pending_id_ = 0;  // 0: nothing pending
    RenderRequest pending_;
    std::shared_ptr<RenderedFrame> finished_;
    bool running_ = false;
    std::chrono::steady_clock::time_point running_since_;
    std::thread thread_;  // last: starts once everything above is constructed
};

}  // namespace raster::tools
