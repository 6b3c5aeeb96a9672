// A pixel's history carried from a lab runner (a child process running a submission's code) to the
// grader: the runner renders with a raster::Trace on one pixel and writes it with traceToJson; the
// grader reads it back with traceFromJson into a Trace of its own and diagnoses it (diagnose.hpp)
// against the solution's, recorded in-process.
//
// What is kept: every draw's record (shader names, topology, blend and depth-stencil state, the vertex
// and geometry shaders' output records, the primitives after setup, the input primitives' vertex indices:
// optional when read, a trace without them reads as one that did not record them) and the fragments of
// the traced pixels. Not kept: the per-pixel overdraw and non-finite counts, the pipeline statistics.
//
// The JSON comes from the submission's process, so it is untrusted: traceFromJson checks every field's
// type and range and throws Error(BadFile) naming `name` and the field at the first that is wrong (a
// diagnosis is then left out; the score never depends on it). Floats are written with 9 significant
// digits (they read back bit for bit); NaN and infinities as the strings "nan", "inf", "-inf".
#pragma once

#include <string>
#include <string_view>

#include "raster/trace.hpp"

namespace raster::grade {

std::string traceToJson(const Trace& trace);
Trace traceFromJson(std::string_view json, const std::string& name);

}  // namespace raster::grade
