#include <cmath>

#include "raster/pipeline.hpp"

namespace raster {

Context::Context(const ContextOptions& options) : options_(options), pool_(options.threads) {}

void Context::setVertexBuffer(uint32_t slot, const VertexBuffer* buffer) {
    RASTER_REQUIRE(slot < kMaxInputSlots, InvalidArgument,
                   "vertex buffer slot " + std::to_string(slot) + " is not below " + std::to_string(kMaxInputSlots));
    vertex_buffers_[slot] = buffer;
}

void Context::setRenderTargets(std::span<RenderTarget* const> targets, DepthTarget* depth) {
    RASTER_REQUIRE(targets.size() <= size_t(kMaxRenderTargets), InvalidArgument,
                   std::to_string(targets.size()) + " render targets bound; at most " +
                       std::to_string(kMaxRenderTargets));
    for (size_t i = 0; i < targets.size(); ++i)
        RASTER_REQUIRE(targets[i] != nullptr, InvalidArgument, "render target " + std::to_string(i) + " is null");
    targets_ = {};
    std::copy(targets.begin(), targets.end(), targets_.begin());
    target_count_ = int(targets.size());
    depth_ = depth;
}

Context::DrawPlan Context::plan(int pixel_shader_targets, bool, PrimitiveKind) const {
    validate(blend_);
    validate(depth_stencil_);
    validate(rasterizer_);
    validate(viewport_);
    RASTER_REQUIRE(target_count_ > 0 || depth_ != nullptr, InvalidState,
                   "draw with neither a render target nor a depth target bound: call setRenderTargets");
    RASTER_REQUIRE(target_count_ <= pixel_shader_targets, InvalidState,
                   std::to_string(target_count_) + " render targets are bound but the pixel shader writes " +
                       std::to_string(pixel_shader_targets));
    uint32_t width = 0, height = 0;
    auto sameSize = [&](uint32_t w, uint32_t h, const std::string& what) {
        RASTER_REQUIRE(w > 0 && h > 0, InvalidState, what + " is empty (0x0)");
        if (width == 0) width = w, height = h;
        RASTER_REQUIRE(w == width && h == height, InvalidState,
                       what + " is " + std::to_string(w) + "x" + std::to_string(h) + " but the other targets are " +
                           std::to_string(width) + "x" + std::to_string(height));
    };
    for (int i = 0; i < target_count_; ++i)
        sameSize(targets_[i]->width(), targets_[i]->height(), "render target " + std::to_string(i));
    if (depth_) sameSize(depth_->width(), depth_->height(), "the depth target");

    DrawPlan p;
    p.targets = targets_;
    p.targetCount = target_count_;
    p.viewport = ViewportTransform(viewport_);
    const Viewport& v = viewport_;
    // Pixels whose centres lie in [topLeft, topLeft + size).
    PixelRect clip{int32_t(std::ceil(v.topLeftX - 0.5f)), int32_t(std::ceil(v.topLeftY - 0.5f)),
                   int32_t(std::ceil(v.topLeftX + v.width - 0.5f)) - 1,
                   int32_t(std::ceil(v.topLeftY + v.height - 0.5f)) - 1};
    clip.x0 = std::max(clip.x0, 0);
    clip.y0 = std::max(clip.y0, 0);
    clip.x1 = std::min(clip.x1, int32_t(width) - 1);
    clip.y1 = std::min(clip.y1, int32_t(height) - 1);
    if (rasterizer_.scissorEnable) {
        clip.x0 = std::max(clip.x0, rasterizer_.scissorLeft);
        clip.y0 = std::max(clip.y0, rasterizer_.scissorTop);
        clip.x1 = std::min(clip.x1, rasterizer_.scissorRight - 1);
        clip.y1 = std::min(clip.y1, rasterizer_.scissorBottom - 1);
    }
    p.width = width, p.height = height;
    p.clip = clip;
    p.grid = TileGrid(clip);
    p.planes.guardX = 1.0f + 2.0f * kGuardBandPixels / v.width;
    p.planes.guardY = 1.0f + 2.0f * kGuardBandPixels / v.height;
    p.planes.depthClip = rasterizer_.depthClipEnable;
    return p;
}

}  // namespace raster
