// The viewer's pictures: the image the window shows, the text over it, screenshots and pixel reports.
#include <SDL.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "overlay.hpp"
#include "raster/image_io.hpp"
#include "trace_views.hpp"
#include "viewer.hpp"

namespace raster::tools {
namespace {

constexpr uint8_t kFarthestGrey = 224;  // the farthest drawn depth; 255 is left for depth 1 (cleared)

// Depth as grey, stretched over the depths the frame drew, so that a scene 4 units away (depth
// ≈ 0.98 under a 0.1 near plane) is not all white: nearest black, farthest 224, depth 1 white.
std::vector<uint8_t> depthImage(const DepthTarget& depth) {
    const size_t n = size_t(depth.width()) * depth.height();
    const float* d = depth.data();
    float lo = 1.0f, hi = 0.0f;
    for (size_t i = 0; i < n; ++i)
        if (d[i] < 1.0f) lo = std::min(lo, d[i]), hi = std::max(hi, d[i]);
    std::vector<uint8_t> rgba(4 * n);
    for (size_t i = 0; i < n; ++i) {
        uint8_t v = 255;
        if (d[i] < 1.0f) v = hi > lo ? uint8_t(std::lround(kFarthestGrey * (d[i] - lo) / (hi - lo))) : 0;
        rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = v;
        rgba[4 * i + 3] = 255;
    }
    return rgba;
}

// An animated scene's clock, as screenshots name it: "t 3.050 s".
std::string timeText(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "t %.3f s", seconds);
    return text;
}

std::string milliseconds(double ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f ms", ms);
    return text;
}

// The panel of the I key: the last few draws of the shown frame (the one being stepped last) and
// the frame's sum, one statistic a row; rows that are 0 everywhere are left out to save room.
TextPanel statisticsPanel(const RenderedFrame& frame, size_t drawColumns) {
    const size_t kMaxDrawColumns = drawColumns;
    const size_t first = frame.drawLog.size() > kMaxDrawColumns ? frame.drawLog.size() - kMaxDrawColumns : 0;
    std::vector<std::vector<std::string>> columns;  // per column: the values' lines
    std::vector<std::string> names, header = {"statistic"};
    const auto add_column = [&](const PipelineStatistics& s, const std::string& title) {
        header.push_back(title);
        std::istringstream lines(s.toString());
        std::vector<std::string> values;
        std::string name, value;
        while (lines >> name >> value) {
            if (columns.empty()) names.push_back(name);
            values.push_back(value);
        }
        columns.push_back(std::move(values));
    };
    for (size_t d = first; d < frame.drawLog.size(); ++d)
        add_column(frame.drawLog[d], "draw " + std::to_string(d + 1));
    add_column(frame.frameStatistics, "frame");
    TextPanel panel;
    std::string line;
    for (const std::string& h : header) line += (line.empty() ? "" : "\t") + h;
    panel.lines.push_back(line);
    size_t zero_rows = 0;
    for (size_t r = 0; r < names.size(); ++r) {
        line = names[r];
        bool zero = true;
        for (const auto& column : columns) {
            line += '\t';
            line += column[r];
            zero = zero && column[r] == "0";
        }
        if (zero)
            ++zero_rows;
        else
            panel.lines.push_back(line);
    }
    if (zero_rows > 0) panel.lines.push_back(std::to_string(zero_rows) + " more are 0 everywhere");
    return panel;
}

// The key help (actions.cpp: aligned with spaces, for a terminal) as a table for the proportional
// font: key, tab, what it does. A line whose description starts elsewhere than the first line's
// stays one line of text.
std::vector<std::string> helpTable(const std::vector<std::string>& help) {
    const auto description = [](const std::string& line) {
        const size_t gap = line.find("  ");
        return gap == std::string::npos ? gap : line.find_first_not_of(' ', gap);
    };
    const size_t column = help.empty() ? std::string::npos : description(help[0]);
    std::vector<std::string> table;
    for (const std::string& line : help) {
        const size_t at = description(line);
        table.push_back(at != std::string::npos && at == column
                            ? line.substr(0, line.find("  ")) + '\t' + line.substr(at)
                            : line);
    }
    return table;
}

constexpr std::string_view kMoreHelp = ": raster view --help lists every key";

}  // namespace

