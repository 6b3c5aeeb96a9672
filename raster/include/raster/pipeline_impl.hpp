// The draw itself, stage by stage. Included by pipeline.hpp; read that first.
#pragma once

#include <bit>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>
#include <variant>

// The fill loops are flattened (their whole call tree inlined): their speed depends on the shader,
// sampler and merge being one block of code (PERFORMANCE.md). Under AddressSanitizer that tree,
// instrumented, takes GCC over 15 minutes and nearly 5 GB for one file, so sanitizer builds leave
// the inlining to the compiler; what the code does is the same either way. RASTER_NO_FLATTEN is
// defined by the build for any RASTER_SANITIZE (CMakeLists.txt): GCC defines __SANITIZE_ADDRESS__
// for AddressSanitizer only, and clang defines nothing at all. (Measured, one PsConstant draw alone
// at -O1 -g: GCC's UBSan 148 s of CPU and 1.6 GB flattened, 66 s and 1.3 GB not; README.)
#if defined(RASTER_NO_FLATTEN) || defined(__SANITIZE_ADDRESS__)
#define RASTER_FLATTEN
#else
#define RASTER_FLATTEN __attribute__((flatten))
#endif

namespace raster {

template <VertexShader VS, GeometryShader GS, PixelShader PS>
void Context::execute(const VS& vs, const GS& gs, const PS& ps, const DrawCall& call) {
    const uint32_t draw_index = draw_count_;
    try {
        executeDraw(vs, gs, ps, call);
    } catch (const std::bad_alloc&) {
        // Counts the caller passed were checked against the machine (requireMemory) before anything
        // was allocated; this is the machine running out while the stages run.
        throw Error(ErrorCode::OutOfMemory,
                    "draw " + std::to_string(draw_index) + " (" + typeName<VS>() + ", " + typeName<PS>() + ", " +
                        std::to_string(call.count) + " vertices × " + std::to_string(call.instanceCount) +
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
    using Stream = typename detail::LastGeometryStage<GS, VsOut>::Stream;
    static_assert(std::is_same_v<PixelShaderInput<PS>, Vertex>,
                  "the pixel shader's input struct must be the geometry shader's output struct (or, without a "
                  "geometry shader, the vertex shader's)");
    using PsOut = PixelShaderOutput<PS>;
    constexpr int kPsTargets = detail::ColorTraits<PsOut>::kTargets;
    PrimitiveKind gs_input = PrimitiveKind::Triangle;
    if constexpr (kHasGs) {
        static_assert(std::is_same_v<GeometryShaderInput<GS>, VsOut>,
                      "the geometry shader's input struct must be the vertex shader's output struct");
        gs_input = kGeometryShaderInputKind<GS>;
    }

    // ---- Validation: every check that can fail runs before anything is written ----
    const DrawPlan p = plan(kPsTargets, kHasGs, gs_input);
    RASTER_REQUIRE(layout_ != nullptr, InvalidState, "draw without an input layout: call setInputLayout");
    const auto signature = VsIn::inputSignature();
    const std::vector<InputFetch> program = layout_->bind(signature, sizeof(VsIn), typeName<VsIn>().c_str());
    // ---- IA: which vertices, which primitives ----
    const AssembledDraw assembled = assemble(topology_, call, index_buffer_);
    if constexpr (kHasGs) {
        RASTER_REQUIRE(assembled.kind == gs_input, InvalidState,
                       "geometry shader " + typeName<GS>() + " takes " + std::to_string(int(gs_input)) +
                           "-vertex primitives but the topology makes " + std::to_string(int(assembled.kind)) +
                           "-vertex ones");
    }
    if (call.instanceCount != 0 && !assembled.fetch.empty())
        checkVertexBuffers(program, vertex_buffers_, assembled.maxFetch, call.instanceCount - 1, call.startInstance);
    const uint64_t vs_outputs = uint64_t(assembled.fetch.size()) * call.instanceCount;  // < 2^64
    requireMemory(byteCount(vs_outputs, sizeof(VsOut)),
                  "the draw's " + std::to_string(vs_outputs) + " vertex shader outputs (" +
                      std::to_string(assembled.fetch.size()) + " vertices × " + std::to_string(call.instanceCount) +
                      " instances × " + std::to_string(sizeof(VsOut)) + " bytes of " + typeName<VsOut>() + ")");
    draw_stats_ = {};
    const uint32_t draw_index = draw_count_++;
    const RenderProgress::DrawScope progress_scope(progress_);
    TraceDraw* trace_draw = trace_ ? &beginTraceDraw<VS, GS, PS>(draw_index, p) : nullptr;
    const bool trace_geometry = trace_draw && trace_->options().geometry;
    auto finish = [&](const PipelineStatistics& s) {
        draw_stats_ = s;
        frame_stats_ += s;
        if (draw_log_.size() < kMaxLoggedDraws) draw_log_.push_back(s);
        if (trace_draw) trace_draw->stats = s;
    };
    if (draw_index >= step_limit_.draws) {
        if (trace_draw) trace_draw->skipped = true;
        return finish({});
    }
    if (call.instanceCount == 0 || assembled.fetch.empty()) return finish({});
    PipelineStatistics stats;
    stats.iaVertices = assembled.indicesRead * call.instanceCount;
    stats.iaPrimitives = uint64_t(assembled.primitiveCount()) * call.instanceCount;
    stats.vsInvocations = vs_outputs;

    // The last stage this draw runs (StepLimit::stage applies to the step's own draw only).
    const Stage last_stage = draw_index + 1 == step_limit_.draws ? step_limit_.stage : Stage::OutputMerger;

    // ---- VS ----
    auto& vs_out = scratch<std::vector<VsOut>>();
    runVertexShader(vs, program, vertex_buffers_, assembled, call, pool_, vs_out);
    if (trace_geometry)
        detail::traceVertices<VsIn>(*trace_draw, trace_->options().maxGeometryRecords, program, vertex_buffers_,
                                    assembled, call, vs_out);
    if (last_stage == Stage::VertexShader || (!kHasGs && last_stage == Stage::GeometryShader)) return finish(stats);
    const bool setup_stage = last_stage != Stage::GeometryShader;

    // ---- GS → clip → setup → bin, in parallel over chunks of primitives ----
    const uint32_t per_instance = uint32_t(assembled.fetch.size());
    const uint32_t prims_per_instance = assembled.primitiveCount();
    const uint64_t total_prims =
        draw_index + 1 == step_limit_.draws ? std::min(stats.iaPrimitives, step_limit_.primitives) : stats.iaPrimitives;
    const uint32_t chunk_count =
        uint32_t(std::clamp<uint64_t>((total_prims + 1023) / 1024, 1, uint64_t(pool_.size()) * 8));
    const uint64_t chunk_size = (total_prims + chunk_count - 1) / chunk_count;
    auto& chunks = scratch<std::vector<detail::Chunk<Vertex>>>();
    if (chunks.size() < chunk_count) chunks.resize(chunk_count);
    const int k_in = int(assembled.kind);
    // The reference pipeline takes no shortcut: billboards stay two triangles there.
    [[maybe_unused]] const bool rectangles = !options_.reference && rasterizer_.fillMode == FillMode::Solid;
    pool_.parallelFor(chunk_count, [&](uint32_t c, unsigned) {
        detail::Chunk<Vertex>& chunk = chunks[c];
        chunk.reset(p.grid.count());
        chunk.tracing = trace_geometry;
        chunk.traceCap = trace_geometry ? trace_->options().maxGeometryRecords : 0;
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
                        if (setup_stage) clipAndSetup(kind, v, uint32_t(prim), p, rasterizer_, chunk);
                    },
                    [&](const Vertex* const* quad) {
                        return setup_stage && rectangles && setupBillboard(quad, uint32_t(prim), p, rasterizer_, chunk);
                    });
                if (overflow && !chunk.gsOverflow) chunk.gsOverflow = overflow, chunk.gsOverflowPrimitive = uint32_t(prim);
                if (chunk.tracing) {
                    for (int i = 0; i < stream->size(); ++i) {
                        if (chunk.traceGsTotal++ >= chunk.traceCap) continue;
                        const float* f = asFloats(stream->vertex(i));
                        chunk.traceGs.push_back(TraceGsVertex{uint32_t(prim), stream->startsStrip(i),
                                                              std::vector<float>(f, f + kVertexFloats<Vertex>)});
                    }
                }
            } else {
                clipAndSetup(assembled.kind, in, uint32_t(prim), p, rasterizer_, chunk);
            }
        }
    });
    for (uint32_t c = 0; c < chunk_count; ++c) {
        const detail::Chunk<Vertex>& chunk = chunks[c];
        RASTER_REQUIRE(chunk.gsOverflow == 0, ShaderError,
                       "geometry shader " + typeName<GS>() + " appended " + std::to_string(chunk.gsOverflow) +
                           " vertices past its maxvertexcount of " +
                           std::to_string(Stream::kMaxVertices) + " for primitive " +
                           std::to_string(chunk.gsOverflowPrimitive) + "; the draw was not rasterised");
        stats += chunk.stats;
        if (trace_geometry) {
            const uint32_t cap = trace_->options().maxGeometryRecords;
            for (auto& g : chunk.traceGs)
                if (trace_draw->gsVertices.size() < cap) trace_draw->gsVertices.push_back(std::move(g));
            for (const auto& t : chunk.tracePrimitives)
                if (trace_draw->primitives.size() < cap) trace_draw->primitives.push_back(t);
            trace_draw->gsVerticesTotal += chunk.traceGsTotal;
            trace_draw->primitivesTotal += chunk.tracePrimitivesTotal;
        }
    }
    if constexpr (!kHasGs) stats.gsInvocations = stats.gsPrimitives = 0;

    // ---- rasterize → PS → OM, in parallel over screen tiles ----
    if (!p.clip.empty() && last_stage == Stage::OutputMerger) {
        const DepthPolicy depth = chooseDepthPolicy(depth_stencil_, depth_, options_.reference);
        const ColorPolicy color = chooseColorPolicy(blend_, p.targets.data(), p.targetCount, options_.reference);
        if (isOrderIndependent(blend_, p.targetCount)) ++stats.sortsAvoided;
        if (!trace_draw) {
            std::visit(
                [&](const auto& d, const auto& c) {
                    using D = std::decay_t<decltype(d)>;
                    using C = std::decay_t<decltype(c)>;
                    constexpr bool kReferenceColor = std::is_same_v<C, ColorGeneric<double>>;
                    constexpr bool kReferenceDepth = std::is_same_v<D, DepthOff> || std::is_same_v<D, DepthDynamic>;
                    if constexpr (kReferenceColor && !kReferenceDepth) {
                        RASTER_CHECK(!"the reference pipeline uses only the dynamic depth policy");
                    } else {
                        renderTiles<PS, Vertex, std::conditional_t<kReferenceColor, double, float>>(
                            ps, chunks, chunk_count, p, d, c, stats, detail::NoTracer{});
                    }
                },
                depth, color);
        } else {
            // Traced: the generic depth and colour policies (the same bits as the specialised ones),
            // fragment by fragment, so that every fragment passes through the recorder.
            detail::FragmentTracer tracer;
            tracer.filter = trace_->options().pixels;
            tracer.draw = draw_index;
            tracer.color = p.targetCount > 0 ? p.targets[0] : nullptr;
            tracer.depth = depth_;
            tracer.overdraw = trace_->overdrawData();
            tracer.nonFinite = trace_->nonFiniteData();
            tracer.width = p.width;
            auto traced_depth = detail::tracingDepthPolicy(depth);
            auto traced_color = detail::tracingColorPolicy(color, blend_, p.targets.data(), p.targetCount);
            std::visit(
                [&](const auto& d, const auto& c) {
                    using C = std::decay_t<decltype(c)>;
                    constexpr bool kReferenceColor = std::is_same_v<C, ColorGeneric<double>>;
                    renderTiles<PS, Vertex, std::conditional_t<kReferenceColor, double, float>>(
                        ps, chunks, chunk_count, p, d, c, stats, tracer);
                },
                traced_depth, traced_color);
        }
    }
    finish(stats);
}

