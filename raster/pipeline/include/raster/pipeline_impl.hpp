// The draw itself, stage by stage: the template pipeline, compiled for the shaders of each file that
// includes it (the benchmark scenes, the tools, the tests). raster/pipeline.hpp declares the draw;
// a file that draws includes this, or raster/teaching_draw.hpp (labs: the library's one compiled
// teaching pipeline), never both.
#pragma once

#ifdef RASTER_TEACHING_DRAW_INCLUDED
#error "raster/pipeline_impl.hpp and raster/teaching_draw.hpp define the same draws: include one of them"
#endif
#define RASTER_PIPELINE_IMPL_INCLUDED 1

#include <bit>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <typeindex>
#include <unordered_map>
#include <variant>

#include "raster/bin_primitives.hpp"
#include "raster/draw_hooks.hpp"
#include "raster/fastpath/merge_policy.hpp"
#include "raster/fastpath/transparency.hpp"
#include "raster/fill/fill_tile.hpp"
#include "raster/pipeline.hpp"
#include "raster/stages/1_input_assembler.hpp"
#include "raster/stages/2_vertex_shader.hpp"
#include "raster/stages/3_geometry_shader.hpp"
#include "raster/stages/4_clipper.hpp"
#include "raster/stages/5_setup.hpp"
#include "raster/stages/6_binner.hpp"
#include "raster/stages/7_rasterizer.hpp"
#include "raster/stages/8_pixel_shader.hpp"
#include "raster/stages/9_output_merger.hpp"
#include "raster/teaching_pipeline.hpp"
#include "raster/thread_pool.hpp"
#include "raster/trace_recorder.hpp"