void Viewer::uploadImage() {
    dirty_ = true;
    if (!shown_) return;
    const uint32_t w = shown_->color.width(), h = shown_->color.height();
    image_ = view_ == ImageView::Depth ? depthImage(shown_->depth) : shown_->color.toRgba8();
    composeViews();
    if (!texture_ || texture_width_ != w || texture_height_ != h) {
        if (texture_) SDL_DestroyTexture(texture_);
        // RGBA32 is R, G, B, A in memory order on any endianness: the render target's own layout.
        texture_ =
            SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, int(w), int(h));
        RASTER_REQUIRE(texture_ != nullptr, InvalidState,
                       "SDL cannot make a " + std::to_string(w) + "x" + std::to_string(h) +
                           " texture: " + SDL_GetError());
        texture_width_ = w, texture_height_ = h;
    }
    SDL_UpdateTexture(texture_, nullptr, image_.data(), int(4 * w));
}

std::string Viewer::viewName() const {
    std::string name = view_ == ImageView::Depth        ? "depth"
                       : view_ == ImageView::Overdraw   ? "overdraw"
                       : view_ == ImageView::NonFinite  ? "NaN/Inf"
                       : view_ == ImageView::Solution   ? "solution"
                       : view_ == ImageView::Difference ? "difference"
                                                        : "colour";
    if (stage_ == Stage::Vertices) name += " + VS output";
    if (stage_ == Stage::GsOutput) name += " + GS output";
    if (stage_ == Stage::Primitives) name += " + set-up primitives";
    if (wireframe_) name += " + primitive wireframe";
    return name;
}

