#include "viewer.hpp"

#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "camera.hpp"
#include "raster/trace_format.hpp"
#include "source_tree.hpp"

namespace raster::tools {
namespace {

constexpr int kDragThreshold = 3;  // window pixels a press may wander and still be a click

// The name actionForKey knows a key by; empty for keys the viewer ignores. `fly` (Shift or the
// right mouse button held) turns W A S D Q E into flying.
std::string keyName(const SDL_Keysym& key, bool fly) {
    const SDL_Keycode k = key.sym;
    if (k >= SDLK_a && k <= SDLK_z) {
        const std::string letter(1, char(k));
        const bool fly_key = std::string_view("wasdqe").find(letter[0]) != std::string_view::npos;
        return fly && fly_key ? "shift+" + letter : letter;
    }
    switch (k) {
        case SDLK_RIGHTBRACKET:
            return "]";
        case SDLK_LEFTBRACKET:
            return "[";
        case SDLK_0:
        case SDLK_KP_0:
            return "0";
        case SDLK_F1:
            return "f1";
        case SDLK_F12:
            return "f12";
        case SDLK_ESCAPE:
            return "esc";
        case SDLK_UP:
            return "up";
        case SDLK_DOWN:
            return "down";
        case SDLK_LEFT:
            return "left";
        case SDLK_RIGHT:
            return "right";
        case SDLK_PAGEUP:
            return "pageup";
        case SDLK_PAGEDOWN:
            return "pagedown";
        case SDLK_SPACE:
            return "space";
        case SDLK_PERIOD:
            return ".";
        case SDLK_COMMA:
            return ",";
        case SDLK_PLUS:
        case SDLK_EQUALS:  // + without Shift on most layouts
        case SDLK_KP_PLUS:
            return "+";
        case SDLK_MINUS:
        case SDLK_KP_MINUS:
            return "-";
        case SDLK_HOME:
            return "home";
        default:
            return {};
    }
}

// A handout (built without solutions/, docs/HANDOUT.md) ships each lab's solution as an image at the
// lab's defaults, labs/<lab>/reference/<lab>@solution.png: there, what K shows and J compares with
// unless told otherwise. Empty where there is none (not a lab, or solutions/ present).
std::string handoutReference(const std::string& scene) {
    const std::string path =
        std::string(sourceTree()) + "/labs/" + scene + "/reference/" + scene + "@solution.png";
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec) ? path : std::string();
}

}  // namespace

Viewer::Viewer(ViewerOptions options) : options_(std::move(options)) {
    // A bad --solution fails here, before SDL starts. A lab is compared with its solution unless
    // told otherwise.
    if (options_.solution.empty()) options_.solution = solutionSceneOf(options_.scene);
    if (options_.solution.empty()) options_.solution = handoutReference(options_.scene);
    solution_ = parseSolution(options_.solution);
    if (solution_.kind == SolutionSource::Kind::Image) solution_image_ = readImageRgba8(solution_.name);
    camera_ = options_.sceneOptions.camera.value_or(defaultCamera(options_.scene));
    camera_moved_ = options_.sceneOptions.camera.has_value();
    width_ = options_.sceneOptions.width;
    height_ = options_.sceneOptions.height;
    // The caller's SDL_VIDEODRIVER wins, so a headless run can still be pointed at a display.
    if (options_.headless) setenv("SDL_VIDEODRIVER", "offscreen", 0);
    RASTER_REQUIRE(SDL_Init(SDL_INIT_VIDEO) == 0, InvalidState,
                   std::string("SDL cannot start its video subsystem: ") + SDL_GetError() +
                       (options_.headless ? "" : " (no display? run with --headless)"));
    // Pixels stay square and sharp when the framebuffer is scaled: stepping is about single pixels.
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "nearest");
    window_ = SDL_CreateWindow(("raster view: " + options_.scene).c_str(), SDL_WINDOWPOS_UNDEFINED,
                               SDL_WINDOWPOS_UNDEFINED, int(width_), int(height_), SDL_WINDOW_RESIZABLE);
    if (window_) renderer_ = SDL_CreateRenderer(window_, -1, 0);
    // Without a GPU driver (Xvfb, offscreen) SDL's software renderer always works.
    if (window_ && !renderer_) renderer_ = SDL_CreateRenderer(window_, -1, SDL_RENDERER_SOFTWARE);
    if (!renderer_) {
        const std::string why = SDL_GetError();
        if (window_) SDL_DestroyWindow(window_);
        SDL_Quit();
        throw Error(ErrorCode::InvalidState, "SDL cannot open a " + std::to_string(width_) + "x" +
                                                 std::to_string(height_) + " window: " + why);
    }
    SDL_RendererInfo info{};
    SDL_GetRendererInfo(renderer_, &info);
    say("raster view: " + options_.scene + ", video driver " + SDL_GetCurrentVideoDriver() + ", renderer " +
        info.name);
    wake_event_ = SDL_RegisterEvents(1);
    const uint32_t wake = wake_event_;
    std::optional<SolutionRender> solution;
    if (solution_.kind == SolutionSource::Kind::Reference)
        solution = SolutionRender{options_.scene, {options_.context.threads, true}};
    if (solution_.kind == SolutionSource::Kind::Scene)
        solution = SolutionRender{solution_.name, options_.context};
    worker_ = std::make_unique<RenderWorker>(
        options_.scene, options_.context,
        [wake] {
            SDL_Event e{};
            e.type = wake;
            SDL_PushEvent(&e);  // thread-safe: wakes the event loop when a frame is ready
        },
        std::move(solution));
}