template <class VS, class GS, class PS>
TraceDraw& Context::beginTraceDraw(uint32_t draw_index, const DrawPlan& plan) {
    using VsIn = VertexShaderInput<VS>;
    using VsOut = VertexShaderOutput<VS>;
    TraceDraw& d = trace_->beginDraw(plan.width, plan.height);
    d.draw = draw_index;
    d.vertexShader = typeName<VS>();
    d.pixelShader = typeName<PS>();
    d.topology = topology_;
    d.blend = blend_;
    d.depthStencil = depth_stencil_;
    for (const ShaderInputField& f : VsIn::inputSignature())
        d.inputFields.push_back({std::string(f.semanticName) + (f.semanticIndex ? std::to_string(f.semanticIndex) : ""),
                                 f.offset / uint32_t(sizeof(float)), f.components});
    d.vsFloats = kVertexFloats<VsOut>;
    d.vsPosition = uint32_t(offsetof(VsOut, position) / sizeof(float));
    if constexpr (!std::is_same_v<GS, NoGeometryShader>) {
        using GsOut = GeometryShaderOutput<GS>;
        d.geometryShader = typeName<GS>();
        d.gsFloats = kVertexFloats<GsOut>;
        d.gsPosition = uint32_t(offsetof(GsOut, position) / sizeof(float));
    }
    return d;
}

template <class V>
bool Context::setupBillboard(const V* const* quad, uint32_t primitive_id, const DrawPlan& plan,
                             const RasterizerState& rs, detail::Chunk<V>& chunk) {
    for (int i = 0; i < 4; ++i)
        if (!isFinite(quad[i]->position) || outcode(quad[i]->position, plan.planes) != 0) return false;
    const V* const v[4] = {quad[0], quad[1], quad[2], quad[3]};
    ScreenVertex s[4];
    for (int i = 0; i < 4; ++i) s[i] = toScreen(v[i]->position, plan.viewport);
    RectSetup r;
    V base, step_x, step_y;
    bool culled = false;
    if (!setupRectangle(v, s, primitive_id, rs, plan.clip, r, base, step_x, step_y, culled)) return false;
    PipelineStatistics& st = chunk.stats;
    st.gsPrimitives += 2;
    st.cInvocations += 2;
    st.cPrimitives += 2;
    ++st.rectanglesRecognized;
    if (chunk.tracing) {
        const float w[4] = {v[0]->position.w, v[1]->position.w, v[2]->position.w, v[3]->position.w};
        chunk.trace(primitive_id, PrimitiveKind::Triangle,
                    culled ? PrimitiveFate::Culled : r.box.empty() ? PrimitiveFate::NoPixels : PrimitiveFate::Rectangle,
                    false, s, 4, w);
    }
    if (culled) {
        st.primitivesCulled += 2;
        return true;
    }
    if (r.box.empty()) {
        st.primitivesNoPixels += 2;
        return true;
    }
    r.vertex = uint32_t(chunk.vertices.size());
    chunk.vertices.push_back(base);
    chunk.vertices.push_back(step_x);
    chunk.vertices.push_back(step_y);
    const uint32_t index = uint32_t(chunk.rects.size());
    chunk.rects.push_back(r);
    st.tilesBinned += binBox(r.box, plan.grid, [&](uint32_t tile) {
        chunk.bins[tile].push_back(binEntry(BinKind::Rectangle, index));
    });
    return true;
}