void Viewer::composeViews() {
    view_notes_.clear();
    overdraw_max_ = 0;
    composeSolutionViews();
    const RenderedFrame& f = *shown_;
    const uint32_t w = f.color.width(), h = f.color.height();
    const Trace* trace = f.trace.get();
    const bool counts = trace && f.request.trace.any();
    const bool geometry = trace && f.request.trace.geometry;
    const std::string tracing = "tracing...";  // the traced frame is on its way (viewsChanged)

    if (view_ == ImageView::Overdraw || view_ == ImageView::NonFinite) {
        if (!counts) {
            view_notes_.push_back((view_ == ImageView::Overdraw ? "overdraw: " : "NaN/Inf: ") + tracing);
        } else {
            // The counts are of the last traced draw's target: the frame's own size.
            const bool sized = trace->width() == w && trace->height() == h;
            const std::vector<uint32_t> none;
            if (view_ == ImageView::Overdraw) {
                image_ = overdrawImage(sized ? trace->overdraw() : none, w, h, &overdraw_max_);
                size_t hottest = 0, at = 0;
                for (size_t i = 0; sized && i < trace->overdraw().size(); ++i)
                    if (trace->overdraw()[i] == overdraw_max_ && overdraw_max_ > 0 && hottest++ == 0) at = i;
                view_notes_.push_back(
                    "overdraw: fragments rasterised per pixel, max " + std::to_string(overdraw_max_) +
                    (hottest > 0 ? " at " + std::to_string(at % w) + "," + std::to_string(at / w) +
                                       (hottest > 1 ? " (" + std::to_string(hottest) + " pixels)" : "")
                                 : ""));
            } else {
                size_t highlighted = 0;
                image_ = nonFiniteImage(image_, sized ? trace->nonFinite() : none, &highlighted);
                view_notes_.push_back("NaN/Inf: " + std::to_string(highlighted) +
                                      " pixels with a non-finite shader output (magenta)");
            }
        }
    }

    // The draw the stage views show: the last one run (the one being stepped).
    const Context::StepLimit& limit = f.request.limit;
    const bool whole = limit.draws == UINT32_MAX;
    const uint32_t started = whole ? f.drawCount : std::min(limit.draws, f.drawCount);
    const bool has_draw = started > 0;
    const uint32_t draw = has_draw ? started - 1 : 0;
    const TraceDraw* traced = geometry && has_draw ? findTraceDraw(*trace, draw) : nullptr;
    Canvas canvas{image_, w, h};
    const std::string draw_name = "draw " + std::to_string(draw + 1);
    if (stage_ != Stage::Final) {
        dim(image_);
        const char* stage = stage_ == Stage::Vertices   ? "stage VS output"
                            : stage_ == Stage::GsOutput ? "stage GS output"
                                                        : "stage set-up primitives";
        if (!geometry) {
            view_notes_.push_back(std::string(stage) + ": " + tracing);
        } else if (!traced) {
            view_notes_.push_back(std::string(stage) + ": no draw has run");
        } else if (stage_ == Stage::Vertices) {
            const size_t n = drawVertices(canvas, *traced, f.viewport);
            view_notes_.push_back(
                std::string(stage) + " of " + draw_name + ": " +
                (traced->geometryShader.empty()
                     ? std::to_string(n) + " of " + std::to_string(traced->verticesTotal) +
                           " vertices on screen (cyan)"
                     : std::to_string(n) +
                           " primitives' GS output centres (cyan; the VS output feeds the GS)"));
        } else if (stage_ == Stage::GsOutput) {
            if (traced->geometryShader.empty()) {
                view_notes_.push_back(std::string(stage) + ": " + draw_name +
                                      " has no geometry shader (V: set-up primitives)");
            } else {
                const size_t n = drawGsOutput(canvas, *traced, f.viewport);
                view_notes_.push_back(std::string(stage) + " of " + draw_name + ": " + std::to_string(n) +
                                      " strips, " + std::to_string(traced->gsVerticesTotal) +
                                      " vertices (orange)");
            }
        } else {
            const size_t n = drawPrimitives(canvas, *traced);
            view_notes_.push_back(std::string(stage) + " of " + draw_name + ": " + std::to_string(n) +
                                  " of " + std::to_string(traced->primitivesTotal) +
                                  " (green rasterized, blue clipped, red culled, grey no pixels)");
        }
        if (traced && (traced->vertices.size() < traced->verticesTotal ||
                       traced->gsVertices.size() < traced->gsVerticesTotal ||
                       traced->primitives.size() < traced->primitivesTotal))
            view_notes_.push_back("(the trace kept the first " + std::to_string(kViewerGeometryRecords) +
                                  " records of each kind)");
    }

    if (wireframe_) {
        // The current primitive: the last the step limit lets the last started draw run.
        uint64_t run = 0;  // primitives of the draw the limit lets run
        if (!whole && has_draw && draw < f.drawLog.size())
            run = std::min(limit.primitives, f.drawLog[draw].iaPrimitives);
        const uint64_t primitive = run > 0 ? run - 1 : 0;
        if (run == 0) {
            view_notes_.push_back("wireframe: step with ] to a primitive");
        } else if (!geometry) {
            view_notes_.push_back("wireframe: " + tracing);
        } else {
            std::string fates;
            size_t shown = 0;
            if (traced) {
                shown = drawInputPrimitive(canvas, *traced, uint32_t(primitive), kCurrentPrimitiveColour);
                for (const TracePrimitive& p : traced->primitives)
                    if (p.primitive == primitive)
                        fates += std::string(fates.empty() ? "" : ", ") + toString(p.fate) +
                                 (p.clipped ? " (clipped)" : "");
            }
            view_notes_.push_back("primitive " + std::to_string(run) + " of " + draw_name +
                                  " (SV_PrimitiveID " + std::to_string(primitive) + "): " +
                                  (fates.empty() ? "not recorded" : fates) + (shown > 0 ? " (yellow)" : ""));
        }
    }
}

void Viewer::drawWindow() {
    composeWindow();
    SDL_RenderPresent(renderer_);
}

