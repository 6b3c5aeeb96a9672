// The diagnosis of raster grade (docs/GRADING.md): given one pixel's history in the submission's
// render and in the solution's, name the first pipeline stage where they part, in words a student
// can act on.
//
//   const raster::grade::Diagnosis d = raster::grade::diagnosePixel(submission_trace, solution_trace, x, y);
//   d.stage     DiagnosisStage::Blend
//   d.headline  "pixel (212, 96), draw 1, primitive 417: blend: your destination factor is INV_SRC_ALPHA
//               where the solution's is ONE"
//   d.details   the draw's state differences, the two fragments' figures
//
// Both traces must have recorded the pixel's fragments (TraceOptions::pixels) and the geometry
// (TraceOptions::geometry, with enough maxGeometryRecords for the draw's primitives).
//
// How the histories are aligned: fragments by draw, then by input primitive, the keys the output merger
// orders them by. A primitive is known by its vertices (instance and vertex-buffer indices,
// TraceDraw::primitiveVertices): where the two draws number the pixel's primitives otherwise (an index
// buffer sorted otherwise), your primitive p is paired with the solution's q of the same vertices, not
// with its q = p. First, per draw: the same primitives at the pixel in another order is the diagnosis
// (DiagnosisStage::Blend, the order the output merger blends them in: both orders' depths, whether
// yours is the solution's reversed or the vertex buffer's own, the numbers paired, and a state of the
// draw that differs too); without recorded vertices, the same when the fragments (depth, shader output)
// are the solution's in another sequence. Then for each pair, in the solution's order (a primitive one
// side's draw lacks or repeats first: InputAssembler, with its vertices), the stages are compared from
// first to last, and the first difference found is the diagnosis:
//   1. the draw itself: a draw the other frame lacks; shaders or topology (DiagnosisStage::Draw)
//   2. geometry of that input primitive: the vertex shader's inputs as the input assembler fetched them,
//      field by field by semantic (InputAssembler: a wrong offset or format in the input layout, or other
//      data in the buffer), then its outputs given the same inputs (VertexShader; positions also in pixels);
//      the geometry shader's vertex count (as triangles of its strips) and output positions, else the
//      positions after setup (GeometryShader, VertexShader); the primitives set up from it (Rasterizer: a
//      fragment one side has and the other not, with the same geometry). The vertices compared are the
//      primitive's own (recorded vertices; else vertex p of a point list's primitive p), then every recorded
//      one in order while both fetched the same vertex.
//   3. the fragment's depth test and depth write (DepthTest)
//   4. the pixel shader's output (PixelShader)
//   5. the colour after the output merger, given the same shader output and colour before (Blend)
// Positions are compared exactly (the solution against itself is bit-exact at any thread count): a
// different order of a strip's corners reads as a geometry difference, but then the images agree and
// no diagnosis is asked for. Draws are compared as a whole too: blend, depth-stencil and rasterizer
// state differences are listed in `details` whatever the stage. A coverage difference (step 2's
// Rasterizer, a fragment one side has and the other not) says what the pixel's centre is to the
// triangle: exactly on an edge (the top-left rule), or inside where the pixel's corner is not or the
// other way round (coverage tested at the corner instead of the centre).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "raster/trace.hpp"

namespace raster::grade {

enum class DiagnosisStage {
    None,
    Draw,
    InputAssembler,
    VertexShader,
    GeometryShader,
    Rasterizer,
    DepthTest,
    PixelShader,
    Blend
};
// "none", "draw", "input assembler", "vertex shader", "geometry shader", "rasterizer", "depth test",
// "pixel shader", "blend".
const char* stageName(DiagnosisStage stage);

struct Diagnosis {
    DiagnosisStage stage = DiagnosisStage::None;
    std::string headline;              // one line: where, which stage, yours against the solution's
    std::vector<std::string> details;  // the state differences of the draws involved, then figures
};

Diagnosis diagnosePixel(const Trace& submission, const Trace& solution, int32_t x, int32_t y);

// The blend, rasterizer and depth-stencil state differences of draw `draw` in both traces, one line each,
// e.g. "draw 1 blend: your destination factor is INV_SRC_ALPHA where the solution's is ONE"; empty when equal
// or when either trace lacks the draw.
std::vector<std::string> drawStateDifferences(const Trace& submission, const Trace& solution, uint32_t draw);

}  // namespace raster::grade