Viewer::~Viewer() {
    worker_.reset();
    if (texture_) SDL_DestroyTexture(texture_);
    SDL_DestroyRenderer(renderer_);
    SDL_DestroyWindow(window_);
    SDL_Quit();
}

void Viewer::say(const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
    messages_.push_back(line);
}

void Viewer::run() {
    queue_.assign(options_.script.begin(), options_.script.end());
    requestRender();
    while (!quit_) {
        SDL_Event event;
        // Short waits while script actions are due; while a render runs, a tenth of a second, for
        // the HUD's clock and progress (each redraw takes CPU from the render); long ones when idle.
        const int timeout = !queue_.empty() ? 15 : !upToDate() ? 100 : 200;
        if (SDL_WaitEventTimeout(&event, timeout)) {
            handleEvent(event);
            while (SDL_PollEvent(&event)) handleEvent(event);
        }
        if (std::shared_ptr<RenderedFrame> frame = worker_->takeFinished()) show(std::move(frame));
        followWindowSize();
        runQueue();
        if (options_.headless && queue_.empty()) playback_.setPlaying(false);  // the script's end ends play
        playOn();
        if (options_.headless && queue_.empty() && upToDate()) quit_ = true;
        if (dirty_ || !upToDate()) drawWindow();
    }
}

void Viewer::handleEvent(const SDL_Event& event) {
    dirty_ = true;
    const bool right_down = SDL_GetMouseState(nullptr, nullptr) & SDL_BUTTON(SDL_BUTTON_RIGHT);
    switch (event.type) {
        case SDL_QUIT:
            quit_ = true;
            break;
        case SDL_KEYDOWN: {
            const bool fly = (event.key.keysym.mod & KMOD_SHIFT) || right_down;
            const std::string name = keyName(event.key.keysym, fly);
            if (const std::optional<Action> action = findKey(name)) queue_.push_back(*action);
            break;
        }
        case SDL_MOUSEBUTTONDOWN:
            if (event.button.button == SDL_BUTTON_LEFT) {
                left_down_ = true, dragging_ = false;
                press_x_ = last_x_ = event.button.x;
                press_y_ = last_y_ = event.button.y;
            }
            break;
        case SDL_MOUSEMOTION:
            if (!left_down_) break;
            if (!dragging_ &&
                std::abs(event.motion.x - press_x_) + std::abs(event.motion.y - press_y_) > kDragThreshold)
                dragging_ = true;
            if (dragging_) {
                queue_.push_back({Verb::Orbit, event.motion.x - last_x_, event.motion.y - last_y_});
                last_x_ = event.motion.x, last_y_ = event.motion.y;
            }
            break;
        case SDL_MOUSEBUTTONUP:
            if (event.button.button == SDL_BUTTON_LEFT && left_down_) {
                if (!dragging_) queue_.push_back({Verb::Click, event.button.x, event.button.y});
                left_down_ = dragging_ = false;
            }
            break;
        case SDL_MOUSEWHEEL: {
            const int notches =
                event.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -event.wheel.y : event.wheel.y;
            if (notches != 0) queue_.push_back({Verb::Zoom, notches});
            break;
        }
        default:
            break;
    }
}

