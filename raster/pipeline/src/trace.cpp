#include "raster/trace.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

namespace raster {

const char* toString(PrimitiveFate fate) {
    switch (fate) {
        case PrimitiveFate::Rasterized: return "rasterized";
        case PrimitiveFate::Rectangle: return "rectangle";
        case PrimitiveFate::NonFinite: return "non-finite";
        case PrimitiveFate::Outside: return "outside";
        case PrimitiveFate::Culled: return "culled";
        case PrimitiveFate::Degenerate: return "degenerate";
        case PrimitiveFate::NoPixels: return "no-pixels";
    }
    return "(invalid)";
}

const char* toString(FragmentFate fate) {
    switch (fate) {
        case FragmentFate::EarlyDepthFailed: return "depth-failed";
        case FragmentFate::LateDepthFailed: return "depth-failed-late";
        case FragmentFate::Discarded: return "discarded";
        case FragmentFate::BlendNoOp: return "blend-no-op";
        case FragmentFate::Written: return "written";
    }
    return "(invalid)";
}

void Trace::clear() {
    draws_.clear();
    fragments_.clear();
    fragments_truncated_ = false;
    std::fill(overdraw_.begin(), overdraw_.end(), 0u);
    std::fill(non_finite_.begin(), non_finite_.end(), 0u);
}

TraceDraw& Trace::beginDraw(uint32_t width, uint32_t height) {
    if (width != width_ || height != height_) {
        width_ = width, height_ = height;
        overdraw_.assign(size_t(width) * height, 0u);
        non_finite_.assign(size_t(width) * height, 0u);
    }
    draws_.emplace_back();
    return draws_.back();
}

void Trace::addFragments(const std::vector<TraceFragment>& fragments) {
    const size_t room = options_.maxFragments - std::min(options_.maxFragments, fragments_.size());
    if (fragments.size() > room) fragments_truncated_ = true;
    fragments_.insert(fragments_.end(), fragments.begin(), fragments.begin() + std::min(room, fragments.size()));
}

std::vector<TraceFragment> Trace::pixelHistory(int32_t x, int32_t y) const {
    std::vector<TraceFragment> out;
    for (const TraceFragment& f : fragments_)
        if (f.x == x && f.y == y) out.push_back(f);
    return out;
}

}  // namespace raster
