// The pipeline trace: what every stage did in a frame, for students to read and tools to show.
//
//   raster::Trace trace({.pixels = {x, y, x, y}});  // record the fragments of one pixel
//   ctx.setTrace(&trace);                            // off again with setTrace(nullptr)
//   scene.render(ctx, color, depth);
//   for (const raster::TraceFragment& f : trace.pixelHistory(x, y)) ...
//
// Per draw it keeps the input assembler's vertices (as the vertex shader's input fields), the
// vertex shader's outputs, the geometry shader's output strips, each primitive after clipping and
// setup with what happened to it, and per fragment inside TraceOptions::pixels: its depth, the
// depth buffer before, the depth test's result, the shader's output and the colour of target 0
// before and after the blend. Overdraw (fragments rasterised per pixel) and non-finite shader
// outputs are counted for the whole target.
//
// Tracing is free when off: draws compile a separate tracing instantiation of the per-pixel
// loop, used only while a trace is set. A traced draw shades fragment by fragment (never eight
// wide) and blends through the generic output merger, which give the same bits as the fast paths
// (tests/trace_test.cpp checks it), so the traced image is the untraced one. Records are kept in
// a deterministic order for any thread count: geometry in API order; fragments of one pixel in the
// order the output merger saw them (draw, then primitive, then the geometry shader's output order).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/draw_hooks.hpp"
#include "raster/shader.hpp"
#include "raster/states.hpp"
#include "raster/statistics.hpp"

namespace raster {

struct TraceOptions {
    // Fragments are recorded only for pixels in this inclusive rectangle (default: none; use
    // everything() for all pixels, which for a busy frame is millions of records).
    PixelRect pixels{0, 0, -1, -1};
    // Geometry records kept per draw for each of: vertices, GS output vertices, primitives.
    // Counts beyond are still counted (TraceDraw::*Total).
    uint32_t maxGeometryRecords = 4096;
    bool geometry = true;  // keep IA/VS/GS/setup records
    size_t maxFragments = size_t(1) << 22;
    static PixelRect everything() { return {0, 0, INT32_MAX - 1, INT32_MAX - 1}; }
};

// A named field of a vertex record (first float at `offset` floats into TraceVertex::values).
struct TraceField {
    std::string name;
    uint32_t offset;
    uint32_t components;
};

// One vertex shader invocation: where its input came from, its input and its output.
struct TraceVertex {
    uint32_t instance;  // SV_InstanceID, from 0
    uint32_t index;     // the vertex buffer index the input assembler fetched (SV_VertexID)
    std::vector<float> input;   // the vertex shader's input struct, field by field (TraceDraw::inputFields)
    std::vector<float> output;  // the vertex shader's output struct as floats (position at TraceDraw::vsPosition)
};

// The geometry shader's vertices and each primitive after setup (TraceGsVertex, TracePrimitive,
// PrimitiveFate) are declared in draw_hooks.hpp: the stages fill them without including this file.

enum class FragmentFate : uint8_t {
    EarlyDepthFailed,  // failed the depth test before the shader: not shaded
    LateDepthFailed,   // failed it after the shader (the reference pipeline's order)
    Discarded,         // the shader discarded it
    BlendNoOp,         // passed, but the blend could not change the pixel: not written
    Written,           // passed the depth test; depth (if enabled and writable) and colour written
};
const char* toString(FragmentFate fate);

struct TraceFragment {
    uint32_t draw;        // draw number since resetFrameStatistics
    uint32_t primitive;   // the input primitive (SV_PrimitiveID)
    int32_t x, y;
    float depth;          // the fragment's depth after the viewport transform
    float depthBefore;    // the depth buffer's value before (NaN without a depth target)
    float depthAfter;     // and after
    FragmentFate fate;
    bool shaded;          // the pixel shader ran (false for EarlyDepthFailed)
    glm::vec4 shaderOutput;  // SV_Target0 (NaN when not shaded or discarded)
    glm::vec4 colorBefore;   // render target 0 before and after, as the shader would load it
    glm::vec4 colorAfter;    // (NaN without a colour target)
};

struct TraceDraw {
    uint32_t draw;
    std::string vertexShader, geometryShader, pixelShader;  // geometryShader empty when none
    Topology topology;
    BlendState blend;
    DepthStencilState depthStencil;
    RasterizerState rasterizer;
    // A lab's coverage test decided the triangles' pixels (Context::setCoverageTest).
    bool coverageTest = false;
    std::vector<TraceField> inputFields;  // the vertex shader's input signature
    uint32_t vsPosition = 0, gsPosition = 0;  // float offset of SV_Position in outputs
    uint32_t vsFloats = 0, gsFloats = 0;
    std::vector<TraceVertex> vertices;
    std::vector<TraceGsVertex> gsVertices;
    std::vector<TracePrimitive> primitives;
    // The input primitives as the input assembler made them, in SV_PrimitiveID order (instances counted
    // on): primitive p's vertices are the buffer indices (SV_VertexID) primitiveVertices[n·p .. n·p + n),
    // n = verticesPerPrimitive (1 point, 2 line, 3 triangle), of instance p / primitivesPerInstance; the
    // first maxGeometryRecords primitives. What makes primitive p of one frame the same as primitive q of
    // another drawing the same buffer in another order (an index buffer sorted otherwise).
    std::vector<uint32_t> primitiveVertices;
    uint32_t verticesPerPrimitive = 0, primitivesPerInstance = 0;
    uint64_t verticesTotal = 0, gsVerticesTotal = 0, primitivesTotal = 0;  // before truncation
    PipelineStatistics stats;
    bool skipped = false;  // past the step limit: validated, not run
};

class Trace {
public:
    explicit Trace(const TraceOptions& options = {}) : options_(options) {}

    const TraceOptions& options() const { return options_; }
    // Drops every record; the next draw starts a new frame's trace.
    void clear();

    const std::vector<TraceDraw>& draws() const { return draws_; }
    // Fragments in recording order: per draw, tile by tile; within a pixel, the output merger's order.
    const std::vector<TraceFragment>& fragments() const { return fragments_; }
    // Every fragment of pixel (x, y) in the order the output merger saw them.
    std::vector<TraceFragment> pixelHistory(int32_t x, int32_t y) const;
    bool fragmentsTruncated() const { return fragments_truncated_; }

    // Per pixel of the last traced draw's target size (row-major, row 0 on top): fragments
    // rasterised (before the depth test), and shader outputs with a NaN or Inf component.
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    const std::vector<uint32_t>& overdraw() const { return overdraw_; }
    const std::vector<uint32_t>& nonFinite() const { return non_finite_; }

    // ---- Filled by the pipeline ----
    // Starts a draw's record; resets the per-pixel counts when the target size changes.
    TraceDraw& beginDraw(uint32_t width, uint32_t height);
    // Appends one tile's fragments (in order); drops what exceeds maxFragments.
    void addFragments(const std::vector<TraceFragment>& fragments);
    uint32_t* overdrawData() { return overdraw_.data(); }
    uint32_t* nonFiniteData() { return non_finite_.data(); }

private:
    TraceOptions options_;
    std::vector<TraceDraw> draws_;
    std::vector<TraceFragment> fragments_;
    bool fragments_truncated_ = false;
    uint32_t width_ = 0, height_ = 0;
    std::vector<uint32_t> overdraw_, non_finite_;
};

}  // namespace raster