void Viewer::runQueue() {
    while (!queue_.empty() && !quit_) {
        const Action action = queue_.front();
        if (!perform(action)) return;  // later actions wait their turn, as typed
        queue_.pop_front();
        dirty_ = true;
        // A click's history comes with a traced render: what follows waits for it, so the history
        // printed is that of the frame clicked on.
        if (action.verb == Verb::Click && !upToDate()) queue_.push_front({Verb::Wait});
        // Play starts before the next key is read: it ticks at least once (a script's
        // "Space wait" sees the clock move).
        if (action.verb == Verb::TogglePlay && playback_.playing()) return;
    }
}

bool Viewer::perform(const Action& a) {
    const auto move_camera = [&](const SceneCamera& c) {
        camera_ = c;
        camera_moved_ = true;
        requestRender();
    };
    switch (a.verb) {
        case Verb::NextDraw:
        case Verb::PreviousDraw:
        case Verb::NextPrimitive:
        case Verb::PreviousPrimitive:
            if (!cursor_.hasShape()) return false;  // known once the first whole frame is rendered
            playback_.setPlaying(false);            // stepping a frame that moves on would lose it
            if (a.verb == Verb::NextDraw)
                cursor_.nextDraw();
            else if (a.verb == Verb::PreviousDraw)
                cursor_.previousDraw();
            else if (a.verb == Verb::NextPrimitive)
                cursor_.nextPrimitive();
            else
                cursor_.previousPrimitive();
            requestRender();
            return true;
        case Verb::WholeFrame:
            cursor_.showAll(), requestRender();
            return true;
        case Verb::ToggleDepth:
        case Verb::ToggleOverdraw:
        case Verb::ToggleNonFinite:
        case Verb::ToggleSolution:
        case Verb::ToggleDifference: {
            const ImageView v = a.verb == Verb::ToggleDepth       ? ImageView::Depth
                                : a.verb == Verb::ToggleOverdraw  ? ImageView::Overdraw
                                : a.verb == Verb::ToggleNonFinite ? ImageView::NonFinite
                                : a.verb == Verb::ToggleSolution  ? ImageView::Solution
                                                                  : ImageView::Difference;
            view_ = view_ == v ? ImageView::Colour : v;
            // The view still shows (the frame, with the same words in the HUD), so K is seen to work.
            if (solution_.kind == SolutionSource::Kind::None &&
                (view_ == ImageView::Solution || view_ == ImageView::Difference))
                say(kNoSolution);
            viewsChanged();
            return true;
        }
        case Verb::ToggleWireframe:
            wireframe_ = !wireframe_, viewsChanged();
            return true;
        case Verb::ToggleGsOutput:
            stage_ = stage_ == Stage::GsOutput ? Stage::Final : Stage::GsOutput, viewsChanged();
            return true;
        case Verb::NextStage:
            stage_ = stage_ == Stage::Final      ? Stage::Vertices
                     : stage_ == Stage::Vertices ? Stage::GsOutput
                     : stage_ == Stage::GsOutput ? Stage::Primitives
                                                 : Stage::Final;
            viewsChanged();
            return true;
        case Verb::ClosePixel:
            pixel_selected_ = history_pending_ = false;
            return true;
        case Verb::ToggleHelp:
            help_ = !help_, statistics_ = statistics_ && !help_;
            return true;
        case Verb::ToggleStatistics:
            statistics_ = !statistics_, help_ = help_ && !statistics_;
            return true;
        case Verb::ResetCamera:
            camera_ = defaultCamera(options_.scene), camera_moved_ = false, requestRender();
            return true;
        case Verb::Fly:
            move_camera(fly(camera_, a.x, a.y, a.z));
            return true;
        case Verb::Orbit:
            move_camera(orbit(camera_, float(a.x), float(a.y)));
            return true;
        case Verb::Zoom:
            move_camera(zoom(camera_, a.x));
            return true;
        case Verb::Resize:
            SDL_SetWindowSize(window_, a.x, a.y);
            followWindowSize();
            return true;
        case Verb::Screenshot:
            if (!upToDate() || !shown_) return false;
            saveScreenshot();
            return true;
        case Verb::Click:
            if (!upToDate() || !shown_) return false;
            playback_.setPlaying(false);  // the history is of the frame clicked on
            reportPixel(a.x, a.y);
            return true;
        case Verb::TogglePlay:
        case Verb::StepFrame:
        case Verb::RestartTime:
        case Verb::Faster:
        case Verb::Slower:
            return performTime(a);
        case Verb::Wait:
            return upToDate();
        case Verb::Quit:
            quit_ = true;
            return true;
    }
    return true;
}

