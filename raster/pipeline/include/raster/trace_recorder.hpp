// The trace's side of the draw's hooks (draw_hooks.hpp): FragmentHooks, the generic tile loop's hooks
// per fragment, and the functions that fill a draw's TraceDraw from the stages' records.
//
// The tile loop is a template over its hooks: NoHooks (draw_hooks.hpp) has none, so a draw through
// the specialised policies has none of this code; FragmentHooks records one tile's fragments into
// its own vector (no locks: a pixel belongs to one tile, so the per-pixel counts are written by one
// thread only) and carries a lab's coverage rule. Draws through the generic policies always take
// FragmentHooks, recording or not (`active`): one instantiation of the tile loop serves traced and
// untraced generic draws alike, which halves what a file that draws through the generic policies
// only (the teaching pipeline) compiles. Its hooks then cost one predictable branch per fragment, on
// the path that reads the state per fragment anyway.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>

#include "raster/bin_primitives.hpp"
#include "raster/draw_hooks.hpp"
#include "raster/input_layout.hpp"
#include "raster/render_target.hpp"
#include "raster/stages/1_input_assembler.hpp"
#include "raster/teaching_pipeline.hpp"
#include "raster/trace.hpp"

namespace raster::detail {

struct FragmentHooks {
    // The hooks are compiled in (the fill paths that cannot call them per fragment are not); whether
    // they record is `active`.
    static constexpr bool kEnabled = true;
    static constexpr size_t kNone = SIZE_MAX;

    // A lab's coverage rule (DrawHooks::coverage): fill/quads.hpp asks its test, not the library's
    // edges, which pixel centres a triangle covers. Null: the library's rule.
    const TeachingCoverage* coverage = nullptr;
    bool active = false;  // false: every recording hook returns at once, and the draw records nothing
    PixelRect filter;
    uint32_t draw = 0;
    uint32_t primitive = 0;
    const RenderTarget* color = nullptr;  // target 0, or none
    const DepthTarget* depth = nullptr;
    uint32_t* overdraw = nullptr;
    uint32_t* nonFinite = nullptr;
    uint32_t width = 0;
    std::vector<TraceFragment> fragments;  // this tile's, in output-merger order

    // A fragment was rasterised (counted before any test).
    void covered(int32_t x, int32_t y) const {
        if (active) ++overdraw[size_t(y) * width + x];
    }

    bool wanted(int32_t x, int32_t y) const {
        return x >= filter.x0 && x <= filter.x1 && y >= filter.y0 && y <= filter.y1;
    }

    static glm::vec4 nan4() { return glm::vec4(std::numeric_limits<float>::quiet_NaN()); }

