// The draw's hooks: everything a draw does besides drawing, behind one door.
//
// Four things watch or steer a draw without being part of D3D11's pipeline: the trace (trace.hpp),
// the step limit (Context::setStepLimit), progress (RenderProgress) and a lab's coverage rule (the
// teaching pipeline's Context::setCoverageTest). They reach the draw through two objects only, both
// declared here, so that a reader who follows a draw from Context::draw (pipeline_impl.hpp) to its
// tile loop sees each hook where it is called, and grep for `hooks.` finds them all:
//
//   detail::DrawHooks  — one per draw, made by Context::drawHooks (src/pipeline.cpp) once the draw
//                        is validated. Plain data and pointers, read by pipeline_impl.hpp between the
//                        stages: a few tests per draw and one per tile, never one per pixel.
//   the tile's hooks   — a template argument of the tile loop (renderTiles, fill/tile.hpp's Tile),
//                        called per primitive and per fragment. The default, NoHooks, has none: its
//                        `kEnabled` is false and every call site is `if constexpr (Hooks::kEnabled)`,
//                        so the specialised tile loops compile to what they would be without hooks.
//                        The other is trace_recorder.hpp's FragmentHooks, which the generic tile loop
//                        always takes (traced or not, with a coverage rule or not: one instantiation).
//
// Each hook, when it is called, and what it costs when unused:
//   step limit  DrawHooks::skipped, primitiveLimit, runsGeometryShader, runsSetup, runsPixels: read
//               after the vertex shader and before each later stage (executeDraw). Unset: all true
//               and UINT64_MAX, one comparison each per draw.
//   progress    DrawHooks::progress: beginTiles before the tile loop, tileFinished after each tile
//               (renderTiles; RenderProgress::DrawScope counts the draw). Unset: a null test per tile.
//   trace       DrawHooks::record (this draw's TraceDraw; null when no trace is set): the shaders'
//               names (describeTraceDraw), the vertex shader's records (traceVertices), the geometry
//               stages' records (Chunk::trace in stages/6_binner.hpp, gathered by gatherGeometryRecords),
//               the statistics and whether the step limit skipped the draw (finishTraceDraw).
//               Per fragment: FragmentHooks::covered, open, close (fill/tile.hpp), active only while
//               a trace is set; a traced draw takes the generic tile loop. Unset: a null test per
//               draw and per chunk of primitives.
//   coverage    DrawHooks::coverage (a teaching draw's TeachingCoverage when the lab set a test;
//               null otherwise, always null for the template pipeline's draws): the binner gives each
//               triangle every tile of its box (PrimitiveSpace::binWholeBoxes), the geometry stages set
//               up no rectangles, and fill/quads.hpp asks the lab's test (FragmentHooks::coverage)
//               instead of the library's edges. Unset: one test per triangle in setup, none in the
//               specialised tile loops.
//
// The records the geometry stages hand to the trace are declared here too, so that the stages and
// the trace both speak this header's words and neither includes the other.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "raster/shader.hpp"

namespace raster {

class Trace;
struct TraceDraw;
class RenderProgress;
struct TeachingCoverage;

// What setup did with a primitive (TracePrimitive::fate).
enum class PrimitiveFate : uint8_t {
    Rasterized,     // set up and binned
    Rectangle,      // a two-triangle billboard drawn as one screen rectangle
    NonFinite,      // a NaN or Inf position: dropped
    Outside,        // wholly outside the view volume
    Culled,         // back- or front-face culling
    Degenerate,     // zero area after snapping to 16.8 fixed point
    NoPixels,       // covers no pixel centre in the viewport
};
const char* toString(PrimitiveFate fate);

// One primitive leaving the clipper (or rejected before it), in screen space.
struct TracePrimitive {
    uint32_t primitive;    // the input primitive it came from
    PrimitiveKind kind;
    PrimitiveFate fate;
    bool clipped;          // made by cutting against a clip plane
    uint8_t vertexCount;   // 1..4 (4: a rectangle's corners as the strip gave them)
    glm::vec4 screen[4];   // x, y in pixels, z depth, w the clip-space w; zero for Outside/NonFinite
};

// One vertex appended by the geometry shader.
struct TraceGsVertex {
    uint32_t primitive;   // the input primitive (SV_PrimitiveID, instances counted on)
    bool startsStrip;     // first vertex of a strip (after RestartStrip or the invocation's first)
    std::vector<float> values;  // the output struct as floats (position at TraceDraw::gsPosition)
};

namespace detail {

// The hooks of one draw, as Context::drawHooks resolved them (see the top of this file).
struct DrawHooks {
    // ---- Step limit: what of this draw runs ----
    bool skipped = false;                  // past the limit: validated and counted, not run
    uint64_t primitiveLimit = UINT64_MAX;  // input primitives run (input-assembler order, instances on)
    bool runsGeometryShader = true;        // false: the draw stops after the vertex shader
    bool runsSetup = true;                 // false: it stops after the geometry shader
    bool runsPixels = true;                // false: it stops after binning
    // ---- Progress ----
    RenderProgress* progress = nullptr;
    // ---- Trace ----
    Trace* trace = nullptr;         // the trace set on the context, or null
    TraceDraw* record = nullptr;    // this draw's record in it (null exactly when trace is)
    bool traceGeometry = false;     // keep the input assembler's, shaders' and setup's records
    uint32_t geometryCap = 0;       // of each kind, per draw (TraceOptions::maxGeometryRecords)
    // ---- Coverage rule ----
    const TeachingCoverage* coverage = nullptr;  // a lab's test decides the triangles' pixels

    // Neither traced nor with a coverage rule: the draw may take the specialised tile loops.
    bool fragmentHooksIdle() const { return record == nullptr && coverage == nullptr; }
};

// The tile loop's default hooks: none. Every call site tests kEnabled with `if constexpr`.
struct NoHooks {
    static constexpr bool kEnabled = false;
    static constexpr bool active = false;  // records nothing
};

}  // namespace detail

}  // namespace raster
