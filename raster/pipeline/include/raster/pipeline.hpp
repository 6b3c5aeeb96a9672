// The pipeline: a Direct3D 11 style immediate context whose draw runs, top to bottom,
//
//   IA → VS → GS → clip → setup → bin → rasterize → PS → OM
//
// each stage in its own header under raster/stages/. Bind state and resources with the set*
// calls (D3D11's IASet*, RSSet*, OMSet*), then draw with the shaders as arguments: shaders are
// template parameters, so every draw is compiled for its own shaders (see shader.hpp).
//
//   raster::Context ctx;                        // all cores
//   ctx.setRenderTargets(&color, &depth);
//   ctx.setViewport({0, 0, 1280, 720, 0, 1});
//   ctx.setInputLayout(&layout);
//   ctx.setVertexBuffer(0, &particles);
//   ctx.setPrimitiveTopology(raster::Topology::PointList);
//   ctx.setBlendState(raster::BlendState::additive());
//   ctx.draw(VsBillboard{}, GsBillboard{...}, PsFire{...}, particleCount);
//
// A file that draws includes raster/pipeline_impl.hpp too (the template pipeline, compiled for its
// shaders; a file that only binds state or holds a Context need not parse it), or, in a lab,
// raster/teaching_draw.hpp (the library's one compiled teaching pipeline; raster/lab.hpp includes it).
//
// A draw validates everything first (states, layout against the vertex shader's input, buffer
// ranges, target sizes) and runs all geometry stages before it writes a pixel, so a draw that
// throws raster::Error leaves the render targets exactly as they were. The image is the same,
// bit for bit, for any thread count. ContextOptions::reference selects the reference pipeline:
// interpolation, sampling and blending in double, rounded once, no shortcuts — slow, and the
// oracle the fast pipeline is measured against.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "raster/bin_primitives.hpp"
#include "raster/buffer.hpp"
#include "raster/check.hpp"
#include "raster/draw_hooks.hpp"
#include "raster/input_layout.hpp"
#include "raster/render_target.hpp"
#include "raster/shader.hpp"
#include "raster/stages/1_input_assembler.hpp"
#include "raster/states.hpp"
#include "raster/statistics.hpp"
#include "raster/teaching_pipeline.hpp"
#include "raster/trace.hpp"

namespace raster {

class ThreadPool;  // thread_pool.hpp: held through a pointer, so that this header need not parse <thread>

// drawStatisticsLog keeps at most this many draws between resets (a frame rarely has more).
constexpr size_t kMaxLoggedDraws = 1 << 16;

struct ContextOptions {
    unsigned threads = 0;    // 0: one per hardware thread
    bool reference = false;  // the double-precision reference pipeline
    // The plain path, for reading and stepping the pipeline in a debugger: every primitive goes
    // through fill/quads.hpp (rasterizer edge functions → early depth test → pixel shader → output
    // merger, quad by quad), with the generic depth and blend (the same bits as the specialised
    // ones), billboards as the two triangles the geometry shader emits, no tile skipped. Images equal
    // the fast path's except where it draws a billboard as a rectangle (within 1/255 there).
    bool plain = false;
};

// How far a frame has got, for a progress display on another thread while the frame renders: give
// one to Context::setProgress, reset() it before the frame, and read snapshot() from any thread.
// The rendering threads write it; it never changes what is drawn. It counts the draws of one
// context at a time (one may follow another, as the frame and its solution do in the viewer).
//
// Cost: a few atomic operations per draw and one relaxed increment per screen tile, only while set;
// nothing per pixel. Without it (the default) a draw tests a null pointer once per tile.
class RenderProgress {
  public:
    struct Snapshot {
        uint32_t drawsStarted = 0;   // draws since reset() that passed validation: run, skipped or empty
        uint32_t drawsFinished = 0;  // of those, the ones that ended (a skipped or empty draw at once)
        // Of draw number drawsStarted (the latest): the screen tiles its rasterisation covers, 0
        // until its geometry stages are done and for a draw that rasterises nothing (skipped, empty,
        // no tile in the viewport), and how many of them are done (≤ tilesInDraw).
        uint32_t tilesInDraw = 0;
        uint32_t tilesFinished = 0;
        bool drawRunning() const { return drawsFinished < drawsStarted; }
    };

    // A consistent reading: the tile counts belong to draw drawsStarted, drawsFinished ≤
    // drawsStarted. Between resets each field only grows from one snapshot to the next, except the
    // tile counts, which start again at 0 when drawsStarted grows.
    Snapshot snapshot() const;
    // Everything to 0. Call while no draw using this object runs (readers may go on reading).
    void reset();