template <class V>
void Context::clipAndSetup(PrimitiveKind kind, const V* const* v, uint32_t primitive_id, const DrawPlan& plan,
                           const RasterizerState& rs, detail::Chunk<V>& chunk) {
    PipelineStatistics& st = chunk.stats;
    ++st.cInvocations;
    const int n = int(kind);
    uint32_t all = ~0u, any = 0;
    for (int i = 0; i < n; ++i) {
        if (!isFinite(v[i]->position)) {
            ++st.primitivesNonFinite;
            chunk.trace(primitive_id, kind, PrimitiveFate::NonFinite, false, nullptr, 0);
            return;
        }
        const uint32_t code = outcode(v[i]->position, plan.planes);
        all &= code;
        any |= code;
    }
    if (all != 0) {
        ++st.primitivesOutside;
        chunk.trace(primitive_id, kind, PrimitiveFate::Outside, false, nullptr, 0);
        return;
    }
    const uint32_t cut = any & kClipPlanesMask;
    if (kind == PrimitiveKind::Point && cut != 0) {
        ++st.primitivesOutside;
        chunk.trace(primitive_id, kind, PrimitiveFate::Outside, false, nullptr, 0);
        return;
    }

    auto setupLine = [&](const ScreenVertex (&s)[2], const uint32_t (&idx)[2]) {
        LineSetup l;
        if (!raster::setupLine(s, idx, primitive_id, plan.clip, l)) {
            ++st.primitivesNoPixels;
            chunk.trace(primitive_id, PrimitiveKind::Line, PrimitiveFate::NoPixels, cut != 0, s, 2);
            return;
        }
        chunk.trace(primitive_id, PrimitiveKind::Line, PrimitiveFate::Rasterized, cut != 0, s, 2);
        const uint32_t index = uint32_t(chunk.lines.size());
        chunk.lines.push_back(l);
        st.tilesBinned += binBox(l.box, plan.grid, [&](uint32_t tile) {
            chunk.bins[tile].push_back(binEntry(PrimitiveKind::Line, index));
        });
    };
    auto emit = [&](const V* const* pv) {
        ++st.cPrimitives;
        const uint32_t base = uint32_t(chunk.vertices.size());
        ScreenVertex s[3];
        uint32_t idx[3];
        for (int i = 0; i < n; ++i) {
            chunk.vertices.push_back(*pv[i]);
            s[i] = toScreen(pv[i]->position, plan.viewport);
            idx[i] = base + uint32_t(i);
        }
        if (kind == PrimitiveKind::Triangle && rs.fillMode == FillMode::Wireframe) {
            TriangleSetup t;  // for culling only
            const SetupResult r = setupTriangle(s, idx, primitive_id, rs, plan.clip, t);
            if (r == SetupResult::Culled) ++st.primitivesCulled;
            if (r == SetupResult::Culled || r == SetupResult::Degenerate) {
                chunk.trace(primitive_id, kind, r == SetupResult::Culled ? PrimitiveFate::Culled : PrimitiveFate::Degenerate,
                            cut != 0, s, 3);
                return;
            }
            for (int e = 0; e < 3; ++e) {
                const int e1 = (e + 1) % 3;
                setupLine({s[e], s[e1]}, {idx[e], idx[e1]});
            }
            return;
        }
        switch (kind) {
            case PrimitiveKind::Triangle: {
                TriangleSetup t;
                const SetupResult result = setupTriangle(s, idx, primitive_id, rs, plan.clip, t);
                if (chunk.tracing) {
                    constexpr PrimitiveFate kFates[] = {PrimitiveFate::Rasterized, PrimitiveFate::Culled,
                                                        PrimitiveFate::Degenerate, PrimitiveFate::NoPixels};
                    chunk.trace(primitive_id, kind, kFates[int(result)], cut != 0, s, 3);
                }
                switch (result) {
                    case SetupResult::Culled: ++st.primitivesCulled; break;
                    case SetupResult::Degenerate: ++st.primitivesDegenerate; break;
                    case SetupResult::NoPixels: ++st.primitivesNoPixels; break;
                    case SetupResult::Ok: {
                        const uint32_t index = uint32_t(chunk.triangles.size());
                        chunk.triangles.push_back(t);
                        binTriangle(
                            t, plan.grid,
                            [&](uint32_t tile) { chunk.bins[tile].push_back(binEntry(PrimitiveKind::Triangle, index)); },
                            st.tilesBinned, st.tilesRejected);
                        return;
                    }
                }
                chunk.vertices.resize(base);
                return;
            }
            case PrimitiveKind::Line: setupLine({s[0], s[1]}, {idx[0], idx[1]}); return;
            case PrimitiveKind::Point: {
                PointSetup pt;
                const bool has_pixels = setupPoint(s[0], idx[0], primitive_id, plan.clip, pt);
                chunk.trace(primitive_id, kind, has_pixels ? PrimitiveFate::Rasterized : PrimitiveFate::NoPixels,
                            cut != 0, s, 1);
                if (!has_pixels) {
                    ++st.primitivesNoPixels;
                    chunk.vertices.resize(base);
                    return;
                }
                const uint32_t index = uint32_t(chunk.points.size());
                chunk.points.push_back(pt);
                const PixelRect box{pt.px, pt.py, pt.px, pt.py};
                st.tilesBinned += binBox(box, plan.grid, [&](uint32_t tile) {
                    chunk.bins[tile].push_back(binEntry(PrimitiveKind::Point, index));
                });
                return;
            }
        }
    };
    if (cut == 0) {
        emit(v);
        return;
    }
    ++st.primitivesClipped;
    if (kind == PrimitiveKind::Triangle) {
        const V* const tri[3] = {v[0], v[1], v[2]};
        clipPrimitive<3>(tri, cut, plan.planes, emit);
    } else {
        const V* const line[2] = {v[0], v[1]};
        clipPrimitive<2>(line, cut, plan.planes, emit);
    }
}

namespace detail {

// Sets the calling thread's reference-mode flag for the lifetime of the guard.
struct ReferenceModeGuard {
    bool saved;
    explicit ReferenceModeGuard(bool on) : saved(tReferenceMode) { tReferenceMode = on; }
    ~ReferenceModeGuard() { tReferenceMode = saved; }
};

}  // namespace detail

namespace detail {
// A copy of a trivially copyable shader (by reference otherwise: a shader that owns resources is
// still called, only without the copy's benefit).
template <class PS>
struct WideShaderCopy {
    std::conditional_t<std::is_trivially_copyable_v<PS>, PS, const PS&> value;
    explicit WideShaderCopy(const PS& ps) : value(ps) {}
    template <class In>
    [[gnu::always_inline]] auto operator()(const In& in) const {
        return value(in);
    }
};

// Two neighbouring blocks' inputs as one Float8x2 input, the left block in half 0.
template <class V>
[[gnu::always_inline]] inline WidePair<V> zipBlocks(const Wide<V>& left, const Wide<V>& right) {
    constexpr uint32_t kN = kVertexFloats<V>;
    Float8 l[kN], r[kN];
    std::memcpy(l, static_cast<const void*>(&left), sizeof l);
    std::memcpy(r, static_cast<const void*>(&right), sizeof r);
    Float8x2 f[kN];
    for (uint32_t k = 0; k < kN; ++k) f[k] = Float8x2(l[k], r[k]);
    WidePair<V> out;
    static_assert(sizeof out == sizeof f);
    std::memcpy(static_cast<void*>(&out), f, sizeof f);
    return out;
}
// Block h (0 left, 1 right) of a Float8x2 shader's colour.
inline glm::vec<4, Float8> blockOf(const glm::vec<4, Float8x2>& c, int h) {
    return {c.x.h[h], c.y.h[h], c.z.h[h], c.w.h[h]};
}
}  // namespace detail