namespace raster {

namespace detail {
// Draws made in this translation unit take the generic depth and colour policies only (the same
// bits): 6 instantiations of the tile loop per shader set instead of 16, so a file that draws
// compiles in a fraction of the time. src/teaching_pipeline.cpp (the pipeline labs draw through) and
// the suites of the stages before the pixels define it. A constant per translation unit (internal
// linkage); the draws it changes are of the unit's own shaders, which are local to it.
#ifdef RASTER_DRAWS_GENERIC_ONLY
constexpr bool kDrawsGenericOnly = true;
#else
constexpr bool kDrawsGenericOnly = false;
#endif
}  // namespace detail

struct Context::Scratch {
    std::unordered_map<std::type_index, std::shared_ptr<void>> buffers;
};

template <class T>
T& Context::scratch() {
    auto& slot = scratch_->buffers[std::type_index(typeid(T))];
    if (!slot) slot = std::shared_ptr<void>(new T(), [](void* p) { delete static_cast<T*>(p); });
    return *static_cast<T*>(slot.get());
}

template <VertexShader VS, GeometryShader GS, PixelShader PS>
void Context::execute(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call) {
    const uint32_t draw_index = draw_count_;
    try {
        executeDraw(vs, gs, ps, call);
    } catch (const std::bad_alloc&) {
        // Counts the caller passed were checked against the machine (requireMemory) before anything
        // was allocated; this is the machine running out while the stages run.
        throw Error(ErrorCode::OutOfMemory,
                    "draw " + std::to_string(draw_index) + " (" + detail::shaderName(vs) + ", " + detail::shaderName(ps) +
                        ", " + std::to_string(call.count) + " vertices × " +
                        std::to_string(call.instanceCount) +
                        " instances): an allocation of its stages failed (the machine may hold " +
                        formatBytes(memoryLimit()) + ")");
    }
}

template <VertexShader VS, GeometryShader GS, PixelShader PS>
void Context::executeDraw(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call) {
    using VsIn = VertexShaderInput<VS>;
    using VsOut = VertexShaderOutput<VS>;
    constexpr bool kHasGs = !std::is_same_v<GS, NoGeometryShader>;
    using Vertex = typename detail::LastGeometryStage<GS, VsOut>::Vertex;
    static_assert(
        std::is_same_v<PixelShaderInput<PS>, Vertex>,
        "the pixel shader's input struct must be the geometry shader's output struct (or, without a "
        "geometry shader, the vertex shader's)");
    PrimitiveKind gs_input = PrimitiveKind::Triangle;
    if constexpr (kHasGs) {
        static_assert(std::is_same_v<GeometryShaderInput<GS>, VsOut>,
                      "the geometry shader's input struct must be the vertex shader's output struct");
        gs_input = kGeometryShaderInputKind<GS>;
    }

    // ---- Validation: every check that can fail runs before anything is written ----
    DrawPlan p = plan(detail::pixelShaderTargets(ps), kHasGs, gs_input);
    RASTER_REQUIRE(layout_ != nullptr, InvalidState, "draw without an input layout: call setInputLayout");
    const detail::VertexInputDescription vs_input = detail::vertexInputOf(vs);
    const std::vector<InputFetch> program = layout_->bind(vs_input.signature, vs_input.bytes, vs_input.name.c_str());
    // ---- IA: which vertices, which primitives ----
    const AssembledDraw assembled = assemble(topology_, call, index_buffer_);
    if constexpr (kHasGs) {
        RASTER_REQUIRE(assembled.kind == gs_input, InvalidState,
                       "geometry shader " + detail::shaderName(gs) + " takes " + std::to_string(int(gs_input)) +
                           "-vertex primitives but the topology makes " +
                           std::to_string(int(assembled.kind)) + "-vertex ones");
    }
    if (call.instanceCount != 0 && !assembled.fetch.empty())
        checkVertexBuffers(program, vertex_buffers_, assembled.maxFetch, call.instanceCount - 1,
                           call.startInstance);
    const uint64_t vs_outputs = uint64_t(assembled.fetch.size()) * call.instanceCount;  // < 2^64
    requireMemory(byteCount(vs_outputs, sizeof(VsOut)),
                  "the draw's " + std::to_string(vs_outputs) + " vertex shader outputs (" +
                      std::to_string(assembled.fetch.size()) + " vertices × " +
                      std::to_string(call.instanceCount) + " instances × " + std::to_string(sizeof(VsOut)) +
                      " bytes of " + detail::shaderName(vs) + "'s output)");
    draw_stats_ = {};
    const uint32_t draw_index = draw_count_++;
    // ---- The draw's hooks: step limit, progress, trace, coverage rule (draw_hooks.hpp) ----
    const RenderProgress::DrawScope progress_scope(progress_);
    const detail::DrawHooks hooks = drawHooks(draw_index, p, detail::coverageRule(ps));
    if (hooks.record) detail::describeTraceDraw(*hooks.record, vs, gs, ps);
    p.binWholeBoxes = hooks.coverage != nullptr;
    auto finish = [&](const PipelineStatistics& s) {
        draw_stats_ = s;
        frame_stats_ += s;
        if (draw_log_.size() < kMaxLoggedDraws) draw_log_.push_back(s);
        detail::finishTraceDraw(hooks, s);
    };
    if (hooks.skipped) return finish({});
    if (call.instanceCount == 0 || assembled.fetch.empty()) return finish({});
    PipelineStatistics stats;
    stats.iaVertices = assembled.indicesRead * call.instanceCount;
    stats.iaPrimitives = uint64_t(assembled.primitiveCount()) * call.instanceCount;
    stats.vsInvocations = vs_outputs;

    // ---- VS ----
    auto& vs_out = scratch<std::vector<VsOut>>();
    runVertexShader(vs, program, vertex_buffers_, assembled, call, *pool_, vs_out);
    if (hooks.traceGeometry)
        detail::traceVertices<VsIn>(*hooks.record, hooks.geometryCap, program, vertex_buffers_, assembled, call,
                                    vs_out, uint32_t(vs_input.bytes / sizeof(float)), detail::vertexShaderFloats(vs));
    if (!hooks.runsGeometryShader || (!kHasGs && !hooks.runsSetup)) return finish(stats);

    // ---- GS → clip → setup → bin, in parallel over chunks of primitives ----
    const uint64_t total_prims = std::min(stats.iaPrimitives, hooks.primitiveLimit);
    auto& chunks = scratch<std::vector<detail::Chunk<Vertex>>>();
    const uint32_t chunk_count = runGeometryStages(gs, vs_out, assembled, total_prims, p, hooks, chunks);
    gatherChunks(gs, chunks, chunk_count, stats, hooks);
    if constexpr (!kHasGs) stats.gsInvocations = stats.gsPrimitives = 0;

    // ---- rasterize → PS → OM, in parallel over screen tiles ----
    if (!p.clip.empty() && hooks.runsPixels) rasterizeDraw(ps, chunks, chunk_count, p, stats, hooks);
    finish(stats);
}

template <class GS, class VsOut>
uint32_t Context::runGeometryStages(
    const GS& gs, const std::vector<VsOut>& vs_out, const AssembledDraw& assembled, uint64_t total_prims,
    const DrawPlan& p, const detail::DrawHooks& hooks,
    std::vector<detail::Chunk<typename detail::LastGeometryStage<GS, VsOut>::Vertex>>& chunks) {
    constexpr bool kHasGs = !std::is_same_v<GS, NoGeometryShader>;
    using Vertex = typename detail::LastGeometryStage<GS, VsOut>::Vertex;
    using Stream = typename detail::LastGeometryStage<GS, VsOut>::Stream;
    const uint32_t per_instance = uint32_t(assembled.fetch.size());
    const uint32_t prims_per_instance = assembled.primitiveCount();
    const uint32_t chunk_count =
        uint32_t(std::clamp<uint64_t>((total_prims + 1023) / 1024, 1, uint64_t(pool_->size()) * 8));
    const uint64_t chunk_size = (total_prims + chunk_count - 1) / chunk_count;
    if (chunks.size() < chunk_count) chunks.resize(chunk_count);
    const int k_in = int(assembled.kind);
    // The reference pipeline takes no shortcut: billboards stay two triangles there.
    // Nor does a draw with a lab's coverage rule, whose triangles the lab's test decides.
    [[maybe_unused]] const bool rectangles = !options_.reference && !options_.plain &&
                                             rasterizer_.fillMode == FillMode::Solid && !hooks.coverage;
    const bool setup_stage = hooks.runsSetup;
    pool_->parallelFor(chunk_count, [&](uint32_t c, unsigned) {
        detail::Chunk<Vertex>& chunk = chunks[c];
        chunk.reset(p.grid.count());
        chunk.tracing = hooks.traceGeometry;
        chunk.traceCap = hooks.geometryCap;
        const uint64_t begin = c * chunk_size, end = std::min(total_prims, begin + chunk_size);
        [[maybe_unused]] std::unique_ptr<Stream> stream;
        if constexpr (kHasGs) stream = std::make_unique<Stream>();
        for (uint64_t prim = begin; prim < end; ++prim) {
            const uint32_t instance = uint32_t(prim / prims_per_instance);
            const uint32_t* refs = &assembled.primitives[size_t(prim % prims_per_instance) * k_in];
            const VsOut* in[3] = {};
            for (int j = 0; j < k_in; ++j) in[j] = &vs_out[size_t(instance) * per_instance + refs[j]];
            if constexpr (kHasGs) {
                constexpr size_t kIn = size_t(kGeometryShaderInputKind<GS>);
                std::array<VsOut, kIn> gs_in;
                for (size_t j = 0; j < kIn; ++j) gs_in[j] = *in[j];
                ++chunk.stats.gsInvocations;
                const int overflow = runGeometryShader(
                    gs, gs_in, *stream,
                    [&](PrimitiveKind kind, const Vertex* const* v) {
                        ++chunk.stats.gsPrimitives;
                        if (setup_stage)
                            detail::clipSetupAndBin(kind, v, uint32_t(prim), p, rasterizer_, chunk);
                    },
                    [&](const Vertex* const* quad) {
                        return setup_stage && rectangles &&
                               detail::setupAndBinRectangle(quad, uint32_t(prim), p, rasterizer_, chunk);
                    });
                if (overflow && !chunk.gsOverflow)
                    chunk.gsOverflow = overflow, chunk.gsOverflowPrimitive = uint32_t(prim);
                if (chunk.tracing)
                    detail::traceGsOutput(chunk, uint32_t(prim), *stream, detail::geometryShaderFloats(gs));
            } else {
                detail::clipSetupAndBin(assembled.kind, in, uint32_t(prim), p, rasterizer_, chunk);
            }
        }
    });
    return chunk_count;
}

template <class GS, class V>
void Context::gatherChunks(const GS& gs, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                           PipelineStatistics& stats, const detail::DrawHooks& hooks) {
    for (uint32_t c = 0; c < chunk_count; ++c) {
        detail::Chunk<V>& chunk = chunks[c];
        RASTER_REQUIRE(chunk.gsOverflow == 0, ShaderError,
                       "geometry shader " + detail::shaderName(gs) + " appended " + std::to_string(chunk.gsOverflow) +
                           " vertices past its maxvertexcount of " + std::to_string(detail::maxVertexCount(gs)) +
                           " for primitive " + std::to_string(chunk.gsOverflowPrimitive) +
                           "; the draw was not rasterised");
        stats += chunk.stats;
        if (hooks.traceGeometry) detail::gatherGeometryRecords(*hooks.record, hooks.geometryCap, chunk);
    }
}

template <class PS, class V>
void Context::rasterizeDraw(const PS& ps, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                            const DrawPlan& p, PipelineStatistics& stats, const detail::DrawHooks& hooks) {
    // The policies for the draw's state, chosen once per draw (fastpath/merge_policy.hpp).
    const DepthPolicy depth = chooseDepthPolicy(depth_stencil_, depth_, options_.reference);
    const ColorPolicy color = chooseColorPolicy(blend_, p.targets.data(), p.targetCount, options_.reference);
    if (isOrderIndependent(blend_, p.targetCount)) ++stats.sortsAvoided;
    // A state the pixel shader is specialised for (specialised_states.hpp), untraced, without a
    // coverage rule and not the plain path: the tile loop with the state folded in, the eight-wide
    // fill paths and no hooks.
    if constexpr (!detail::kDrawsGenericOnly) {
        if (hooks.fragmentHooksIdle() && !options_.plain &&
            withSpecialisedPolicies(typename SpecialisedStatesOf<PS>::type{}, depth, color,
                                    [&](const auto& d, const auto& c) {
                                        renderTiles<PS, V, float>(ps, chunks, chunk_count, p, d, c, stats,
                                                                  detail::NoHooks{}, hooks);
                                    })) {
            ++stats.drawsSpecialised;
            return;
        }
    }
    // Everything else (traced draws, the plain path, files that draw through the generic policies
    // only, and the states without a specialisation) reads the state per fragment: the same bits.
    GenericDepthPolicy generic_depth = genericDepthPolicy(depth);
    const GenericColorPolicy generic_color = genericColorPolicy(color, blend_, p.targets.data(), p.targetCount);
    if (auto* dynamic = std::get_if<DepthDynamic>(&generic_depth))
        dynamic->late = options_.plain;  // D3D's order
    // Records only a traced draw's fragments, fragment by fragment; carries the coverage rule.
    const detail::FragmentHooks tile_hooks =
        detail::fragmentHooks(hooks, p.targetCount > 0 ? p.targets[0] : nullptr, depth_, p.width);
    withGenericPolicies(generic_depth, generic_color, [&](const auto& d, const auto& c) {
        using C = std::decay_t<decltype(c)>;
        // The reference pipeline computes in double (ColorGeneric<double>).
        using Real = std::conditional_t<std::is_same_v<C, ColorGeneric<double>>, double, float>;
        renderTiles<PS, V, Real>(ps, chunks, chunk_count, p, d, c, stats, tile_hooks, hooks);
    });
}

namespace detail {

// Sets the calling thread's reference-mode flag for the lifetime of the guard.
struct ReferenceModeGuard {
    bool saved;
    explicit ReferenceModeGuard(bool on) : saved(tReferenceMode) { tReferenceMode = on; }
    ~ReferenceModeGuard() { tReferenceMode = saved; }
};

}  // namespace detail

// rasterize → PS → OM, screen tile by screen tile in parallel; each tile reads its bins in primitive
// order, so the image is the same for any thread count. Which fill path a tile's primitives take is
// fillTile's choice (fill/fill_tile.hpp).
template <class PS, class V, class Real, class TileHooks, class Depth, class Color>
void Context::renderTiles(const PS& ps, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                          const DrawPlan& plan, const Depth& depth, const Color& color,
                          PipelineStatistics& stats, const TileHooks& tile_hooks, const detail::DrawHooks& hooks) {
    using TileFill = Tile<PS, V, Real, TileHooks, Depth, Color>;
    typename TileFill::Draw draw{
        ps, depth,         color, chunks, chunk_count, plan.viewport.minDepth, plan.viewport.maxDepth,
        {}, options_.plain};
    if constexpr (TileFill::kSkipTransparent)
        draw.transparentColumns = detail::TransparentColumns(ps.alphaSource());
    // One cache line or more per thread, so that the counters of two threads never share one.
    struct alignas(64) ThreadStatistics {
        PipelineStatistics s;
    };
    std::vector<ThreadStatistics> per_thread(pool_->size());
    [[maybe_unused]] std::vector<std::vector<TraceFragment>> traced_tiles(tile_hooks.active ? plan.grid.count() : 0);
    RenderProgress* const progress = hooks.progress;
    if (progress) progress->beginTiles(plan.grid.count());
    pool_->parallelFor(plan.grid.count(), [&](uint32_t index, unsigned thread) {
        const detail::ReferenceModeGuard reference(std::is_same_v<Real, double>);
        TileFill tile(draw, index, plan.grid.tileRect(index), per_thread[thread].s, tile_hooks);
        fillTile(tile);
        if constexpr (TileHooks::kEnabled)
            if (tile_hooks.active) traced_tiles[index] = std::move(tile.hooks.fragments);
        if (progress) progress->tileFinished();  // per tile, never per pixel: see RenderProgress
    });
    for (const ThreadStatistics& t : per_thread) stats += t.s;
    for (const auto& fragments : traced_tiles) hooks.trace->addFragments(fragments);
}

}  // namespace raster