  private:
    friend class Context;
    void beginDraw();
    void beginTiles(uint32_t tiles) { tiles_in_draw_.store(tiles, std::memory_order_release); }
    void tileFinished() { tiles_finished_.fetch_add(1, std::memory_order_relaxed); }
    void endDraw() { draws_finished_.fetch_add(1, std::memory_order_release); }
    // A draw, started when made and finished when gone, however the draw ends (run, skipped, empty,
    // or throwing after validation). Null: nothing counted.
    class DrawScope {
      public:
        explicit DrawScope(RenderProgress* progress) : progress_(progress) {
            if (progress_) progress_->beginDraw();
        }
        ~DrawScope() {
            if (progress_) progress_->endDraw();
        }
        DrawScope(const DrawScope&) = delete;
        DrawScope& operator=(const DrawScope&) = delete;

      private:
        RenderProgress* progress_;
    };

    // A sequence lock over the per-draw reset: odd while beginDraw (or reset) rewrites the fields,
    // so that a snapshot never pairs one draw's number with another draw's tiles.
    std::atomic<uint32_t> sequence_{0};
    std::atomic<uint32_t> draws_started_{0}, draws_finished_{0};
    std::atomic<uint32_t> tiles_in_draw_{0}, tiles_finished_{0};
};

namespace detail {

template <class GS, class VsOut>
struct LastGeometryStage {
    using Vertex = GeometryShaderOutput<GS>;
    using Stream = GeometryShaderStream<GS>;
};
template <class VsOut>
struct LastGeometryStage<NoGeometryShader, VsOut> {
    using Vertex = VsOut;
    using Stream = OutputStream<VsOut, 1, PrimitiveKind::Point>;  // never used
};

}  // namespace detail

class Context {
  public:
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    // ---- Input assembler ----
    void setInputLayout(const InputLayout* layout) { layout_ = layout; }
    void setPrimitiveTopology(Topology topology) { topology_ = topology; }
    void setVertexBuffer(uint32_t slot, const VertexBuffer* buffer);
    void setIndexBuffer(const IndexBuffer* buffer) { index_buffer_ = buffer; }
    // ---- Rasterizer ----
    void setRasterizerState(const RasterizerState& state) { rasterizer_ = state; }
    void setViewport(const Viewport& viewport) { viewport_ = viewport; }
    // The rasterizer lab's coverage test (stages/5_setup.hpp's CoverageTest), or nullptr for the
    // library's rule: which pixel centres the triangles of the teaching pipeline's draws (a lab's
    // file, raster/teaching_draw.hpp) cover. The template pipeline's draws ignore it. No D3D11 state:
    // the lab's way into the rasterizer. beginSceneFrame resets it.
    void setCoverageTest(CoverageTest test) { coverage_test_ = test; }
    CoverageTest coverageTest() const { return coverage_test_; }
    // ---- Output merger ----
    void setBlendState(const BlendState& state) { blend_ = state; }
    void setDepthStencilState(const DepthStencilState& state) { depth_stencil_ = state; }
    // Up to kMaxRenderTargets colour targets (nullptr entries not allowed) and an optional depth target.
    void setRenderTargets(std::span<RenderTarget* const> targets, DepthTarget* depth);
    void setRenderTargets(RenderTarget* target, DepthTarget* depth) {
        RenderTarget* const one[1] = {target};
        setRenderTargets(target ? std::span<RenderTarget* const>(one) : std::span<RenderTarget* const>(),
                         depth);
    }

    // D3D11's ClearRenderTargetView and ClearDepthStencilView (depth only): as target.clear(), on
    // the Context's threads, a band of rows each; the same bytes for any thread count.
    void clearRenderTarget(RenderTarget& target, const glm::vec4& color);
    void clearDepthTarget(DepthTarget& target, float depth);

    const RasterizerState& rasterizerState() const { return rasterizer_; }
    const Viewport& viewport() const { return viewport_; }
    const BlendState& blendState() const { return blend_; }
    const DepthStencilState& depthStencilState() const { return depth_stencil_; }

