// The solution views (K, J): the solution's image, or its difference from the frame, with what the
// HUD and the messages say about them (compare_views.hpp holds the arithmetic).
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "viewer.hpp"

namespace raster::tools {
namespace {

std::string sizeText(uint32_t width, uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

const std::vector<uint8_t>* Viewer::solutionPixels(std::vector<uint8_t>& storage, std::string& why) const {
    const RenderedFrame& f = *shown_;
    const uint32_t w = f.color.width(), h = f.color.height();
    switch (solution_.kind) {
        case SolutionSource::Kind::None:
            why = kNoSolution;
            return nullptr;
        case SolutionSource::Kind::Image: {
            const uint32_t iw = solution_image_.width, ih = solution_image_.height;
            if (iw == w && ih == h) return &solution_image_.pixels;
            why = solution_.name + " is " + sizeText(iw, ih) + ", the frame " + sizeText(w, h) +
                  ": no pixel to pixel comparison (start with --size " + sizeText(iw, ih) +
                  " or resize the window to it)";
            return nullptr;
        }
        default:
            if (!f.request.solution) {
                why = "rendering " + solutionLabel(solution_) + "...";  // the frame with it is coming
            } else if (!f.solutionError.empty()) {
                why = "rendering " + solutionLabel(solution_) + " failed: " + f.solutionError;
            } else if (f.solution) {
                storage = f.solution->toRgba8();
                return &storage;
            } else {
                why = solutionLabel(solution_) + " was not rendered";
            }
            return nullptr;
    }
}

void Viewer::composeSolutionViews() {
    if (view_ != ImageView::Solution && view_ != ImageView::Difference) return;
    const bool difference = view_ == ImageView::Difference;
    const RenderedFrame& f = *shown_;
    const uint32_t w = f.color.width(), h = f.color.height();
    std::vector<uint8_t> storage;
    std::string why;
    const std::vector<uint8_t>* solution = solutionPixels(storage, why);
    if (!solution) {
        // The frame stays in view, with the reason over it; a PNG of another size is still worth a
        // look, scaled to the frame.
        const bool none = solution_.kind == SolutionSource::Kind::None;
        view_notes_.push_back((none ? "" : difference ? "difference: " : "solution: ") + why);
        if (!difference && solution_.kind == SolutionSource::Kind::Image) {
            image_ =
                scaleNearest(solution_image_.pixels, solution_image_.width, solution_image_.height, w, h);
            view_notes_.back() += "; shown scaled";
        }
        return;
    }
    if (!difference) {
        std::string note = "solution: " + solutionLabel(solution_);
        if (solution_.kind != SolutionSource::Kind::Image) {
            char ms[48];
            std::snprintf(ms, sizeof ms, ", rendered in %.1f ms", f.solutionMilliseconds);
            note += ms;
        }
        view_notes_.push_back(note);
        image_ = *solution;
        return;
    }
    // image_ holds the frame's colour image here (uploadImage: only D replaces it).
    const std::vector<std::string> lines =
        describeDifference(compareImages({image_, w, h}, {*solution, w, h}), solutionLabel(solution_));
    image_ = differenceImage(image_, *solution, w, h);
    view_notes_.insert(view_notes_.end(), lines.begin(), lines.end());
    // Printed when the figures change: not at every redraw, nor for a re-render of the same image
    // (a click's traced frame).
    if (lines == difference_said_) return;
    difference_said_ = lines;
    for (const std::string& line : lines) say(line);
}

void Viewer::reportSolutionPixel(uint32_t x, uint32_t y, const uint8_t* frame) {
    std::vector<uint8_t> storage;
    std::string why;
    const std::vector<uint8_t>* solution = solutionPixels(storage, why);
    if (!solution) {
        say(solution_.kind == SolutionSource::Kind::None ? why : "solution: " + why);
        return;
    }
    const uint8_t* p = &(*solution)[4 * (size_t(y) * shown_->color.width() + x)];
    const int largest = largestChannelDifference(p, frame);
    char text[160];
    std::snprintf(text, sizeof text, "solution pixel %u,%u: rgba %d %d %d %d, largest difference %d/255", x,
                  y, p[0], p[1], p[2], p[3], largest);
    say(text);
}

}  // namespace raster::tools