template <class PS, class V, class Real, class Tracer, class Depth, class Color>
void Context::renderTiles(const PS& ps, std::vector<detail::Chunk<V>>& chunks, uint32_t chunk_count,
                          const DrawPlan& plan, const Depth& depth, const Color& color, PipelineStatistics& stats,
                          const Tracer& tracer_prototype) {
    using Out = PixelShaderOutput<PS>;
    // The reference pipeline tests depth after the shader, in D3D's literal order; the fast one
    // before it (the result is the same: shaders here cannot write depth).
    constexpr bool kEarlyDepth = std::is_same_v<Real, float>;
    constexpr bool kWide = [] {
        if constexpr (WidePixelShader<PS>)
            return std::is_same_v<Real, float> && std::is_same_v<Out, glm::vec4> && !Tracer::kEnabled;
        else
            return false;
    }();
    // Billboards shade two neighbouring blocks per call where the shader takes Float8x2 (shadePair).
    constexpr bool kPairs = [] {
        if constexpr (PairPixelShader<PS>)
            return kWide;
        else
            return false;
    }();
    // Opaque draws with depth writes may be shaded deferred (shadeDeferred below).
    constexpr bool kDeferrable = [] {
        if constexpr (requires { Depth::kWrite; })
            return kWide && Depth::kWide && Color::kWide && Depth::kEnabled && Depth::kWrite &&
                   std::is_same_v<Color, ColorFast<BlendReplaceRgba8>>;
        else
            return false;
    }();
    // Billboard pixels known to be transparent before shading are skipped (transparency.hpp).
    constexpr bool kSkipTransparent = kWide && detail::kSkipsTransparent<PS, Depth, Color>;
    [[maybe_unused]] detail::TransparentColumns transparent_columns;
    if constexpr (kSkipTransparent) transparent_columns = detail::TransparentColumns(ps.alphaSource());
    const float min_depth = plan.viewport.minDepth, max_depth = plan.viewport.maxDepth;
    // One cache line or more per thread, so that the counters of two threads never share one.
    struct alignas(64) ThreadStatistics {
        PipelineStatistics s;
    };
    std::vector<ThreadStatistics> per_thread(pool_.size());
    [[maybe_unused]] std::vector<std::vector<TraceFragment>> traced_tiles(Tracer::kEnabled ? plan.grid.count() : 0);
    RenderProgress* const progress = progress_;
    if (progress) progress->beginTiles(plan.grid.count());
    pool_.parallelFor(plan.grid.count(), [&](uint32_t tile, unsigned thread) {
        PipelineStatistics& st = per_thread[thread].s;
        const PixelRect rect = plan.grid.tileRect(tile);
        detail::ReferenceModeGuard reference(std::is_same_v<Real, double>);
        QuadShader<PS> shader(ps);
        // The eight-wide paths call a copy of the shader that lives on this thread's stack and whose
        // address stays inside the inlined loop: the compiler may then keep the shader's constants
        // (and what it computes from them alone) in registers across the blocks, which it cannot do
        // through `ps`, since a store to the targets might, for all it knows, change `ps`.
        [[maybe_unused]] const detail::WideShaderCopy<PS> wide_shader(ps);
        [[maybe_unused]] Tracer tracer = tracer_prototype;

        // Whole primitives in front of nothing: true when a primitive whose nearest depth is
        // `nearest` fails the depth test everywhere in this tile (see DepthFixed::kBoundsTile).
        // Not while tracing, so that a pixel's history shows the fragments the test rejected.
        [[maybe_unused]] float tile_far = 0.0f;
        [[maybe_unused]] bool tile_far_known = false;
        auto occludedInTile = [&]([[maybe_unused]] float nearest) {
            if constexpr (requires { Depth::kBoundsTile; }) {
                if constexpr (Depth::kBoundsTile && !Tracer::kEnabled) {
                    if (!tile_far_known) tile_far = depth.farthest(rect), tile_far_known = true;
                    if (Depth::occluded(nearest, tile_far)) {
                        ++st.tilesOccluded;
                        return true;
                    }
                }
            }
            return false;
        };

        // Whole primitives in front of everything: under a draw that writes no depth, the tile's
        // nearest stored depth stays put, so a rectangle of one depth in front of it passes the
        // depth test in every pixel and its blocks need no test. The same per row pair of the tile
        // (rows y, y + 1 for even y) for rectangles not in front of the whole tile: a row pair they
        // are in front of needs no depth test, and its skipped transparent lanes no counting block by
        // block (PERFORMANCE.md, stop 27). Both from one pass over the tile's depth, once per tile
        // and draw: the tile's nearest is the least of its row pairs' (−∞ if any entry is NaN).
        [[maybe_unused]] float tile_near = 0.0f;
        [[maybe_unused]] float row_near[kTileSize / 2 + 1];
        [[maybe_unused]] bool near_known = false;
        [[maybe_unused]] const int32_t first_row_pair = rect.y0 & ~1;
        [[maybe_unused]] auto knowNear = [&] {
            if constexpr (requires { depth.nearest(rect); }) {
                if (near_known) return;
                tile_near = std::numeric_limits<float>::infinity();
                for (int32_t p = 0, y = first_row_pair; y <= rect.y1; y += 2, ++p) {
                    row_near[p] =
                        depth.nearest(PixelRect{rect.x0, std::max(y, rect.y0), rect.x1, std::min(y + 1, rect.y1)});
                    tile_near = std::min(tile_near, row_near[p]);
                }
                near_known = true;
            }
        };
        auto inFrontInTile = [&]([[maybe_unused]] float z) {
            if constexpr (requires { Depth::kBoundsTile; }) {
                if constexpr (Depth::kBoundsTile && !Depth::kWrite && !Tracer::kEnabled) {
                    knowNear();
                    return Depth::passesAll(z, tile_near);
                }
            }
            return false;
        };
        [[maybe_unused]] auto inFrontInRows = [&]([[maybe_unused]] float z, [[maybe_unused]] int32_t y) {
            if constexpr (requires { Depth::kBoundsTile; }) {
                if constexpr (Depth::kBoundsTile && !Depth::kWrite && !Tracer::kEnabled) {
                    knowNear();
                    return Depth::passesAll(z, row_near[(y - first_row_pair) >> 1]);
                }
            }
            return false;
        };

        // A depth no fragment of triangle t lies in front of: interpolated depths stay within the
        // vertices' (to double rounding, far below the 2^-20 margin) and are clamped to the viewport.
        auto nearestDepth = [&](const TriangleSetup& t) {
            const float lowest = std::min({t.z[0], t.z[1], t.z[2]});
            return std::clamp(lowest - std::abs(lowest) * 0x1p-20f, min_depth, max_depth);
        };

        // The output merger for one shaded fragment.
        auto mergeFragment = [&](int32_t x, int32_t y, Real z, const Out& out) {
            if (isDiscarded(out)) {
                ++st.fragmentsDiscarded;
                return FragmentFate::Discarded;
            }
            if constexpr (!kEarlyDepth && Depth::kEnabled) {
                if (!depth.test(x, y, float(z))) {
                    ++st.fragmentsLateDepthKilled;
                    return FragmentFate::LateDepthFailed;
                }
            }
            depth.write(x, y, float(z));
            const auto& colors = colorsOf(out);
            if (color.isNoOp(colors)) {
                ++st.fragmentsBlendNoOp;
                return FragmentFate::BlendNoOp;
            }
            color.write(x, y, colors);
            return FragmentFate::Written;
        };
        auto merge = [&](int32_t x, int32_t y, Real z, const Out& out) {
            if constexpr (Tracer::kEnabled) {
                glm::vec4 target0(0.0f);
                if (!isDiscarded(out)) {
                    const auto& colors = colorsOf(out);
                    target0 = detail::ColorTraits<std::decay_t<decltype(colors)>>::color(colors, 0);
                }
                const size_t record = tracer.open(x, y, float(z), !isDiscarded(out), target0);
                tracer.close(record, mergeFragment(x, y, z, out));
            } else {
                mergeFragment(x, y, z, out);
            }
        };
        auto earlyDepthPasses = [&](int32_t x, int32_t y, Real z) {
            if constexpr (Tracer::kEnabled) tracer.covered(x, y);
            if constexpr (kEarlyDepth && Depth::kEnabled) {
                if (!depth.test(x, y, float(z))) {
                    ++st.fragmentsEarlyDepthKilled;
                    if constexpr (Tracer::kEnabled)
                        tracer.close(tracer.open(x, y, float(z), false, glm::vec4(0.0f)), FragmentFate::EarlyDepthFailed);
                    return false;
                }
            }
            return true;
        };

        // One 2×2 quad: depth_at(lane) gives a lane's depth, fill(lane, z, in) its shader input
        // (also for helper lanes, which may lie outside the primitive).
        auto shadeQuad = [&](int32_t qx, int32_t qy, uint32_t mask, auto&& depth_at, auto&& fill) {
            V in[4];
            Out out[4];
            Real z[4];
            uint32_t live = 0;
            for (uint32_t m = mask; m; m &= m - 1) {
                const int lane = std::countr_zero(m);
                z[lane] = depth_at(lane);
                if (!earlyDepthPasses(qx + (lane & 1), qy + (lane >> 1), z[lane])) continue;
                fill(lane, z[lane], in[lane]);
                live |= 1u << lane;
            }
            if (!live) return;
            st.psInvocations += uint64_t(std::popcount(live));
            shader.shade(
                in, live, out, [&](int lane, V& helper) { fill(lane, depth_at(lane), helper); }, st);
            for (uint32_t m = live; m; m &= m - 1) {
                const int lane = std::countr_zero(m);
                merge(qx + (lane & 1), qy + (lane >> 1), z[lane], out[lane]);
            }
        };

        // A rectangle (billboard) with a shader that runs eight wide: 4×2 blocks, one call each, or
        // two neighbouring blocks per call where the shader also takes Float8x2 (shadePair).
        // The same arithmetic as the scalar path lane by lane, so the same bits.
        // in_front: the rectangle passes the depth test in every pixel of the tile (inFrontInTile).
        // A copy of the loop each way (one function, flattened: a template lambda of its own was not
        // inlined whole): in front, a block has no depth test and its lanes need no counting (they
        // all pass; the shaded ones are what the skips leave), which measured 4–6 % of the 100 000-
        // particle frame as per-block popcounts (PERFORMANCE.md).
        [[maybe_unused]] auto shadeRectWide = [&](const RectSetup& r, const float* base, const float* step_x,
                                                  const float* step_y, Real z, bool in_front) RASTER_FLATTEN {
            auto loop = [&]<class InFront>(InFront) {
                if constexpr (kWide) {
                    // Every lane of the rectangle in the tile passes the depth test.
                    constexpr bool kAllPass = InFront::value || !(Depth::kEnabled && Depth::kWide);
                    constexpr uint32_t kN = kVertexFloats<V>;
                    // What every block reads, in locals: the targets are written through uint8_t and float
                    // pointers, which may alias anything, so through `rect`, `base` or `depth` the compiler
                    // would load it again for every block.
                    const PixelRect tile = rect;
                    [[maybe_unused]] const Depth depth_here = depth;
                    [[maybe_unused]] const Color color_here = color;
                    // The shader too: its texture pointer and sampler then stay in registers.
                    const auto shader_here = wide_shader;
                    const int32_t x0 = std::max(r.box.x0, tile.x0), x1 = std::min(r.box.x1, tile.x1);
                    const int32_t y0 = std::max(r.box.y0, tile.y0), y1 = std::min(r.box.y1, tile.y1);
                    const int32_t bx = r.box.x0, by = r.box.y0;
                    Float8 plane[kN], plane_x[kN], plane_y[kN];
                    for (uint32_t k = 0; k < kN; ++k)
                        plane[k] = Float8(base[k]), plane_x[k] = Float8(step_x[k]),
                        plane_y[k] = Float8(step_y[k]);
                    const Float8 lane_x(simd::F32x8{0, 1, 2, 3, 0, 1, 2, 3});
                    const Float8 lane_y(simd::F32x8{0, 0, 0, 0, 1, 1, 1, 1});
                    const Float8 z8 = Float8(float(z));
                    // Statistics in locals, per block only what cannot be counted per rectangle: blocks
                    // shaded, their live lanes, their no-op lanes, lanes skipped at the blend's ceiling.
                    // Helpers = 8·blocks − live; lanes the early depth test killed = lanes of blocks
                    // taken whole − the lanes of those blocks that passed it. With kAllPass every lane
                    // of a block taken whole passes, and the live lanes of the shaded ones are the rest
                    // after the transparent and ceiling skips: neither is counted per block.
                    uint64_t blocks = 0, live_lanes = 0, no_ops = 0, ceiling = 0, whole_lanes = 0, passed = 0,
                             transparent = 0;
                    // attribute = (base + i·step_x) + j·step_y, the scalar path's order; j·step_y per row.
                    auto rowPart = [&](int32_t y, Float8(&row_part)[kN]) {
                        const Float8 j = Float8(float(y - by)) + lane_y;
                        for (uint32_t k = 0; k < kN; ++k) row_part[k] = j * plane_y[k];
                    };
                    auto inputs = [&](int32_t x, const Float8(&row_part)[kN]) {
                        const Float8 i = Float8(float(x - bx)) + lane_x;
                        Float8 f[kN];
                        for (uint32_t k = 0; k < kN; ++k) f[k] = plane[k] + i * plane_x[k] + row_part[k];
                        Wide<V> in;
                        static_assert(sizeof in == sizeof f);
                        std::memcpy(static_cast<void*>(&in), f, sizeof f);
                        return in;
                    };
                    // A shaded block's live lanes into depth and colour, counted (targets with an
                    // eight-wide merge only).
                    [[maybe_unused]] auto mergeBlock = [&](int32_t x, int32_t y, const glm::vec<4, Float8>& c,
                                                           uint32_t live) {
                        if constexpr (Depth::kWide && Color::kWide) {
                            if constexpr (!kAllPass) live_lanes += uint64_t(std::popcount(live));
                            depth_here.writeWide(x, y, z8, live);
                            no_ops += uint64_t(std::popcount(color_here.noOpWide(c) & live));
                            // Every block is written, no-op lanes too (they add zero): a block wholly inside
                            // the rectangle is then stored without a lane select, and a block whose lanes
                            // are all no-ops (texels of alpha 0, a third of the particle scene's) costs a
                            // blend, not the mispredicted branch that skipped it (PERFORMANCE.md: −3 %).
                            color_here.writeWide(x, y, c, live);
                        }
                    };
                    // mergeBlock for blocks x and x + 4 of a pair, the colour in one 16-lane blend where
                    // the target has one (ColorFast::writeWidePair). Why: the pair sampler's 16-lane
                    // result then stays in its register, which two eight-lane blends split (PERFORMANCE.md,
                    // stop 29).
                    [[maybe_unused]] auto mergePair = [&](int32_t x, int32_t y,
                                                          const glm::vec<4, Float8x2>& c, uint32_t live0,
                                                          uint32_t live1) {
                        if constexpr (Depth::kWide && Color::kWide && Color::kWidePair) {
                            const uint32_t live = live0 | (live1 << 8);
                            if constexpr (!kAllPass) live_lanes += uint64_t(std::popcount(live));
                            depth_here.writeWide(x, y, z8, live0);
                            depth_here.writeWide(x + 4, y, z8, live1);
                            no_ops += uint64_t(std::popcount(color_here.writeWidePair(x, y, c, live) & live));
                        } else {
                            mergeBlock(x, y, detail::blockOf(c, 0), live0);
                            mergeBlock(x + 4, y, detail::blockOf(c, 1), live1);
                        }
                    };
                    // The lanes of a block inside the tile in `covered` that pass the depth test, counted
                    // (without kAllPass; with it, all of them, counted per rectangle).
                    // Without kAllPass, whether the row pair being shaded is in front of its pixels
                    // (inFrontInRows); false where row pairs are not looked up.
                    [[maybe_unused]] bool rows_in_front = false;
                    [[maybe_unused]] auto passing = [&](int32_t x, int32_t y, uint32_t covered) -> uint32_t {
                        uint32_t live = covered;
                        // Depth::kWide first, which kAllPass implies when false: the test inside names
                        // testWide, which not every Depth has, and clang rejects it in a discarded
                        // branch whose condition depends on InFront (ill-formed, no diagnostic required).
                        if constexpr (Depth::kWide) {
                            if constexpr (!kAllPass) {
                                if (!rows_in_front) live &= depth_here.testWide(x, y, z8);
                                passed += uint64_t(std::popcount(live));
                            }
                        }
                        return live;
                    };
                    // Blocks whose pixels are all at the blend's ceiling are not shaded, their live lanes
                    // counted. Why: dense additive particles saturate the middle of the cloud, and every
                    // fragment after that changes nothing (100 000 particles at 1080p: 11 % of the
                    // fragments; PERFORMANCE.md). Tested after depth, so that the counts add up to the
                    // traced draw's, which shades every fragment.
                    [[maybe_unused]] auto skipped = [&](bool at_ceiling, uint32_t lanes) {
                        if (at_ceiling) ceiling += uint64_t(std::popcount(lanes));
                        return at_ceiling;
                    };
                    // One block inside the tile whose live lanes are known: shaded and merged unless at the
                    // ceiling.
                    [[maybe_unused]] auto shadeLive = [&](int32_t x, int32_t y, uint32_t live,
                                                          const Float8(&row_part)[kN]) {
                        if constexpr (Depth::kWide && Color::kWide) {
                            if constexpr (Color::kCeiling)
                                if (skipped(color_here.template atCeiling<1>(x, y), live)) return;
                            ++blocks;
                            mergeBlock(x, y, shader_here(inputs(x, row_part)), live);
                        }
                    };
                    // One block inside the tile through depth, shader and blend at once, its lanes outside
                    // the rectangle (not in `covered`) masked off.
                    [[maybe_unused]] auto shadeBlock = [&](int32_t x, int32_t y, uint32_t covered,
                                                           const Float8(&row_part)[kN]) {
                        if (const uint32_t live = passing(x, y, covered)) shadeLive(x, y, live, row_part);
                    };
                    // Blocks x and x + 4 of a row pair inside the tile through one Float8x2 call when both
                    // have live lanes (else each alone); the same bits as shadeBlock on each. Why: a
                    // block's texture fetch is one long dependency chain, and two of them interleaved keep
                    // the core busy where one leaves it waiting (PERFORMANCE.md).
                    [[maybe_unused]] auto shadePair = [&](int32_t x, int32_t y, uint32_t covered0,
                                                          uint32_t covered1, const Float8(&row_part)[kN]) {
                        if constexpr (Depth::kWide && Color::kWide && kPairs) {
                            const uint32_t live0 = passing(x, y, covered0),
                                           live1 = passing(x + 4, y, covered1);
                            if (!live0 || !live1) {
                                if (live0) shadeLive(x, y, live0, row_part);
                                if (live1) shadeLive(x + 4, y, live1, row_part);
                                return;
                            }
                            // Both blocks at once (one branch, not two): a pair with one block at the ceiling
                            // is shaded whole, which stores that block unchanged.
                            if constexpr (Color::kCeiling)
                                if (skipped(color_here.template atCeiling<2>(x, y), live0 | (live1 << 8)))
                                    return;
                            const glm::vec<4, Float8x2> c2 = shader_here(
                                detail::zipBlocks<V>(inputs(x, row_part), inputs(x + 4, row_part)));
                            blocks += 2;
                            mergePair(x, y, c2, live0, live1);
                        }
                    };
                    // The lanes of row pair y inside the rectangle: the top row's (0x0F) if y ≥ y0, the
                    // bottom row's (0xF0) if y + 1 ≤ y1.
                    auto rowLanes = [&](int32_t y) {
                        return (y >= y0 ? 0x0Fu : 0u) | (y + 1 <= y1 ? 0xF0u : 0u);
                    };
                    bool done = false;
                    if constexpr (Depth::kWide && Color::kWide) {
                        // Every 4×2 block of the rectangle inside the tile (always, but at a target or
                        // scissor edge that is not a multiple of 4×2): one loop, no per-block tests but
                        // depth. The columns a block covers depend on x alone, so they are found once.
                        const int32_t bx0 = x0 & ~3, by0 = y0 & ~1;
                        if (x0 <= x1 && y0 <= y1 && bx0 >= tile.x0 && (x1 | 3) <= tile.x1 && by0 >= tile.y0 &&
                            (y1 | 1) <= tile.y1) {
                            constexpr int kMaxBlocks = kTileSize / 4 + 1;
                            uint8_t columns[kMaxBlocks];
                            const int n_blocks = (x1 - bx0) / 4 + 1;
                            RASTER_DCHECK(n_blocks <= kMaxBlocks);
                            for (int k = 0; k < n_blocks; ++k)
                                columns[k] = uint8_t(blockColumns(bx0 + 4 * k, x0, x1));
                            // The blocks of each row pair that may not be transparent, [k_begin, k_end),
                            // found for all row pairs before any is shaded (four at a time,
                            // TransparentColumns::rowPairs): each is a chain of dependent operations (texel
                            // rows, spans, columns) that the shading loop would wait for at every row pair.
                            constexpr int kMaxRowPairs = kTileSize / 2 + 1;
                            [[maybe_unused]] uint8_t k_begins[kMaxRowPairs], k_ends[kMaxRowPairs];
                            [[maybe_unused]] bool row_fronts[kMaxRowPairs];
                            [[maybe_unused]] bool spans = false;
                            if constexpr (kSkipTransparent) {
                                const detail::TransparentColumns& tc = transparent_columns;
                                const auto planes =
                                    tc.planes(base, step_x, step_y, r.box.x1 - bx + 1, r.box.y1 - by + 1);
                                if (planes.usable) {
                                    const int n_pairs = (y1 - by0) / 2 + 1;
                                    RASTER_DCHECK(n_pairs <= kMaxRowPairs);
                                    spans = true;
                                    constexpr int kRoom =
                                        kMaxRowPairs + detail::TransparentColumns::kRowPairsPadding;
                                    int32_t los[kRoom], his[kRoom];
                                    // The columns of [x0, x1] in blocks [0, k).
                                    const int32_t width = x1 - x0 + 1;
                                    [[maybe_unused]] auto columnsBefore = [&](int k) {
                                        return std::clamp(bx0 + 4 * k - x0, 0, width);
                                    };
                                    tc.rowPairs(planes, by0 - by, n_pairs, x0 - bx, x1 - bx, los, his);
                                    for (int32_t y = by0, p = 0; y <= y1; y += 2, ++p) {
                                        const int32_t lo = los[p], hi = his[p];
                                        const int kb = lo > hi ? n_blocks : (lo + bx - bx0) >> 2;
                                        const int ke = lo > hi ? n_blocks : ((hi + bx - bx0) >> 2) + 1;
                                        k_begins[p] = uint8_t(kb), k_ends[p] = uint8_t(ke);
                                        // The skipped blocks' lanes that pass the depth test, counted: in
                                        // front of the row pair's pixels from the span's ends (the columns
                                        // of [x0, x1] outside blocks [kb, ke), times the rows), else block
                                        // by block.
                                        bool front = kAllPass;
                                        if constexpr (!kAllPass)
                                            front = row_fronts[p] = inFrontInRows(float(z), y);
                                        if (front) {
                                            const int32_t n_rows = std::popcount(rowLanes(y)) / 4;
                                            const int32_t outside =
                                                columnsBefore(kb) + width - columnsBefore(std::max(kb, ke));
                                            transparent += uint64_t(n_rows * outside);
                                            if constexpr (!kAllPass) passed += uint64_t(n_rows * outside);
                                        } else {
                                            const uint32_t rows = rowLanes(y);
                                            auto count = [&](int s0, int s1) {
                                                for (int s = s0; s < s1; ++s)
                                                    transparent += std::popcount(
                                                        passing(bx0 + 4 * s, y, rows & columns[s]));
                                            };
                                            count(0, kb);
                                            count(std::max(kb, ke), n_blocks);
                                        }
                                    }
                                }
                            }
                            for (int32_t y = by0, p = 0; y <= y1; y += 2, ++p) {
                                const uint32_t rows = rowLanes(y);
                                int k = 0, k_end = n_blocks;
                                if constexpr (kSkipTransparent)
                                    if (spans) k = k_begins[p], k_end = k_ends[p];
                                if (k >= k_end) continue;  // all transparent: no row part to compute
                                if constexpr (!kAllPass) {
                                    if constexpr (kSkipTransparent)
                                        rows_in_front = spans ? row_fronts[p] : inFrontInRows(float(z), y);
                                    else
                                        rows_in_front = inFrontInRows(float(z), y);
                                }
                                Float8 row_part[kN];
                                rowPart(y, row_part);
                                if constexpr (kPairs)
                                    for (; k + 1 < k_end; k += 2)
                                        shadePair(bx0 + 4 * k, y, rows & columns[k], rows & columns[k + 1],
                                                  row_part);
                                for (; k < k_end; ++k)
                                    shadeBlock(bx0 + 4 * k, y, rows & columns[k], row_part);
                            }
                            whole_lanes += uint64_t(x1 - x0 + 1) * uint64_t(y1 - y0 + 1);
                            done = true;
                        }
                    }
                    rows_in_front = false;
                    if (!done)
                        for (int32_t y = y0 & ~1; y <= y1; y += 2) {
                            const uint32_t rows = rowLanes(y);
                            Float8 row_part[kN];
                            rowPart(y, row_part);
                            const bool rows_in_tile = y >= tile.y0 && y + 1 <= tile.y1;
                            for (int32_t x = x0 & ~3; x <= x1; x += 4) {
                                if constexpr (Depth::kWide && Color::kWide) {
                                    if (rows_in_tile && x >= tile.x0 && x + 3 <= tile.x1) {
                                        const uint32_t covered = rows & blockColumns(x, x0, x1);
                                        whole_lanes += uint64_t(std::popcount(covered));
                                        shadeBlock(x, y, covered, row_part);
                                        continue;
                                    }
                                }
                                // Lane by lane: blocks that straddle the tile's edge, and targets or shaders
                                // without an eight-wide merge.
                                uint32_t live = 0;
                                for (int l = 0; l < 8; ++l) {
                                    const int32_t px = x + (l & 3), py = y + (l >> 2);
                                    if (px >= x0 && px <= x1 && py >= y0 && py <= y1 &&
                                        earlyDepthPasses(px, py, z))
                                        live |= 1u << l;
                                }
                                if (!live) continue;
                                const glm::vec<4, Float8> c = shader_here(inputs(x, row_part));
                                ++blocks;
                                live_lanes += uint64_t(std::popcount(live));
                                for (uint32_t m = live; m; m &= m - 1) {
                                    const int l = std::countr_zero(m);
                                    merge(x + (l & 3), y + (l >> 2), z,
                                          glm::vec4(c.x[l], c.y[l], c.z[l], c.w[l]));
                                }
                            }
                        }
                    if constexpr (kAllPass)
                        live_lanes += whole_lanes - transparent - ceiling, passed = whole_lanes;
                    st.psInvocations += live_lanes;
                    st.helperInvocations += 8 * blocks - live_lanes;
                    st.fragmentsEarlyDepthKilled += whole_lanes - passed;
                    st.fragmentsBlendNoOp += no_ops;
                    st.fragmentsBlendSaturated += ceiling;
                    st.fragmentsTransparentSkipped += transparent;
                }
            };
            if (in_front)
                loop(std::true_type{});
            else
                loop(std::false_type{});
        };

        // One 4×2 block's inputs through an eight-wide shader, its invocations (lanes in `live`) and
        // helper lanes counted.
        [[maybe_unused]] auto shadeInputWide = [&](const auto& shader, const auto& in, uint32_t live) {
            const glm::vec<4, Float8> c = shader(in);
            const int n = std::popcount(live);
            st.psInvocations += uint64_t(n);
            st.helperInvocations += uint64_t(8 - n);
            return c;
        };
        // One 4×2 block of a triangle through an eight-wide shader: its attributes interpolated, then
        // shadeInputWide.
        [[maybe_unused]] auto shadeBlockWide = [&](const auto& shader, const TriangleInterpolant<Real>& ti,
                                                   const int64_t (&e)[3][8], const auto& verts, int32_t x, int32_t y,
                                                   Float8 z, uint32_t live) {
            Wide<std::remove_cvref_t<decltype(*verts[0])>> in;
            interpolateAttributesWide(ti, e, verts, x, y, z, in);
            return shadeInputWide(shader, in, live);
        };
        // Two such blocks of one triangle, interpolated already, through one Float8x2 call (the same
        // bits as a call each): two shaders' dependency chains interleaved (see shadeRectWide).
        [[maybe_unused]] auto shadePairWide = [&](const auto& shader, const auto& left, const auto& right,
                                                  uint32_t live_left, uint32_t live_right) {
            const glm::vec<4, Float8x2> c = shader(detail::zipBlocks<V>(left, right));
            const int n = std::popcount(live_left) + std::popcount(live_right);
            st.psInvocations += uint64_t(n);
            st.helperInvocations += uint64_t(16 - n);
            return c;
        };

        // A triangle with a shader that runs eight wide: 4×2 blocks wholly inside the tile go
        // through depth, shader and blend at once; blocks on the tile's border go quad by quad.
        [[maybe_unused]] auto shadeTriangleWide = [&](const TriangleSetup& t, const TriangleInterpolant<Real>& ti,
                                                      const EdgeSteps& steps,
                                                      const V* const (&verts)[3]) RASTER_FLATTEN {
            if constexpr (kWide && Depth::kWide && Color::kWide) {
                // Locals, as in shadeRectWide: stores to the targets would otherwise reload them.
                const PixelRect tile = rect;
                const Depth depth_here = depth;
                const Color color_here = color;
                const auto shader_here = wide_shader;
                auto finishBlock = [&](int32_t x, int32_t y, Float8 z, uint32_t live, const glm::vec<4, Float8>& c) {
                    depth_here.writeWide(x, y, z, live);
                    const uint32_t noop = color_here.noOpWide(c) & live;
                    st.fragmentsBlendNoOp += uint64_t(std::popcount(noop));
                    if (live & ~noop) color_here.writeWide(x, y, c, live & ~noop);
                };
                // With a Float8x2 shader an inner block waits, interpolated, for the rasteriser's next
                // block: if that is its right neighbour, the two are shaded in one call (shadePairWide).
                // Blocks of one triangle cover distinct pixels, so delaying one's tests and writes past
                // its neighbour's changes no bit.
                struct Waiting {
                    bool held;
                    int32_t x, y;
                    uint32_t live;
                    Float8 z;
                    Wide<V> in;
                };
                [[maybe_unused]] Waiting waiting{};
                [[maybe_unused]] auto flush = [&] {
                    if constexpr (kPairs) {
                        if (!waiting.held) return;
                        finishBlock(waiting.x, waiting.y, waiting.z, waiting.live,
                                    shadeInputWide(shader_here, waiting.in, waiting.live));
                        waiting.held = false;
                    }
                };
                rasterizeTriangleBlocks(t, steps, tile, [&](int32_t x, int32_t y, uint32_t mask, const int64_t (&e)[3][8]) {
                    if (x >= tile.x0 && x + 3 <= tile.x1 && y >= tile.y0 && y + 1 <= tile.y1) {
                        const Float8 z = interpolateDepthWide(t, e, min_depth, max_depth);
                        uint32_t live = mask;
                        if constexpr (Depth::kEnabled) {
                            live &= depth_here.testWide(x, y, z);
                            st.fragmentsEarlyDepthKilled += uint64_t(std::popcount(mask & ~live));
                            if (!live) return;
                        }
                        if constexpr (Color::kCeiling) {  // as in shadeRectWide
                            if (color_here.template atCeiling<1>(x, y)) {
                                st.fragmentsBlendSaturated += uint64_t(std::popcount(live));
                                return;
                            }
                        }
                        if constexpr (kPairs) {
                            Wide<V> in;
                            interpolateAttributesWide(ti, e, verts, x, y, z, in);
                            if (waiting.held && waiting.y == y && waiting.x + 4 == x) {
                                const glm::vec<4, Float8x2> c =
                                    shadePairWide(shader_here, waiting.in, in, waiting.live, live);
                                finishBlock(waiting.x, y, waiting.z, waiting.live, detail::blockOf(c, 0));
                                finishBlock(x, y, z, live, detail::blockOf(c, 1));
                                waiting.held = false;
                            } else {
                                flush();
                                waiting = Waiting{true, x, y, live, z, in};
                            }
                        } else {
                            finishBlock(x, y, z, live, shadeBlockWide(shader_here, ti, e, verts, x, y, z, live));
                        }
                        return;
                    }
                    // On the border: the two 2×2 quads of the block, lane by lane.
                    for (int half = 0; half < 2; ++half) {
                        const int b = 2 * half;  // block lanes b, b+1, b+4, b+5 form the quad
                        const uint32_t qmask = ((mask >> b) & 3u) | (((mask >> (b + 4)) & 3u) << 2);
                        if (!qmask) continue;
                        const int32_t qx = x + b;
                        auto edges = [&](int lane) {
                            const int bl = b + (lane & 1) + 4 * (lane >> 1);
                            return std::array<int64_t, 3>{e[0][bl], e[1][bl], e[2][bl]};
                        };
                        auto extrapolated = [&](int lane) {  // helper lanes may lie outside the block's mask
                            return edges(lane);
                        };
                        shadeQuad(
                            qx, y, qmask,
                            [&](int lane) {
                                const auto el = extrapolated(lane);
                                return interpolateDepth<Real>(t, el[0], el[1], el[2], min_depth, max_depth);
                            },
                            [&](int lane, Real zl, V& in) {
                                const auto el = extrapolated(lane);
                                interpolateAttributes(ti, barycentrics(ti, el[0], el[1], el[2]), verts,
                                                      qx + (lane & 1), y + (lane >> 1), zl, in);
                            });
                    }
                });
                flush();
            }
        };

        // Deferred shading of an opaque draw (blending off, depth written): a pixel ends with the
        // shader's output for the last of its fragments that passed the depth test, so a first pass
        // runs the depth test alone and notes, per pixel, which triangle (its place in the tile's
        // list) that fragment came from; a second shades those fragments only. The same bits as
        // shading in order, since an eight-wide shader has no side effects, cannot discard and
        // cannot write depth; the fragments a later one replaced are never shaded. Taken for tiles
        // of two triangles or more (nothing to save with one) and none of another kind, whose 4×2
        // blocks all lie inside the tile.
        [[maybe_unused]] auto shadeDeferred = [&]() RASTER_FLATTEN {
            if constexpr (kDeferrable) {
                if (rect.x0 % 4 != 0 || (rect.x1 + 1) % 4 != 0 || rect.y0 % 2 != 0 || (rect.y1 + 1) % 2 != 0)
                    return false;
                uint32_t triangles = 0;
                for (uint32_t c = 0; c < chunk_count; ++c) {
                    for (const uint32_t entry : chunks[c].bins[tile]) {
                        if (binKind(entry) != BinKind::Triangle) return false;
                        ++triangles;
                    }
                }
                if (triangles < 2) return false;
                // Locals, as in shadeRectWide: stores to the targets would otherwise reload them.
                const Depth depth_here = depth;
                const Color color_here = color;
                const auto shader_here = wide_shader;
                auto forEachTriangle = [&](auto&& visit) {
                    uint32_t n = 0;
                    for (uint32_t c = 0; c < chunk_count; ++c)
                        for (const uint32_t entry : chunks[c].bins[tile])
                            visit(chunks[c], chunks[c].triangles[binIndex(entry)], n++);
                };
                // owner[row][column] within the tile: the triangle whose fragment the pixel shows;
                // ~0 where no fragment of this draw passed.
                alignas(32) uint32_t owner[kTileSize][kTileSize];
                std::fill_n(&owner[0][0], kTileSize * kTileSize, ~0u);
                // The tile's triangles by their place in its list, for the second pass.
                static thread_local std::vector<std::pair<const detail::Chunk<V>*, const TriangleSetup*>> listed;
                listed.resize(triangles);
                uint64_t passed = 0;
                forEachTriangle([&](const detail::Chunk<V>& chunk, const TriangleSetup& t, uint32_t n) {
                    listed[n] = {&chunk, &t};
                    if (occludedInTile(nearestDepth(t))) return;
                    rasterizeTriangleBlocks(t, edgeSteps(t), rect,
                                            [&](int32_t x, int32_t y, uint32_t mask, const int64_t (&e)[3][8]) {
                        const Float8 z = interpolateDepthWide(t, e, min_depth, max_depth);
                        const uint32_t live = mask & depth_here.testWide(x, y, z);
                        st.fragmentsEarlyDepthKilled += uint64_t(std::popcount(mask & ~live));
                        if (!live) return;
                        depth_here.writeWide(x, y, z, live);
                        passed += uint64_t(std::popcount(live));
                        uint32_t* row = &owner[y - rect.y0][x - rect.x0];
                        simd::I32x8 ids = detail::loadRows<Int8>(row, row + kTileSize).v;
                        ids = select(Mask8::fromBits(live), Int8(int32_t(n)), Int8(ids)).v;
                        std::memcpy(row, &ids, 16);
                        std::memcpy(row + kTileSize, reinterpret_cast<const char*>(&ids) + 16, 16);
                    });
                });
                // The second pass walks the tile's blocks, not the triangles: a block is shaded once
                // per triangle it shows, with that triangle's lanes live, and needs no rasterising.
                // Its edge functions are edgeAt's at the block's lane 0 plus the per-lane steps,
                // the same exact integers rasterizeTriangleBlocks steps to, so the same bits.
                // What shading a block of triangle n needs, found when the walk meets n (mostly once
                // per run of blocks: neighbours usually show the same triangle).
                struct Shown {
                    const TriangleSetup* t;
                    const V* verts[3];
                    TriangleInterpolant<Real> ti;
                    BlockLaneOffsets lanes;
                };
                std::optional<Shown> shown;
                uint32_t shown_id = ~0u;
                auto show = [&](uint32_t n) {
                    if (n == shown_id) return;
                    const auto [chunk, t] = listed[n];
                    shown.emplace(Shown{t,
                                        {&chunk->vertices[t->vertex[0]], &chunk->vertices[t->vertex[1]],
                                         &chunk->vertices[t->vertex[2]]},
                                        TriangleInterpolant<Real>(*t),
                                        BlockLaneOffsets(edgeSteps(*t))});
                    shown_id = n;
                };
                auto edgesAt = [&](int32_t x, int32_t y, int64_t (&e)[3][8]) {
                    for (int k = 0; k < 3; ++k) {
                        const int64_t e0 = edgeAt(*shown->t, k, x, y);
                        const simd::I64x4 top = e0 + shown->lanes.top[k];
                        const simd::I64x4 bottom = e0 + shown->lanes.bottom[k];
                        std::memcpy(&e[k][0], &top, sizeof top);
                        std::memcpy(&e[k][4], &bottom, sizeof bottom);
                    }
                };
                uint64_t shaded = 0;
                for (int32_t y = rect.y0; y <= rect.y1; y += 2) {
                    for (int32_t x = rect.x0; x <= rect.x1; x += 4) {
                        const uint32_t* row = &owner[y - rect.y0][x - rect.x0];
                        const simd::I32x8 ids = detail::loadRows<Int8>(row, row + kTileSize).v;
                        uint32_t pending = ~Mask8{ids == -1}.bits() & 0xFFu;
                        if constexpr (kPairs) {
                            // A block showing one triangle whose right neighbour shows that one only too
                            // (most blocks inside a triangle): both through one Float8x2 call.
                            if (pending && x + 4 <= rect.x1) {
                                const int32_t n = ids[std::countr_zero(pending)];
                                const uint32_t live_left = Mask8{ids == n}.bits();
                                const simd::I32x8 next = detail::loadRows<Int8>(row + 4, row + 4 + kTileSize).v;
                                const uint32_t live_right = Mask8{next == n}.bits();
                                if (live_left == pending && live_right != 0 &&
                                    live_right == (~Mask8{next == -1}.bits() & 0xFFu)) {
                                    show(uint32_t(n));
                                    Wide<V> in[2];
                                    for (int h = 0; h < 2; ++h) {
                                        alignas(32) int64_t e[3][8];
                                        edgesAt(x + 4 * h, y, e);
                                        const Float8 z = interpolateDepthWide(*shown->t, e, min_depth, max_depth);
                                        interpolateAttributesWide(shown->ti, e, shown->verts, x + 4 * h, y, z, in[h]);
                                    }
                                    const glm::vec<4, Float8x2> c =
                                        shadePairWide(shader_here, in[0], in[1], live_left, live_right);
                                    color_here.writeWide(x, y, detail::blockOf(c, 0), live_left);
                                    color_here.writeWide(x + 4, y, detail::blockOf(c, 1), live_right);
                                    shaded += uint64_t(std::popcount(live_left) + std::popcount(live_right));
                                    x += 4;
                                    continue;
                                }
                            }
                        }
                        while (pending) {
                            const uint32_t n = uint32_t(ids[std::countr_zero(pending)]);
                            const uint32_t live = Mask8{ids == int32_t(n)}.bits();
                            pending &= ~live;
                            show(n);
                            alignas(32) int64_t e[3][8];
                            edgesAt(x, y, e);
                            const Float8 z = interpolateDepthWide(*shown->t, e, min_depth, max_depth);
                            const glm::vec<4, Float8> c =
                                shadeBlockWide(shader_here, shown->ti, e, shown->verts, x, y, z, live);
                            color_here.writeWide(x, y, c, live);
                            shaded += uint64_t(std::popcount(live));
                        }
                    }
                }
                st.fragmentsOverdrawSkipped += passed - shaded;
                return true;
            } else {
                return false;
            }
        };
        bool deferred = false;
        if constexpr (kDeferrable) deferred = shadeDeferred();

        if (!deferred)
        for (uint32_t c = 0; c < chunk_count; ++c) {
            const detail::Chunk<V>& chunk = chunks[c];
            const std::vector<uint32_t>& bin = chunk.bins[tile];
            for (size_t k = 0; k < bin.size(); ++k) {
                const uint32_t entry = bin[k];
                const uint32_t index = binIndex(entry);
                // A tile visits its primitives sparsely, so their records miss the cache: fetch the
                // setup two entries ahead, and the vertex records of the next rectangle, whose
                // setup the previous entry fetched (measured: 8 % of the particle pass waited here).
                if (k + 2 < bin.size() && binKind(bin[k + 2]) == BinKind::Rectangle)
                    __builtin_prefetch(&chunk.rects[binIndex(bin[k + 2])]);
                if (k + 1 < bin.size() && binKind(bin[k + 1]) == BinKind::Rectangle) {
                    const V* next = &chunk.vertices[chunk.rects[binIndex(bin[k + 1])].vertex];
                    __builtin_prefetch(next);
                    __builtin_prefetch(reinterpret_cast<const char*>(next + 3) - 1);
                }
                switch (binKind(entry)) {
                    case BinKind::Triangle: {
                        const TriangleSetup& t = chunk.triangles[index];
                        if constexpr (Tracer::kEnabled) tracer.primitive = t.primitiveId;
                        if (occludedInTile(nearestDepth(t))) break;
                        const V* const verts[3] = {&chunk.vertices[t.vertex[0]], &chunk.vertices[t.vertex[1]],
                                                   &chunk.vertices[t.vertex[2]]};
                        const TriangleInterpolant<Real> ti(t);
                        const EdgeSteps steps = edgeSteps(t);
                        if constexpr (kWide && Depth::kWide && Color::kWide) {
                            shadeTriangleWide(t, ti, steps, verts);
                            break;
                        }
                        rasterizeTriangle(t, steps, rect, [&](const Quad& q) {
                            auto edges = [&](int lane) {
                                const int lx = lane & 1, ly = lane >> 1;
                                return std::array<int64_t, 3>{q.e[0] + lx * steps.dx[0] + ly * steps.dy[0],
                                                              q.e[1] + lx * steps.dx[1] + ly * steps.dy[1],
                                                              q.e[2] + lx * steps.dx[2] + ly * steps.dy[2]};
                            };
                            shadeQuad(
                                q.x, q.y, q.mask,
                                [&](int lane) {
                                    const auto e = edges(lane);
                                    return interpolateDepth<Real>(t, e[0], e[1], e[2], min_depth, max_depth);
                                },
                                [&](int lane, Real z, V& in) {
                                    const auto e = edges(lane);
                                    interpolateAttributes(ti, barycentrics(ti, e[0], e[1], e[2]), verts,
                                                          q.x + (lane & 1), q.y + (lane >> 1), z, in);
                                });
                        });
                        break;
                    }
                    case BinKind::Rectangle: {
                        const RectSetup& r = chunk.rects[index];
                        if constexpr (Tracer::kEnabled) tracer.primitive = r.primitiveId;
                        const float* base = asFloats(chunk.vertices[r.vertex]);
                        const float* step_x = asFloats(chunk.vertices[r.vertex + 1]);
                        const float* step_y = asFloats(chunk.vertices[r.vertex + 2]);
                        const Real z = std::clamp(Real(r.z), Real(min_depth), Real(max_depth));
                        if (occludedInTile(float(z))) break;
                        if constexpr (kWide) {
                            shadeRectWide(r, base, step_x, step_y, z, inFrontInTile(float(z)));
                            break;
                        }
                        rasterizeRect(r.box, rect, [&](int32_t qx, int32_t qy, uint32_t mask) {
                            shadeQuad(
                                qx, qy, mask, [&](int) { return z; },
                                [&](int lane, Real, V& in) {
                                    const float i = float(qx + (lane & 1) - r.box.x0);
                                    const float j = float(qy + (lane >> 1) - r.box.y0);
                                    float* o = asFloats(in);
                                    for (uint32_t k = 0; k < kVertexFloats<V>; ++k)
                                        o[k] = base[k] + i * step_x[k] + j * step_y[k];
                                });
                        });
                        break;
                    }
                    case BinKind::Line: {
                        const LineSetup& l = chunk.lines[index];
                        if constexpr (Tracer::kEnabled) tracer.primitive = l.primitiveId;
                        const V* const verts[2] = {&chunk.vertices[l.vertex[0]], &chunk.vertices[l.vertex[1]]};
                        rasterizeLine(l, rect, [&](int32_t x, int32_t y, double t) {
                            V in;
                            Real z;
                            interpolateLine<Real>(l, verts, x, y, t, min_depth, max_depth, in, z);
                            if (!earlyDepthPasses(x, y, z)) return;
                            ++st.psInvocations;
                            merge(x, y, z, shader.shadeSingle(in));
                        });
                        break;
                    }
                    case BinKind::Point: {
                        const PointSetup& pt = chunk.points[index];
                        if constexpr (Tracer::kEnabled) tracer.primitive = pt.primitiveId;
                        if (pt.px < rect.x0 || pt.px > rect.x1 || pt.py < rect.y0 || pt.py > rect.y1) break;
                        V in = chunk.vertices[pt.vertex];
                        const Real z = std::clamp(Real(pt.z), Real(min_depth), Real(max_depth));
                        const float w = in.position.w;
                        in.position = glm::vec4(float(pt.px) + 0.5f, float(pt.py) + 0.5f, float(z), w);
                        if (!earlyDepthPasses(pt.px, pt.py, z)) break;
                        ++st.psInvocations;
                        merge(pt.px, pt.py, z, shader.shadeSingle(in));
                        break;
                    }
                }
            }
        }
        if constexpr (Tracer::kEnabled) traced_tiles[tile] = std::move(tracer.fragments);
        if (progress) progress->tileFinished();  // per tile, never per pixel: see RenderProgress
    });
    for (const ThreadStatistics& t : per_thread) stats += t.s;
    if constexpr (Tracer::kEnabled)
        for (const auto& fragments : traced_tiles) trace_->addFragments(fragments);
}

}  // namespace raster