    // ---- Draws (D3D11's Draw, DrawIndexed, DrawInstanced, DrawIndexedInstanced) ----
    template <VertexShader VS, PixelShader PS>
    void draw(const VS& vs, const PS& ps, uint32_t vertexCount, uint32_t startVertex = 0) {
        execute(vs, NoGeometryShader{}, ps, DrawCall{false, vertexCount, startVertex});
    }
    template <VertexShader VS, GeometryShader GS, PixelShader PS>
    void draw(const VS& vs, const GS& gs, const PS& ps, uint32_t vertexCount, uint32_t startVertex = 0) {
        execute(vs, gs, ps, DrawCall{false, vertexCount, startVertex});
    }
    template <VertexShader VS, PixelShader PS>
    void drawIndexed(const VS& vs, const PS& ps, uint32_t indexCount, uint32_t startIndex = 0,
                     int32_t baseVertex = 0) {
        execute(vs, NoGeometryShader{}, ps, DrawCall{true, indexCount, startIndex, baseVertex});
    }
    template <VertexShader VS, GeometryShader GS, PixelShader PS>
    void drawIndexed(const VS& vs, const GS& gs, const PS& ps, uint32_t indexCount, uint32_t startIndex = 0,
                     int32_t baseVertex = 0) {
        execute(vs, gs, ps, DrawCall{true, indexCount, startIndex, baseVertex});
    }
    template <VertexShader VS, PixelShader PS>
    void drawInstanced(const VS& vs, const PS& ps, uint32_t vertexCountPerInstance, uint32_t instanceCount,
                       uint32_t startVertex = 0, uint32_t startInstance = 0) {
        execute(vs, NoGeometryShader{}, ps,
                DrawCall{false, vertexCountPerInstance, startVertex, 0, instanceCount, startInstance});
    }
    template <VertexShader VS, PixelShader PS>
    void drawIndexedInstanced(const VS& vs, const PS& ps, uint32_t indexCountPerInstance,
                              uint32_t instanceCount, uint32_t startIndex = 0, int32_t baseVertex = 0,
                              uint32_t startInstance = 0) {
        execute(vs, NoGeometryShader{}, ps,
                DrawCall{true, indexCountPerInstance, startIndex, baseVertex, instanceCount, startInstance});
    }
    // Any draw, spelled out. Counts that would need more memory than the machine has are refused
    // before anything is allocated, and an allocation that fails while the stages run is reported:
    // both as Error(OutOfMemory), never std::bad_alloc.
    template <VertexShader VS, GeometryShader GS, PixelShader PS>
    void execute(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call);
    // The same draw through the teaching pipeline (teaching_pipeline.hpp), compiled in the library:
    // what execute() calls in a file that includes raster/teaching_draw.hpp.
    void executeTeaching(const TeachingVertexShader& vs, const TeachingPixelShader& ps, const DrawCall& call);
    void executeTeaching(const TeachingVertexShader& vs, const TeachingPointGeometryShader& gs,
                         const TeachingPixelShader& ps, const DrawCall& call);
    void executeTeaching(const TeachingVertexShader& vs, const TeachingTriangleGeometryShader& gs,
                         const TeachingPixelShader& ps, const DrawCall& call);

    // ---- Statistics ----
    const PipelineStatistics& drawStatistics() const { return draw_stats_; }    // the last draw
    const PipelineStatistics& frameStatistics() const { return frame_stats_; }  // since resetFrameStatistics
    // Stepping: draws are numbered from 0 since resetFrameStatistics. With a step limit, draws
    // numbered `draws` and later are skipped (validated, not run), and draw `draws − 1` runs only
    // its first `primitives` input primitives (in input-assembler order, instances included).
    // Replaying a frame under growing limits steps it draw by draw and primitive by primitive.
    // `stage` steps it stage by stage: draw `draws − 1` (only that one, so only when `draws` is
    // set) runs its admitted primitives up to and including that stage and no further —
    //   VertexShader:   input assembler and vertex shader (the GS, clipper, setup and pixels not run),
    //   GeometryShader: also the geometry shader (its output neither clipped nor set up; for a draw
    //                   without one, the same as VertexShader),
    //   Setup:          also clipping, setup and binning (no pixel rasterised, shaded or written),
    //   OutputMerger:   the whole pipeline (the default).
    // Statistics and the trace then hold what ran: e.g. at Setup, cPrimitives but no psInvocations.
    enum class Stage : uint8_t { VertexShader, GeometryShader, Setup, OutputMerger };
    struct StepLimit {
        uint32_t draws = UINT32_MAX;
        uint64_t primitives = UINT64_MAX;
        Stage stage = Stage::OutputMerger;
        bool operator==(const StepLimit&) const = default;
    };
    void setStepLimit(const StepLimit& limit) { step_limit_ = limit; }
    const StepLimit& stepLimit() const { return step_limit_; }
    // Draws since resetFrameStatistics (run or skipped).
    uint32_t drawCount() const { return draw_count_; }

