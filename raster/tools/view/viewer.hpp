// The SDL2 window of `raster view`: shows a scene's framebuffer scaled to the window, steps through
// its draws and primitives by replaying the frame under a Context::StepLimit, orbits and flies the
// camera, and runs a script of the same keys (headless, for tests, or in a real window).
//
// The window shows the framebuffer with text drawn over it; screenshots save the framebuffer
// itself (or, in depth view, the depth image), never the text, so a screenshot is exactly what
// rendering the scene through the library gives.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "actions.hpp"
#include "render_worker.hpp"
#include "step_cursor.hpp"

struct SDL_Window;
struct SDL_Renderer;
struct SDL_Texture;
union SDL_Event;

namespace raster::tools {

struct ViewerOptions {
    std::string scene = "particles";
    SceneOptions sceneOptions;  // width × height: the window's first size; camera: where to start
    ContextOptions context;
    // SDL's offscreen video driver (unless SDL_VIDEODRIVER says otherwise); the viewer quits once
    // the script has run and the last render has finished.
    bool headless = false;
    std::vector<Action> script;
    std::string screenshotDir = ".";
    bool screenshotWindow = false;  // also save the window, text included, as <shot>-window.png
};

class Viewer {
  public:
    // Opens the window. Throws Error(InvalidArgument) for an unknown scene and Error(InvalidState)
    // if SDL cannot open a window.
    explicit Viewer(ViewerOptions options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Runs until the user quits or, headless, until the script is done. Throws Error if a render
    // fails in headless mode (in a window, the error is shown and printed instead).
    void run();

    // What is shown now (null before the first frame), for tests and the overlay.
    const RenderedFrame* shownFrame() const { return shown_.get(); }
    const StepCursor& cursor() const { return cursor_; }
    const SceneCamera& camera() const { return camera_; }
    const std::vector<std::string>& screenshots() const { return screenshots_; }
    // Every line the viewer printed to stdout (click reports, screenshot paths).
    const std::vector<std::string>& messages() const { return messages_; }

  private:
    void handleEvent(const SDL_Event& event);
    // False when the action must wait (for the frame's shape, or for the latest render).
    bool perform(const Action& action);
    void runQueue();
    void requestRender();
    void followWindowSize();
    void show(std::shared_ptr<RenderedFrame> frame);
    bool upToDate() const { return shown_id_ == requested_id_; }
    void uploadImage();
    void composeWindow();  // the frame and the text, not yet presented
    void drawWindow();
    void saveScreenshot();
    void reportPixel(int windowX, int windowY);
    void say(const std::string& line);

    ViewerOptions options_;
    SDL_Window* window_ = nullptr;
    SDL_Renderer* renderer_ = nullptr;
    SDL_Texture* texture_ = nullptr;
    uint32_t texture_width_ = 0, texture_height_ = 0;
    uint32_t wake_event_ = 0;

    std::deque<Action> queue_;
    StepCursor cursor_;
    SceneCamera camera_;
    bool camera_moved_ = false;        // until then the scene renders with its own camera, bit for bit
    uint32_t width_ = 0, height_ = 0;  // the size renders are requested at: the window's
    uint64_t requested_id_ = 0, shown_id_ = 0;
    std::shared_ptr<RenderedFrame> shown_;
    std::vector<uint8_t> image_;  // RGBA8 of what the window shows: colour, or depth as grey
    std::string render_error_;

    bool quit_ = false, dirty_ = true;
    bool depth_view_ = false, help_ = false, statistics_ = false;
    bool left_down_ = false, dragging_ = false;
    int press_x_ = 0, press_y_ = 0, last_x_ = 0, last_y_ = 0;
    int screenshot_counter_ = 0;
    std::vector<std::string> screenshots_, messages_;

    std::unique_ptr<RenderWorker> worker_;  // last: joined before the window goes
};

}  // namespace raster::tools
