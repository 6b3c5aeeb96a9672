// The SDL2 window of `raster view`: shows a scene's framebuffer scaled to the window, steps through
// its draws and primitives by replaying the frame under a Context::StepLimit, orbits and flies the
// camera, and runs a script of the same keys (headless, for tests, or in a real window).
//
// The window shows the framebuffer with text drawn over it; screenshots save the framebuffer
// itself (or the image of the view shown: depth, overdraw, NaN/Inf, wireframes), never the text, so
// a screenshot of the colour view is exactly what rendering the scene through the library gives.
//
// The trace views (overdraw, NaN/Inf, the wireframes, a clicked pixel's history) render the frame
// again with the pipeline trace on, on the render worker like any frame; frames no view needs a
// trace for render untraced.
//
// With --solution, K shows the solution's image and J the difference between the frame and it
// (compare_views.hpp): the reference pipeline's render of the same scene (the fast path's error),
// another scene's (a lab's solution), or a PNG. Rendered solutions come from the render worker with
// the frame, at its size, camera and step, and only while a solution view is shown.
#pragma once

#include <chrono>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "actions.hpp"
#include "compare_views.hpp"
#include "playback.hpp"
#include "raster/image_io.hpp"
#include "render_worker.hpp"
#include "step_cursor.hpp"
#include "trace_views.hpp"

struct SDL_Window;
struct SDL_Renderer;
struct SDL_Texture;
union SDL_Event;

namespace raster::tools {

// The image the window shows (D, O, X, K, J).
enum class ImageView { Colour, Depth, Overdraw, NonFinite, Solution, Difference };
// The pipeline stage drawn over the dimmed image (V cycles, G toggles the GS output).
enum class Stage { Final, Vertices, GsOutput, Primitives };

struct ViewerOptions {
    std::string scene = "particles";
    SceneOptions sceneOptions;  // width × height: the window's first size; camera: where to start
    ContextOptions context;
    // SDL's offscreen video driver (unless SDL_VIDEODRIVER says otherwise); the viewer quits once
    // the script has run and the last render has finished.
    bool headless = false;
    std::vector<Action> script;
    std::string screenshotDir = ".";
    // An animated scene starts paused (Space plays). Headless runs always start paused, so that a
    // script's frames are those of its keys (. , Home), never of the machine's speed.
    bool paused = false;
    bool screenshotWindow = false;  // also save the window, text included, as <shot>-window.png
    // What K shows and J compares with: "reference" (this scene through the reference pipeline),
    // a scene of sceneNames(), or a .png file; empty: a lab's own solution scene (solutionSceneOf),
    // none for other scenes (parseSolution).
    std::string solution;
};

// What K and J say without a solution.
constexpr const char* kNoSolution = "no solution: start with --solution reference|<scene>|<file.png>";

class Viewer {
  public:
    // Opens the window. Throws Error(InvalidArgument) for an unknown scene or --solution,
    // Error(BadFile) for a solution PNG that cannot be read, and Error(InvalidState) if SDL cannot
    // open a window.
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
    // Every line the viewer printed to stdout (click reports, pixel histories, screenshot paths).
    const std::vector<std::string>& messages() const { return messages_; }
    ImageView imageView() const { return view_; }
    const Playback& playback() const { return playback_; }
    Stage stage() const { return stage_; }
    // What the views say about the shown image (the overdraw's maximum, ...), as the HUD shows it.
    const std::vector<std::string>& viewNotes() const { return view_notes_; }
    // The status lines (top left) as last drawn, and the rows they took: wrapped to the window.
    const std::vector<std::string>& statusLines() const { return status_lines_; }
    const std::vector<std::string>& statusRows() const { return status_rows_; }

  private:
    void handleEvent(const SDL_Event& event);
    // False when the action must wait (for the frame's shape, or for the latest render).
    bool perform(const Action& action);
    void runQueue();
    bool performTime(const Action& action);  // the time keys (Space . , Home + -)
    void playOn();                           // while playing: the clock moves, the next frame is asked for
    void requestRender();
    void followWindowSize();
    void show(std::shared_ptr<RenderedFrame> frame);
    bool upToDate() const { return shown_id_ == requested_id_; }
    void uploadImage();
    void composeWindow();  // the frame and the text, not yet presented
    void drawMarchPlot(const MarchPlot& plot, int room_x, int bottom, int scale);
    void drawWindow();
    void saveScreenshot();
    void reportPixel(int windowX, int windowY);
    // The cursor's step limit, with the stage a stage view (V, G) stops the current draw at.
    Context::StepLimit stepLimit() const;
    // What the shown views need the frame's trace to hold.
    TraceRequest traceNeeds() const;
    // After a view changed: re-render with the trace it needs, or just redraw the image.
    void viewsChanged();
    bool shownHasHistory() const;
    void printHistory();
    void composeViews();  // the trace views into image_ (uploadImage's second half)
    // What the solution views need rendered: the solution, unless there is none or it is a PNG.
    bool solutionNeeded() const;
    // K and J: the solution's image or the difference into image_, their notes (viewer_solution.cpp).
    void composeSolutionViews();
    // The solution's RGBA8 at the shown frame's size, or null with `why` saying what is missing.
    const std::vector<uint8_t>* solutionPixels(std::vector<uint8_t>& storage, std::string& why) const;
    // A click in K or J: the solution's pixel and its difference from the frame's (`frame`: RGBA8).
    void reportSolutionPixel(uint32_t x, uint32_t y, const uint8_t* frame);
    std::string viewName() const;
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
    std::vector<uint8_t> image_;  // RGBA8 of what the window shows: colour, depth as grey, a trace view
    std::vector<std::string> view_notes_;
    std::vector<std::string> status_lines_, status_rows_;
    uint32_t overdraw_max_ = 0;
    std::string render_error_;

    bool quit_ = false, dirty_ = true;
    ImageView view_ = ImageView::Colour;
    Stage stage_ = Stage::Final;
    bool wireframe_ = false, help_ = false, statistics_ = false;
    // The clicked pixel whose history is traced and shown (until C); printed once per click.
    bool pixel_selected_ = false, history_pending_ = false;
    int32_t pixel_x_ = 0, pixel_y_ = 0;
    TraceRequest requested_trace_;
    Context::StepLimit requested_limit_;
    SolutionSource solution_;
    ImageRgba8 solution_image_;  // Kind::Image: the PNG, read once
    bool requested_solution_ = false;
    uint32_t solution_draws_ = 0;  // draws of the last rendered solution (0: none yet), for its progress
    std::vector<std::string> difference_said_;  // the difference's lines printed last
    bool left_down_ = false, dragging_ = false;
    int press_x_ = 0, press_y_ = 0, last_x_ = 0, last_y_ = 0;
    int screenshot_counter_ = 0;
    std::vector<std::string> screenshots_, messages_;

    Playback playback_;
    std::chrono::steady_clock::time_point last_tick_;
    bool said_static_ = false;

    std::unique_ptr<RenderWorker> worker_;  // last: joined before the window goes
};

}  // namespace raster::tools
