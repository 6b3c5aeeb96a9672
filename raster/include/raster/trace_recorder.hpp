// The pipeline trace's hooks in the per-pixel loop (see raster/trace.hpp). The loop is a template
// over a Tracer: NoTracer's hooks are `if constexpr`-ed away, so a draw through the specialised
// policies has none of this code; FragmentTracer records one tile's fragments into its own vector
// (no locks: a pixel belongs to one tile, so the per-pixel counts are written by one thread only).
// Draws through the generic policies always take FragmentTracer, recording or not (`active`): one
// instantiation of the tile loop serves traced and untraced generic draws alike, which halves what
// a file that draws through the generic policies only (the teaching pipeline) compiles. Its hooks then cost one
// predictable branch per fragment, on the path that reads the state per fragment anyway.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include <cstring>
#include <span>

#include "raster/input_layout.hpp"
#include "raster/render_target.hpp"
#include "raster/stages/input_assembler.hpp"
#include "raster/fastpath/merge_policy.hpp"
#include "raster/trace.hpp"

namespace raster::detail {

struct NoTracer {
    static constexpr bool kEnabled = false;
    static constexpr bool active = false;
};

struct FragmentTracer {
    // The hooks are compiled in (the fill paths that cannot call them per fragment are not); whether
    // they record is `active`.
    static constexpr bool kEnabled = true;
    static constexpr size_t kNone = SIZE_MAX;

    bool active = false;  // false: every hook returns at once, and the draw records nothing
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