    // Opens a record before the output merger touches the pixel; kNone when the pixel is not traced.
    size_t open(int32_t x, int32_t y, float z, bool shaded, const glm::vec4& output) {
        if (!active) return kNone;
        if (shaded && !(std::isfinite(output.x) && std::isfinite(output.y) && std::isfinite(output.z) &&
                        std::isfinite(output.w)))
            ++nonFinite[size_t(y) * width + x];
        if (!wanted(x, y)) return kNone;
        TraceFragment f;
        f.draw = draw, f.primitive = primitive, f.x = x, f.y = y, f.depth = z;
        f.depthBefore = depth ? depth->load(uint32_t(x), uint32_t(y)) : std::numeric_limits<float>::quiet_NaN();
        f.fate = FragmentFate::Written;
        f.shaded = shaded;
        f.shaderOutput = shaded ? output : nan4();
        f.colorBefore = color ? color->load(uint32_t(x), uint32_t(y)) : nan4();
        fragments.push_back(f);
        return fragments.size() - 1;
    }
    // Closes it with what the output merger did, reading the pixel back.
    void close(size_t record, FragmentFate fate) {
        if (record == kNone) return;
        TraceFragment& f = fragments[record];
        f.fate = fate;
        // The shader ran for a discarded fragment (psInvocations counts it), though it has no output.
        if (fate == FragmentFate::Discarded) f.shaded = true;
        f.depthAfter = depth ? depth->load(uint32_t(f.x), uint32_t(f.y)) : std::numeric_limits<float>::quiet_NaN();
        f.colorAfter = color ? color->load(uint32_t(f.x), uint32_t(f.y)) : nan4();
    }
};

// The generic tile loop's hooks for one draw: recording while the draw is traced (the fragments
// inside TraceOptions::pixels; overdraw and non-finite outputs of the whole target), and the draw's
// coverage rule.
inline FragmentHooks fragmentHooks(const DrawHooks& hooks, const RenderTarget* color, const DepthTarget* depth,
                                   uint32_t width) {
    FragmentHooks f;
    f.coverage = hooks.coverage;
    if (!hooks.record) return f;
    f.active = true;
    f.filter = hooks.trace->options().pixels;
    f.draw = hooks.record->draw;
    f.color = color;
    f.depth = depth;
    f.overdraw = hooks.trace->overdrawData();
    f.nonFinite = hooks.trace->nonFiniteData();
    f.width = width;
    return f;
}

// The draw's statistics, and whether the step limit skipped it, into its record (when traced).
inline void finishTraceDraw(const DrawHooks& hooks, const PipelineStatistics& stats) {
    if (!hooks.record) return;
    hooks.record->stats = stats;
    hooks.record->skipped = hooks.skipped;
}

// What a draw's record says of its shaders: their names, the vertex shader's input signature, the
// float counts and SV_Position's offset of their outputs (the state is Context::drawHooks's part).
template <class VS, class GS, class PS>
void describeTraceDraw(TraceDraw& d, const VS& vs, const GS& gs, const PS& ps) {
    using VsOut = VertexShaderOutput<VS>;
    d.vertexShader = shaderName(vs);
    d.pixelShader = shaderName(ps);
    const VertexInputDescription input = vertexInputOf(vs);
    for (const ShaderInputField& f : input.signature)
        d.inputFields.push_back(
            {std::string(f.semanticName) + (f.semanticIndex ? std::to_string(f.semanticIndex) : ""),
             f.offset / uint32_t(sizeof(float)), f.components});
    d.vsFloats = vertexShaderFloats(vs);
    d.vsPosition = uint32_t(offsetof(VsOut, position) / sizeof(float));
    if constexpr (!std::is_same_v<GS, NoGeometryShader>) {
        using GsOut = GeometryShaderOutput<GS>;
        d.geometryShader = shaderName(gs);
        d.gsFloats = geometryShaderFloats(gs);
        d.gsPosition = uint32_t(offsetof(GsOut, position) / sizeof(float));
    }
}

// The geometry shader's output for one input primitive, into the chunk's records (at most traceCap).
template <class V, class Stream>
void traceGsOutput(Chunk<V>& chunk, uint32_t primitive, const Stream& stream, uint32_t floats) {
    for (int i = 0; i < stream.size(); ++i) {
        if (chunk.traceGsTotal++ >= chunk.traceCap) continue;
        const float* f = asFloats(stream.vertex(i));
        chunk.traceGs.push_back(TraceGsVertex{primitive, stream.startsStrip(i), std::vector<float>(f, f + floats)});
    }
}

// One chunk's geometry records into the draw's, chunk after chunk (API order), at most cap of each.
template <class V>
void gatherGeometryRecords(TraceDraw& d, uint32_t cap, Chunk<V>& chunk) {
    for (auto& g : chunk.traceGs)
        if (d.gsVertices.size() < cap) d.gsVertices.push_back(std::move(g));
    for (const auto& t : chunk.tracePrimitives)
        if (d.primitives.size() < cap) d.primitives.push_back(t);
    d.gsVerticesTotal += chunk.traceGsTotal;
    d.primitivesTotal += chunk.tracePrimitivesTotal;
}

// Vertex shader records: the first `cap` invocations' inputs (fetched again, as the input
// assembler did) and outputs; and the first `cap` input primitives' vertex indices.
template <class VsIn, class VsOut>
void traceVertices(TraceDraw& d, uint32_t cap, std::span<const InputFetch> program,
                   std::span<const VertexBuffer* const> slots, const AssembledDraw& draw, const DrawCall& call,
                   const std::vector<VsOut>& out, uint32_t input_floats, uint32_t output_floats) {
    const uint32_t per_instance = uint32_t(draw.fetch.size());
    d.verticesTotal = out.size();
    for (size_t i = 0; i < out.size() && i < cap; ++i) {
        const uint32_t instance = uint32_t(i / per_instance), local = uint32_t(i % per_instance);
        VsIn in;
        std::memset(static_cast<void*>(&in), 0, sizeof in);
        fetchVertex(program, slots, draw.fetch[local], instance, call.startInstance, reinterpret_cast<std::byte*>(&in));
        TraceVertex v;
        v.instance = instance;
        v.index = draw.fetch[local];
        v.input.resize(input_floats);  // the shader's input struct's (≤ sizeof(VsIn))
        std::memcpy(v.input.data(), &in, v.input.size() * sizeof(float));
        const float* o = asFloats(out[i]);
        v.output.assign(o, o + output_floats);  // ≤ kVertexFloats<VsOut>
        d.vertices.push_back(std::move(v));
    }
    // Each input primitive's vertices, as buffer indices, instance by instance.
    const uint32_t n = uint32_t(draw.kind), per_instance_primitives = draw.primitiveCount();
    d.verticesPerPrimitive = n, d.primitivesPerInstance = per_instance_primitives;
    const uint64_t primitives = uint64_t(per_instance_primitives) * call.instanceCount;
    for (uint64_t p = 0; p < primitives && p < cap; ++p)
        for (uint32_t k = 0; k < n; ++k)
            d.primitiveVertices.push_back(draw.fetch[draw.primitives[(p % per_instance_primitives) * n + k]]);
}

}  // namespace raster::detail
