// The plain fill path: one primitive at a time, in the order the tile's bins list them, through the
// stages one 2×2 quad (or one pixel) at a time —
//
//   rasterizer (stages/7_rasterizer.hpp: edge functions, top-left rule)
//     → early depth test (Tile::earlyDepthPasses → the depth policy's test)
//     → pixel shader (stages/8_pixel_shader.hpp: interpolation, QuadShader)
//     → output merger (Tile::depthTestAndBlend: late depth test, depth write, blend)
//
// This is the path to read and to step through in a debugger (ContextOptions::plain takes it for
// every primitive, labs/README.md shows the gdb session). It is also the only path of lines, points,
// traced draws and the reference pipeline; the eight-wide paths give the same bits.
#pragma once

#include <array>
#include <cstdint>

#include "raster/fastpath/rectangle.hpp"
#include "raster/fill/tile.hpp"

namespace raster {

// The triangle a coverage test is given: t's vertices back in the draw's order (setupTriangle swaps
// vertices 1 and 2 of a counter-clockwise triangle) with their unsnapped window positions. Coverage:
// the draw's coverage rule (teaching_pipeline.hpp's TeachingCoverage).
template <class V, class Coverage>
CoverageTriangle coverageTriangle(const TriangleSetup& t, const V* const (&verts)[3], const Coverage& coverage) {
    const bool clockwise = coverage.frontCounterClockwise ? !t.frontFacing : t.frontFacing;
    const int order[3] = {0, clockwise ? 1 : 2, clockwise ? 2 : 1};
    CoverageTriangle triangle;
    for (int k = 0; k < 3; ++k) {
        const glm::vec4& clip = verts[order[k]]->position;
        triangle.x[k] = windowX(clip, coverage.viewport);
        triangle.y[k] = windowY(clip, coverage.viewport);
    }
    return triangle;
}

// A triangle, quad by quad.
template <class T>
void fillTriangleQuads(T& tile, const TriangleSetup& t, const TriangleInterpolant<typename T::RealType>& ti,
                       const EdgeSteps& steps, const typename T::Vertex* const (&verts)[3]) {
    using Real = typename T::RealType;
    using V = typename T::Vertex;
    const float min_depth = tile.draw.minDepth, max_depth = tile.draw.maxDepth;
    auto shade = [&](const Quad& q) {
        // The edge functions at a lane's centre: lane 0's plus the steps.
        auto edges = [&](int lane) {
            const int lx = lane & 1, ly = lane >> 1;
            return std::array<int64_t, 3>{q.e[0] + lx * steps.dx[0] + ly * steps.dy[0],
                                          q.e[1] + lx * steps.dx[1] + ly * steps.dy[1],
                                          q.e[2] + lx * steps.dx[2] + ly * steps.dy[2]};
        };
        tile.shadeQuad(
            q.x, q.y, q.mask,
            [&](int lane) {
                const auto e = edges(lane);
                return interpolateDepth<Real>(t, e[0], e[1], e[2], min_depth, max_depth);
            },
            [&](int lane, Real z, V& in) {
                const auto e = edges(lane);
                interpolateAttributes(ti, barycentrics(ti, e[0], e[1], e[2]), verts, q.x + (lane & 1),
                                      q.y + (lane >> 1), z, in);
            });
    };
    // A draw with a lab's coverage rule (the tile's hooks, draw_hooks.hpp): the lab's test decides
    // which pixel centres are covered. The specialised tile loops have no hooks: compiled out there.
    if constexpr (T::HooksType::kEnabled) {
        if (const auto* coverage = tile.hooks.coverage) {
            const CoverageTriangle triangle = coverageTriangle(t, verts, *coverage);
            rasterizeTriangleCovered(
                t, tile.rect, [&](int32_t x, int32_t y) { return coverage->test(triangle, x, y); }, shade);
            return;
        }
    }
    rasterizeTriangle(t, steps, tile.rect, shade);
}

// A billboard's screen rectangle, quad by quad: attribute = base + i·step_x + j·step_y at pixel
// (x0 + i, y0 + j) of its box, one depth z.
template <class T>
void fillRectangleQuads(T& tile, const RectSetup& r, const float* base, const float* step_x,
                        const float* step_y, typename T::RealType z) {
    using Real = typename T::RealType;
    using V = typename T::Vertex;
    rasterizeRect(r.box, tile.rect, [&](int32_t qx, int32_t qy, uint32_t mask) {
        tile.shadeQuad(
            qx, qy, mask, [&](int) { return z; },
            [&](int lane, Real, V& in) {
                const float i = float(qx + (lane & 1) - r.box.x0);
                const float j = float(qy + (lane >> 1) - r.box.y0);
                float* o = asFloats(in);
                for (uint32_t k = 0; k < kVertexFloats<V>; ++k)
                    o[k] = base[k] + i * step_x[k] + j * step_y[k];
            });
    });
}

// A line, pixel by pixel (no quads: D3D11 lines have no derivatives here).
template <class T>
void fillLine(T& tile, const LineSetup& l, const typename T::Vertex* const (&verts)[2]) {
    using Real = typename T::RealType;
    rasterizeLine(l, tile.rect, [&](int32_t x, int32_t y, double t) {
        typename T::Vertex in;
        Real z;
        interpolateLine<Real>(l, verts, x, y, t, tile.draw.minDepth, tile.draw.maxDepth, in, z);
        if (!tile.earlyDepthPasses(x, y, z)) return;
        tile.countShaded(1, 0);
        tile.merge(x, y, z, tile.shader.shadeSingle(in));
    });
}

// A point: one pixel, if it lies in the tile.
template <class T>
void fillPoint(T& tile, const PointSetup& pt, const typename T::Vertex& vertex) {
    using Real = typename T::RealType;
    const PixelRect& rect = tile.rect;
    if (pt.px < rect.x0 || pt.px > rect.x1 || pt.py < rect.y0 || pt.py > rect.y1) return;
    typename T::Vertex in = vertex;
    const Real z = std::clamp(Real(pt.z), Real(tile.draw.minDepth), Real(tile.draw.maxDepth));
    const float w = in.position.w;
    in.position = glm::vec4(float(pt.px) + 0.5f, float(pt.py) + 0.5f, float(z), w);
    if (!tile.earlyDepthPasses(pt.px, pt.py, z)) return;
    tile.countShaded(1, 0);
    tile.merge(pt.px, pt.py, z, tile.shader.shadeSingle(in));
}

}  // namespace raster
