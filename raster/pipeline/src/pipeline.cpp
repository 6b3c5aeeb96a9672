#include "raster/pipeline.hpp"
#include "raster/pipeline_impl.hpp"

#include <cmath>
#include <initializer_list>
#include <thread>

namespace raster {

Context::Context(const ContextOptions& options)
    : options_(options), pool_(std::make_unique<ThreadPool>(options.threads)), scratch_(std::make_unique<Scratch>()) {}
Context::~Context() = default;

unsigned Context::threads() const { return pool_->size(); }

namespace {

// The write side of RenderProgress's sequence lock (Boehm's seqlock): `sequence` odd while `write`
// rewrites the fields, even again after; a reader retries when it saw it odd or changed under it.
// One writer at a time (one draw at a time, or a reset between frames).
template <class Write>
void writeLocked(std::atomic<uint32_t>& sequence, Write write) {
    sequence.fetch_add(1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    write();
    sequence.fetch_add(1, std::memory_order_release);
}

}  // namespace

void RenderProgress::beginDraw() {
    writeLocked(sequence_, [&] {
        tiles_in_draw_.store(0, std::memory_order_relaxed);
        tiles_finished_.store(0, std::memory_order_relaxed);
        draws_started_.fetch_add(1, std::memory_order_relaxed);
    });
}

void RenderProgress::reset() {
    writeLocked(sequence_, [&] {
        for (std::atomic<uint32_t>* a :
             {&draws_started_, &draws_finished_, &tiles_in_draw_, &tiles_finished_})
            a->store(0, std::memory_order_relaxed);
    });
}

RenderProgress::Snapshot RenderProgress::snapshot() const {
    for (;;) {
        const uint32_t before = sequence_.load(std::memory_order_acquire);
        if (before & 1) {  // a draw is starting: a handful of stores, unless its thread was preempted
            std::this_thread::yield();
            continue;
        }
        Snapshot s;
        // Finished before started, and tiles done before tiles in the draw (each ends after the
        // other began), so that neither count is seen ahead of the one it is part of.
        s.drawsFinished = draws_finished_.load(std::memory_order_acquire);
        s.drawsStarted = draws_started_.load(std::memory_order_acquire);
        s.tilesFinished = tiles_finished_.load(std::memory_order_acquire);
        s.tilesInDraw = tiles_in_draw_.load(std::memory_order_acquire);
        std::atomic_thread_fence(std::memory_order_acquire);
        if (sequence_.load(std::memory_order_relaxed) != before) continue;
        // Tiles are counted with relaxed increments, which do not carry tilesInDraw's store with them.
        s.tilesFinished = std::min(s.tilesFinished, s.tilesInDraw);
        return s;
    }
}

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

namespace {
// Rows per band of a parallel clear: 32 rows of 1280 RGBA8 pixels are 160 KB, enough to pay for a
// hand-out, and a 720-row target still splits into 23 bands for two to eight threads.
constexpr uint32_t kClearBandRows = 32;
}  // namespace

void Context::clearRenderTarget(RenderTarget& target, const glm::vec4& color) {
    const uint32_t bands = (target.height() + kClearBandRows - 1) / kClearBandRows;
    pool_->parallelFor(bands, [&](uint32_t band, unsigned) { target.clearRows(color, band * kClearBandRows, kClearBandRows); });
}

void Context::clearDepthTarget(DepthTarget& target, float depth) {
    const uint32_t bands = (target.height() + kClearBandRows - 1) / kClearBandRows;
    pool_->parallelFor(bands, [&](uint32_t band, unsigned) { target.clearRows(depth, band * kClearBandRows, kClearBandRows); });
}

detail::DrawHooks Context::drawHooks(uint32_t draw_index, const DrawPlan& plan, const TeachingCoverage* coverage) {
    detail::DrawHooks h;
    h.skipped = draw_index >= step_limit_.draws;
    if (draw_index + 1 == step_limit_.draws) {  // the step's own draw
        h.primitiveLimit = step_limit_.primitives;
        h.runsGeometryShader = step_limit_.stage != Stage::VertexShader;
        h.runsSetup = h.runsGeometryShader && step_limit_.stage != Stage::GeometryShader;
        h.runsPixels = step_limit_.stage == Stage::OutputMerger;
    }
    h.progress = progress_;
    h.coverage = coverage;
    if (trace_) {
        TraceDraw& d = trace_->beginDraw(plan.width, plan.height);
        d.draw = draw_index;
        d.topology = topology_;
        d.blend = blend_;
        d.depthStencil = depth_stencil_;
        d.rasterizer = rasterizer_;
        d.coverageTest = coverage != nullptr;
        h.trace = trace_;
        h.record = &d;
        h.traceGeometry = trace_->options().geometry;
        h.geometryCap = h.traceGeometry ? trace_->options().maxGeometryRecords : 0;
    }
    return h;
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
        // Pixels left <= x < right: the inclusive last one is right − 1, taken in 64 bits and kept
        // at −1 or more (x0 and y0 are at least 0 here), so that right = INT_MIN is an empty
        // rectangle instead of wrapping around to INT_MAX.
        const RasterizerState& rs = rasterizer_;
        auto lastBefore = [](int32_t last, int32_t end) {
            return int32_t(std::max<int64_t>(-1, std::min<int64_t>(last, int64_t(end) - 1)));
        };
        clip.x0 = std::max(clip.x0, rs.scissorLeft);
        clip.y0 = std::max(clip.y0, rs.scissorTop);
        clip.x1 = lastBefore(clip.x1, rs.scissorRight);
        clip.y1 = lastBefore(clip.y1, rs.scissorBottom);
    }
    p.width = width, p.height = height;
    p.clip = clip;
    p.grid = TileGrid(clip);
    // At most 1e30, so that a viewport narrower than a denormal still gives a finite plane (the
    // band is then narrower than 16384 pixels, which only moves where a cut falls, not coverage).
    p.planes.guardX = std::min(1.0f + 2.0f * kGuardBandPixels / v.width, 1e30f);
    p.planes.guardY = std::min(1.0f + 2.0f * kGuardBandPixels / v.height, 1e30f);
    p.planes.depthClip = rasterizer_.depthClipEnable;
    return p;
}

}  // namespace raster