void Viewer::requestRender() {
    RenderRequest request;
    request.scene = options_.sceneOptions;
    request.scene.width = width_;
    request.scene.height = height_;
    request.scene.camera = camera_moved_ ? std::optional<SceneCamera>(camera_) : std::nullopt;
    if (playback_.animated()) request.scene.time = playback_.time();
    request.limit = requested_limit_ = stepLimit();
    request.stepLabel = cursor_.label();
    request.trace = requested_trace_ = traceNeeds();
    request.solution = requested_solution_ = solutionNeeded();
    requested_id_ = worker_->request(std::move(request));
}

Context::StepLimit Viewer::stepLimit() const {
    Context::StepLimit limit = cursor_.limit();
    if (stage_ == Stage::Final) return limit;
    // A stage view runs the current draw (the whole frame's last) only up to its stage, so the
    // image under the overlay is the framebuffer before that draw's pixels. The vertex view runs
    // the geometry shader too: with one, its output is what places the input primitives.
    if (limit.draws == UINT32_MAX) {
        if (!cursor_.hasShape() || cursor_.drawCount() == 0) return limit;
        limit.draws = cursor_.drawCount();
    }
    limit.stage = stage_ == Stage::Primitives ? Context::Stage::Setup : Context::Stage::GeometryShader;
    return limit;
}

TraceRequest Viewer::traceNeeds() const {
    TraceRequest t;
    t.counts = view_ == ImageView::Overdraw || view_ == ImageView::NonFinite;
    t.geometry = wireframe_ || stage_ != Stage::Final;
    if (pixel_selected_ && uint32_t(pixel_x_) < width_ && uint32_t(pixel_y_) < height_)
        t.pixel = true, t.x = pixel_x_, t.y = pixel_y_;
    return t;
}

bool Viewer::solutionNeeded() const {
    const bool rendered =
        solution_.kind == SolutionSource::Kind::Reference || solution_.kind == SolutionSource::Kind::Scene;
    return rendered && (view_ == ImageView::Solution || view_ == ImageView::Difference);
}

void Viewer::viewsChanged() {
    const TraceRequest need = traceNeeds();
    const bool need_solution = solutionNeeded();
    // Views switched off, or on with what the shown (or the coming) frame has: no new render.
    // A stage view also changes the step limit (the current draw stops at the stage).
    const Context::StepLimit limit = stepLimit();
    const bool coming = !upToDate() && requested_trace_.covers(need) &&
                        (requested_solution_ || !need_solution) && requested_limit_ == limit;
    // (The shown frame counts only when no other render is coming to replace it.)
    const bool shown_has = upToDate() && shown_ && shown_->request.trace.covers(need) &&
                           (shown_->request.solution || !need_solution) && shown_->request.limit == limit;
    if (!coming && !shown_has)
        requestRender();
    else
        uploadImage();
}

bool Viewer::shownHasHistory() const {
    return shown_ && shown_->trace && shown_->request.trace.pixel && shown_->request.trace.x == pixel_x_ &&
           shown_->request.trace.y == pixel_y_;
}