    // ---- Progress (see RenderProgress): draws report into `progress` until setProgress(nullptr),
    // for another thread to show while the frame renders. Not reset here; it must outlive its use.
    void setProgress(RenderProgress* progress) { progress_ = progress; }
    RenderProgress* progress() const { return progress_; }

    // ---- Trace (see trace.hpp): draws record into `trace` until setTrace(nullptr). The trace
    // must outlive its use; it is not cleared here (Trace::clear starts a new frame's records).
    void setTrace(Trace* trace) { trace_ = trace; }
    Trace* trace() const { return trace_; }

    // One entry per draw since resetFrameStatistics (skipped and empty draws too), in draw order.
    const std::vector<PipelineStatistics>& drawStatisticsLog() const { return draw_log_; }
    void resetFrameStatistics() {
        frame_stats_ = {};
        draw_log_.clear();
        draw_count_ = 0;
    }

    unsigned threads() const;
    bool reference() const { return options_.reference; }

  private:
    // Everything a draw needs that does not depend on the shaders' types; throws on misuse.
    struct DrawPlan : detail::PrimitiveSpace {
        std::array<RenderTarget*, kMaxRenderTargets> targets{};
        int targetCount = 0;
        uint32_t width = 0, height = 0;  // of the bound targets
    };
    DrawPlan plan(int pixel_shader_targets, bool has_gs, PrimitiveKind gs_input) const;

    // execute() without its std::bad_alloc → Error(OutOfMemory) translation.
    template <VertexShader VS, GeometryShader GS, PixelShader PS>
    void executeDraw(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call);

    // The draw's hooks (draw_hooks.hpp): the step limit, progress and trace resolved for draw
    // draw_index, its trace record begun with the context's state; coverage: the draw's coverage rule.
    detail::DrawHooks drawHooks(uint32_t draw_index, const DrawPlan& plan, const TeachingCoverage* coverage);

    // GS → clip → setup → bin of the draw's first total_prims primitives, in parallel over chunks of
    // them; returns how many chunks. Without hooks.runsSetup: the geometry shader only (a step's stage).
    template <class GS, class VsOut>
    uint32_t runGeometryStages(
        const GS& gs, const std::vector<VsOut>& vs_out, const AssembledDraw& assembled, uint64_t total_prims,
        const DrawPlan& p, const detail::DrawHooks& hooks,
        std::vector<detail::Chunk<typename detail::LastGeometryStage<GS, VsOut>::Vertex>>& chunks);
    // The chunks' statistics and trace records into the draw's; a geometry shader's overflow throws.
    template <class GS, class V>
    void gatherChunks(const GS& gs, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                      PipelineStatistics& stats, const detail::DrawHooks& hooks);
    // rasterize → PS → OM: the depth and colour policies for the draw's state, then renderTiles.
    template <class PS, class V>
    void rasterizeDraw(const PS& ps, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                       const DrawPlan& p, PipelineStatistics& stats, const detail::DrawHooks& hooks);

    // A buffer of type T kept from draw to draw, so that a frame's draws reuse their allocations.
    template <class T>
    T& scratch();

    // The tile loop, for one depth and one colour policy and the tile's hooks (NoHooks or
    // FragmentHooks, draw_hooks.hpp).
    template <class PS, class V, class Real, class TileHooks, class Depth, class Color>
    void renderTiles(const PS& ps, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                     const DrawPlan& plan, const Depth& depth, const Color& color, PipelineStatistics& stats,
                     const TileHooks& tile_hooks, const detail::DrawHooks& hooks);

    ContextOptions options_;
    std::unique_ptr<ThreadPool> pool_;
    const InputLayout* layout_ = nullptr;
    Topology topology_ = Topology::Undefined;
    std::array<const VertexBuffer*, kMaxInputSlots> vertex_buffers_{};
    const IndexBuffer* index_buffer_ = nullptr;
    RasterizerState rasterizer_;
    Viewport viewport_;
    CoverageTest coverage_test_ = nullptr;
    BlendState blend_;
    DepthStencilState depth_stencil_;
    std::array<RenderTarget*, kMaxRenderTargets> targets_{};
    int target_count_ = 0;
    DepthTarget* depth_ = nullptr;
    PipelineStatistics draw_stats_, frame_stats_;
    std::vector<PipelineStatistics> draw_log_;
    StepLimit step_limit_;
    uint32_t draw_count_ = 0;
    struct Scratch;  // pipeline_impl.hpp
    std::unique_ptr<Scratch> scratch_;
    Trace* trace_ = nullptr;
    RenderProgress* progress_ = nullptr;
};

}  // namespace raster