void Viewer::composeWindow() {
    dirty_ = false;
    SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 255);
    SDL_RenderClear(renderer_);
    // While a new size renders, the last frame is stretched to the window.
    if (texture_) SDL_RenderCopy(renderer_, texture_, nullptr, nullptr);

    int window_width = 0, window_height = 0;
    SDL_GetRendererOutputSize(renderer_, &window_width, &window_height);
    const int scale = overlayScale(window_width);
    const int room_x = window_width - 2 * kPanelMargin;  // the widest a panel may be, in window pixels
    TextPanel hud;
    hud.x = hud.y = kPanelMargin;
    if (shown_) {
        hud.lines.push_back(options_.scene + "  " + std::to_string(shown_->color.width()) + "x" +
                            std::to_string(shown_->color.height()) + "  frame " +
                            milliseconds(shown_->milliseconds) + (shown_->trace ? " (traced)" : "") +
                            (viewName() != "colour" ? "  [" + viewName() + "]" : "") + "   H: help");
        hud.lines.push_back(shown_->request.stepLabel);
        if (playback_.animated()) hud.lines.push_back(playback_.label() + "   Space . , + - Home");
        hud.lines.insert(hud.lines.end(), view_notes_.begin(), view_notes_.end());
    }
    // While playing, frames follow each other: their progress shows only when one takes long.
    const std::optional<RunningRender> running_now = worker_->running();
    const bool slow = !playback_.playing() || (running_now && running_now->seconds > 0.5);
    if (!upToDate() && slow) {
        // Between the request and the worker taking it up, nothing runs yet: 0 s, no draw.
        const RunningRender running = running_now.value_or(RunningRender{});
        // The frame's draws are its scene's, whatever the step (later draws are skipped, not
        // left out); the solution's are known once one has been rendered.
        const uint32_t total = running.solution ? solution_draws_ : cursor_.drawCount();
        hud.lines.push_back(progressText(running, total));
    }
    if (!render_error_.empty()) hud.lines.push_back("render failed: " + render_error_);
    status_lines_ = hud.lines;
    hud = fitPanel(std::move(hud), room_x, window_height - 2 * kPanelMargin, scale);
    status_rows_ = hud.lines;
    drawPanel(renderer_, hud, scale);
    // Help and statistics take turns below the status lines (H and I switch between them).
    const int below_hud = kPanelMargin + (hud.lines.empty() ? 0 : panelSize(hud, scale).y + kPanelMargin);
    const int room_below = window_height - below_hud - kPanelMargin;
    if (help_) {
        TextPanel help;
        help.x = kPanelMargin, help.y = below_hud;
        help.lines = helpTable(keyHelp());
        help.color = {255, 240, 160, 255};
        // Small rather than cut where the large text leaves no room for all of it.
        int help_scale = scale;
        if (help_scale > 1 && panelSize(fitPanel(help, room_x, INT_MAX, scale), scale).y > room_below)
            help_scale = 1;
        drawPanel(renderer_, fitPanel(std::move(help), room_x, room_below, help_scale, kMoreHelp),
                  help_scale);
    } else if (statistics_ && shown_) {
        TextPanel statistics = statisticsPanel(*shown_, scale == 2 ? 3 : 1);
        statistics.x = -kPanelMargin, statistics.y = below_hud;
        drawPanel(renderer_, fitPanel(std::move(statistics), room_x, room_below, scale), scale);
    }
    if (!shown_) return;
    const uint32_t w = shown_->color.width(), h = shown_->color.height();
    // The overdraw legend, bottom right: the ramp from 1 to the maximum.
    if (view_ == ImageView::Overdraw && overdraw_max_ > 0) {
        TextPanel legend;
        legend.lines = {
            "fragments per pixel", "",
            overdraw_max_ == 1 ? "1 (white)" : "1\t" + std::to_string(overdraw_max_) + " (white)"};
        const SDL_Point size = panelSize(legend, scale);
        legend.x = -kPanelMargin, legend.y = window_height - size.y - kPanelMargin;
        drawPanel(renderer_, legend, scale);
        const int left = panelLeft(renderer_, legend, scale) + kPanelPadding * scale;
        const int top = legend.y + (kPanelPadding + kPanelLineHeight + 1) * scale;
        const int bar = size.x - 2 * kPanelPadding * scale;
        for (int i = 0; i < bar; ++i) {
            const uint32_t count =
                1 + uint32_t(uint64_t(overdraw_max_ - 1) * uint64_t(i) / uint64_t(std::max(1, bar - 1)));
            const Rgb c = heatColour(count, overdraw_max_);
            SDL_SetRenderDrawColor(renderer_, c[0], c[1], c[2], 255);
            const SDL_Rect r{left + i, top, 1, (kPanelLineHeight - 3) * scale};
            SDL_RenderFillRect(renderer_, &r);
        }
    }
    if (!pixel_selected_ || uint32_t(pixel_x_) >= w || uint32_t(pixel_y_) >= h) return;
    // The clicked pixel, outlined (at least 7 window pixels across however small it is scaled)...
    const double sx = double(window_width) / w, sy = double(window_height) / h;
    const int cx = int((pixel_x_ + 0.5) * sx), cy = int((pixel_y_ + 0.5) * sy);
    const int rx = std::max(3, int(sx / 2) + 1), ry = std::max(3, int(sy / 2) + 1);
    const SDL_Rect outer{cx - rx - 1, cy - ry - 1, 2 * rx + 3, 2 * ry + 3},
        inner{cx - rx, cy - ry, 2 * rx + 1, 2 * ry + 1};
    SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 255);
    SDL_RenderDrawRect(renderer_, &outer);
    SDL_SetRenderDrawColor(renderer_, 255, 255, 0, 255);
    SDL_RenderDrawRect(renderer_, &inner);
    // ... and its history, bottom left.
    TextPanel history;
    if (shownHasHistory())
        history.lines = compactPixelHistory(*shown_->trace, pixel_x_, pixel_y_, scale == 2 ? 12 : 8);
    else
        history.lines = {"pixel (" + std::to_string(pixel_x_) + ", " + std::to_string(pixel_y_) +
                         "): tracing..."};
    history.color = {200, 255, 220, 255};
    history = fitPanel(std::move(history), room_x, window_height - 2 * kPanelMargin, scale);
    history.x = kPanelMargin, history.y = window_height - panelSize(history, scale).y - kPanelMargin;
    drawPanel(renderer_, history, scale);
    if (shownHasHistory() && shown_->march) drawMarchPlot(marchPlot(*shown_->march), room_x, history.y, scale);
}

