// A trace (trace.hpp) read out: a pixel's history as text for students and as JSON for tools, a
// draw's state and geometry records as text. The tooling's, not the pipeline's: the pipeline fills
// the trace, the command line, the viewer and the grader format it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "raster/trace.hpp"

namespace raster {

// Text for students and JSON for tools.
std::string formatPixelHistory(const Trace& trace, int32_t x, int32_t y);
std::string pixelHistoryJson(const Trace& trace, int32_t x, int32_t y);
// The draw's rasterizer state in one line: "rasterizer: cull None, fill Solid, front clockwise,
// scissor off, depth clip on" and, where a lab's coverage test decided its pixels, ", coverage: the
// lab's test".
std::string rasterizerSummary(const TraceDraw& draw);
// A draw's geometry records, at most `limit` of each kind, as text.
std::string formatDraw(const TraceDraw& draw, size_t limit);

}  // namespace raster
