#include "step_cursor.hpp"

#include <algorithm>

namespace raster::tools {

void StepCursor::setShape(std::vector<uint64_t> primitivesPerDraw) {
    shape_ = std::move(primitivesPerDraw);
    has_shape_ = true;
    // A new shape (the scene is the same, so this only matters on the first one) keeps the position valid.
    draws_ = std::min(draws_, drawCount());
    if (draws_ > 0) primitives_ = std::min(primitives_, primitivesOf(draws_));
}

bool StepCursor::partial() const {
    return !whole_ && draws_ > 0 && primitives_ < primitivesOf(draws_);
}

void StepCursor::leaveWhole(bool atEnd) {
    if (!whole_) return;
    whole_ = false;
    draws_ = atEnd ? drawCount() : 0;
    primitives_ = draws_ > 0 ? primitivesOf(draws_) : 0;
}

void StepCursor::nextDraw() {
    leaveWhole(false);
    if (!partial()) {
        if (draws_ == drawCount()) return;
        ++draws_;
    }
    primitives_ = primitivesOf(draws_);
}

void StepCursor::previousDraw() {
    leaveWhole(true);
    // From inside a draw or from its end, the same place: the end of the draw before.
    if (draws_ == 0) return;
    --draws_;
    primitives_ = draws_ > 0 ? primitivesOf(draws_) : 0;
}

void StepCursor::nextPrimitive() {
    leaveWhole(false);
    if (partial()) {
        ++primitives_;
        return;
    }
    if (draws_ == drawCount()) return;
    ++draws_;
    // A draw without primitives is passed over in one step, as complete.
    primitives_ = std::min<uint64_t>(1, primitivesOf(draws_));
}

void StepCursor::previousPrimitive() {
    leaveWhole(true);
    if (draws_ == 0) return;
    if (primitives_ >= 2) {
        --primitives_;
        return;
    }
    --draws_;
    primitives_ = draws_ > 0 ? primitivesOf(draws_) : 0;
}

Context::StepLimit StepCursor::limit() const {
    if (whole_) return {};
    // A complete draw runs without a primitive limit, exactly as in the whole frame.
    return {draws_, partial() ? primitives_ : UINT64_MAX};
}

std::string StepCursor::label() const {
    const std::string n = has_shape_ ? std::to_string(drawCount()) : "?";
    if (whole_) return "whole frame, " + n + " draws";
    if (draws_ == 0) return "draw 0 of " + n + " (cleared targets)";
    const std::string head = "draw " + std::to_string(draws_) + " of " + n;
    if (!partial()) return head + ", complete (" + std::to_string(primitivesOf(draws_)) + " primitives)";
    return head + ", primitive " + std::to_string(primitives_) + " of " +
           std::to_string(primitivesOf(draws_));
}

}  // namespace raster::tools