// A media pixel's march above the history panel: L (green) and T (white) against s, T on [0, 1] and L
// on [0, lMax], the caption above.
void Viewer::drawMarchPlot(const MarchPlot& plot, int room_x, int bottom, int scale) {
    const int w = std::min(room_x, 360 * scale), h = 110 * scale;
    const int left = kPanelMargin, top = bottom - h - kPanelMargin;
    if (w < 40 || top < kPanelMargin) return;
    SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 200);
    const SDL_Rect box{left, top, w, h};
    SDL_RenderFillRect(renderer_, &box);
    const float span = std::max(plot.sMax - plot.sMin, 1e-6f);
    auto toWindow = [&](const std::vector<glm::vec2>& points, float scale_y) {
        std::vector<SDL_Point> out;
        for (const glm::vec2& p : points)
            out.push_back({left + int((p.x - plot.sMin) / span * float(w - 1)), top + h - 1 - int(p.y / scale_y * float(h - 1))});
        return out;
    };
    const std::vector<SDL_Point> t = toWindow(plot.transmittance, 1.0f), l = toWindow(plot.radiance, plot.lMax);
    SDL_SetRenderDrawColor(renderer_, 255, 255, 255, 255);
    SDL_RenderDrawLines(renderer_, t.data(), int(t.size()));
    SDL_SetRenderDrawColor(renderer_, 80, 255, 120, 255);
    SDL_RenderDrawLines(renderer_, l.data(), int(l.size()));
    TextPanel caption;
    caption.lines = {plot.caption};
    caption.color = {200, 255, 220, 255};
    caption = fitPanel(std::move(caption), room_x, top, scale);
    caption.x = left, caption.y = top - panelSize(caption, scale).y;
    if (caption.y >= 0) drawPanel(renderer_, caption, scale);
}