void Viewer::printHistory() {
    history_pending_ = false;
    const std::string text = formatPixelHistory(*shown_->trace, pixel_x_, pixel_y_);
    size_t start = 0;
    while (start < text.size()) {
        const size_t end = std::min(text.find('\n', start), text.size());
        say(text.substr(start, end - start));
        start = end + 1;
    }
}

void Viewer::followWindowSize() {
    int w = 0, h = 0;
    SDL_GetWindowSize(window_, &w, &h);
    if (w <= 0 || h <= 0 || (uint32_t(w) == width_ && uint32_t(h) == height_)) return;
    width_ = uint32_t(w), height_ = uint32_t(h);
    requestRender();
}

void Viewer::show(std::shared_ptr<RenderedFrame> frame) {
    shown_id_ = frame->id;
    dirty_ = true;
    if (!frame->error.empty()) {
        render_error_ = frame->error;
        if (options_.headless)
            throw Error(ErrorCode::InvalidState, "rendering " + options_.scene + " failed: " + render_error_);
        std::fprintf(stderr, "raster view: rendering %s failed: %s\n", options_.scene.c_str(),
                     render_error_.c_str());
        return;  // the last good frame stays
    }
    render_error_.clear();
    // The frame is good; K and J say what became of its solution.
    if (!frame->solutionError.empty()) {
        const std::string what = "rendering " + solutionLabel(solution_) + " failed: " + frame->solutionError;
        if (options_.headless) throw Error(ErrorCode::InvalidState, what);
        std::fprintf(stderr, "raster view: %s\n", what.c_str());
    }
    if (frame->solution) solution_draws_ = frame->solutionDrawCount;
    const Context::StepLimit& limit = frame->request.limit;
    const bool whole = limit.draws == UINT32_MAX && limit.primitives == UINT64_MAX;
    if (whole) frame->request.stepLabel = "whole frame, " + std::to_string(frame->drawCount) + " draws";
    if (whole && !cursor_.hasShape()) {
        std::vector<uint64_t> shape;
        for (const PipelineStatistics& s : frame->drawLog) shape.push_back(s.iaPrimitives);
        // One log entry per draw, skipped and empty ones too: entry d is draw d.
        shape.resize(frame->drawCount, 0);
        cursor_.setShape(std::move(shape));
    }
    if (!playback_.known()) {  // the first frame says whether the scene moves, and from when
        playback_.setScene(frame->animated, frame->sceneTime);
        playback_.setPlaying(!options_.headless && !options_.paused);
        last_tick_ = std::chrono::steady_clock::now();
    }
    shown_ = std::move(frame);
    uploadImage();
    if (history_pending_ && pixel_selected_ && shownHasHistory()) printHistory();
}

}  // namespace raster::tools

namespace raster::tools {

bool Viewer::performTime(const Action& a) {
    if (!playback_.known()) return false;  // the first frame tells whether the scene is animated
    if (!playback_.animated()) {
        if (!said_static_)
            say(options_.scene + " is static: the time keys (Space . , + - Home) change nothing");
        said_static_ = true;
        return true;
    }
    bool moved = false;
    switch (a.verb) {
        case Verb::TogglePlay:
            playback_.setPlaying(!playback_.playing());
            last_tick_ = std::chrono::steady_clock::now();  // play resumes from now, without a jump
            break;
        case Verb::StepFrame:
            moved = playback_.step(a.x);
            break;
        case Verb::RestartTime:
            moved = playback_.restart();
            break;
        case Verb::Faster:
        case Verb::Slower:
            a.verb == Verb::Faster ? playback_.faster() : playback_.slower();
            say(playback_.label());
            break;
        default:
            break;
    }
    if (moved) requestRender();
    return true;
}

void Viewer::playOn() {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - last_tick_).count();
    // The next frame is asked for once the last one is shown: as fast as frames render.
    if (!playback_.playing() || !upToDate()) return;
    last_tick_ = now;
    if (playback_.tick(elapsed)) requestRender();
    dirty_ = true;
}

}  // namespace raster::tools
