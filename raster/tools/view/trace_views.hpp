// The viewer's trace views (raster/pipeline/include/raster/trace.hpp), as plain images without SDL, so that
// tests can compute what the window must show: the overdraw heat map, the NaN/Inf view, and
// wireframes of a draw's stages drawn into the image (vertex shader output points, geometry shader
// output strips, primitives after clipping and setup, the current primitive of a step).
//
// Images are RGBA8, row 0 on top, one pixel per framebuffer pixel; screen positions are the
// pipeline's (x, y in pixels, pixel (i, j) covering [i, i + 1) × [j, j + 1)).
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "raster/pixel_march.hpp"
#include "raster/states.hpp"
#include "raster/trace.hpp"

namespace raster::tools {

using Rgb = std::array<uint8_t, 3>;

// The overdraw ramp: 0 black; 1..max from dark purple through red and yellow to white, white only
// at `max` (so the hottest pixels are exactly the white ones).
Rgb heatColour(uint32_t count, uint32_t max);
// Trace::overdraw() as a heat map (`max`: its largest count, returned for the legend).
std::vector<uint8_t> overdrawImage(const std::vector<uint32_t>& counts, uint32_t width, uint32_t height,
                                   uint32_t* max = nullptr);

constexpr Rgb kNonFiniteColour = {255, 0, 255};
// Every channel divided by 3: what the NaN/Inf view and the stage views draw over.
void dim(std::vector<uint8_t>& rgba);
// The dimmed colour image with pixels whose shader output was NaN or Inf (Trace::nonFinite() > 0)
// in kNonFiniteColour; `highlighted` counts them.
std::vector<uint8_t> nonFiniteImage(const std::vector<uint8_t>& rgba, const std::vector<uint32_t>& nonFinite,
                                    size_t* highlighted = nullptr);

// Wireframe colours.
constexpr Rgb kVertexColour = {0, 255, 255};      // VS output positions
constexpr Rgb kGsColour = {255, 160, 0};          // GS output strips
constexpr Rgb kRasterizedColour = {0, 255, 0};    // set-up primitives: rasterized or rectangle
constexpr Rgb kClippedColour = {0, 200, 255};     //   made by clipping
constexpr Rgb kCulledColour = {255, 60, 60};      //   culled
constexpr Rgb kNoPixelsColour = {160, 160, 160};  //   degenerate or covering no pixel centre
constexpr Rgb kCurrentPrimitiveColour = {255, 255, 0};

struct Canvas {
    std::vector<uint8_t>& rgba;
    uint32_t width, height;
    void set(int32_t x, int32_t y, const Rgb& c);
    // The pixels a segment between two screen positions crosses (clipped to the image).
    void line(glm::vec2 a, glm::vec2 b, const Rgb& c);
    // A (2r+1)² square about the pixel holding p.
    void dot(glm::vec2 p, int r, const Rgb& c);
};

// A clip-space position to screen (x, y), as the pipeline's viewport transform does; false when
// it cannot be placed (w <= 0 or not finite).
bool clipToScreen(const glm::vec4& clip, const Viewport& viewport, glm::vec2& screen);

// The outline of a set-up primitive: a triangle's 3 edges, a rectangle's 4 (corners in strip
// order), a line, or a dot for a point. Nothing for primitives rejected before setup.
void drawPrimitive(Canvas& canvas, const TracePrimitive& primitive, const Rgb& colour);
// Every record of input primitive `primitive` (clipping can make several, a billboard one
// rectangle or two triangles); returns how many were drawn.
size_t drawInputPrimitive(Canvas& canvas, const TraceDraw& draw, uint32_t primitive, const Rgb& colour);
// The draw's vertex shader outputs as dots at their positions; with a geometry shader, whose input
// is in a space of its own, a dot at the centre of each input primitive's GS output instead.
size_t drawVertices(Canvas& canvas, const TraceDraw& draw, const Viewport& viewport);
// The geometry shader's output strips as a wireframe (points as dots). The output's primitive
// kind is taken from the draw's set-up primitives (triangles when there are none).
size_t drawGsOutput(Canvas& canvas, const TraceDraw& draw, const Viewport& viewport);
// All the draw's set-up primitives, coloured by fate.
size_t drawPrimitives(Canvas& canvas, const TraceDraw& draw);
Rgb fateColour(const TracePrimitive& primitive);

const TraceDraw* findTraceDraw(const Trace& trace, uint32_t draw);

// The pixel history panel: a header line, then one tab-separated row per fragment (at most
// `maxRows`, then how many more).
std::vector<std::string> compactPixelHistory(const Trace& trace, int32_t x, int32_t y, size_t maxRows);

// The march panel of a media scene's pixel: L (the mean of its channels, gathered from the eye) and T
// along the ray, as points (s in metres, value) from the box's entry (L = 0, T = 1) to past each
// evaluated sample's step; lMax the largest L (the plot's scale, at least 1e-6).
struct MarchPlot {
    std::vector<glm::vec2> radiance, transmittance;
    float sMin = 0.0f, sMax = 0.0f, lMax = 1e-6f;
    std::string caption;  // "L (mean rgb) and T along the ray: N samples, L = .., T = .."
};
MarchPlot marchPlot(const PixelMarch& march);

}  // namespace raster::tools