void Viewer::saveScreenshot() {
    std::error_code ec;
    std::filesystem::create_directories(options_.screenshotDir, ec);
    RASTER_REQUIRE(!ec, BadFile,
                   "cannot create screenshot directory '" + options_.screenshotDir + "': " + ec.message());
    // Numbered on from the last one, skipping names already taken: earlier runs' shots are kept.
    std::string path;
    do {
        char name[64];
        std::snprintf(name, sizeof name, "-%04d.png", ++screenshot_counter_);
        path = (std::filesystem::path(options_.screenshotDir) / (options_.scene + name)).string();
    } while (std::filesystem::exists(path));
    writePngRgba8(path, shown_->color.width(), shown_->color.height(), image_);
    screenshots_.push_back(path);
    say("screenshot " + path + " (" + std::to_string(shown_->color.width()) + "x" +
        std::to_string(shown_->color.height()) + ", " + viewName() + ", " + shown_->request.stepLabel +
        (shown_->animated ? ", " + timeText(shown_->sceneTime) : "") + ")");
    if (!options_.screenshotWindow) return;
    // The window as the user sees it, text included: composed, read back, then presented.
    composeWindow();
    int w = 0, h = 0;
    SDL_GetRendererOutputSize(renderer_, &w, &h);
    std::vector<uint8_t> window(size_t(4) * w * h);
    const bool read =
        SDL_RenderReadPixels(renderer_, nullptr, SDL_PIXELFORMAT_RGBA32, window.data(), 4 * w) == 0;
    SDL_RenderPresent(renderer_);
    RASTER_REQUIRE(read, InvalidState, std::string("SDL cannot read the window back: ") + SDL_GetError());
    for (size_t i = 3; i < window.size(); i += 4) window[i] = 255;  // a window has no transparency
    const std::string window_path = path.substr(0, path.size() - 4) + "-window.png";
    writePngRgba8(window_path, uint32_t(w), uint32_t(h), window);
    say("window " + window_path);
}

void Viewer::reportPixel(int windowX, int windowY) {
    int window_width = 0, window_height = 0;
    SDL_GetWindowSize(window_, &window_width, &window_height);
    const uint32_t w = shown_->color.width(), h = shown_->color.height();
    // The framebuffer fills the window: scale window pixels to framebuffer pixels.
    const int64_t x = window_width > 0 ? int64_t(windowX) * w / window_width : windowX;
    const int64_t y = window_height > 0 ? int64_t(windowY) * h / window_height : windowY;
    if (x < 0 || y < 0 || x >= int64_t(w) || y >= int64_t(h)) {
        say("click " + std::to_string(windowX) + "," + std::to_string(windowY) + ": outside the framebuffer");
        return;
    }
    const std::vector<uint8_t> rgba = shown_->color.toRgba8();
    const uint8_t* p = &rgba[4 * (size_t(y) * w + size_t(x))];
    char text[160];
    std::snprintf(text, sizeof text, "pixel %lld,%lld: rgba %d %d %d %d, depth %.7g", (long long)x,
                  (long long)y, p[0], p[1], p[2], p[3], double(shown_->depth.load(uint32_t(x), uint32_t(y))));
    say(text);
    if (view_ == ImageView::Solution || view_ == ImageView::Difference)
        reportSolutionPixel(uint32_t(x), uint32_t(y), p);
    // Its history: every fragment that reached it, from a traced render of the same frame.
    pixel_selected_ = history_pending_ = true;
    pixel_x_ = int32_t(x), pixel_y_ = int32_t(y);
    if (shownHasHistory())
        printHistory();
    else
        requestRender();
}

}  // namespace raster::tools
