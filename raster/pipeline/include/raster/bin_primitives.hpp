// Stages 4 to 6 assembled for one primitive on a geometry thread: the clipper (stages/4_clipper.hpp),
// setup (stages/5_setup.hpp) and the binner (stages/6_binner.hpp) in that order, writing into the
// chunk of primitives the tiles later read. The billboard rectangle (fastpath/rectangle.hpp) is tried
// first for four-vertex strips. Every primitive is counted here, once, by what happened to it.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/draw_hooks.hpp"
#include "raster/fastpath/rectangle.hpp"
#include "raster/stages/4_clipper.hpp"
#include "raster/stages/5_setup.hpp"
#include "raster/stages/6_binner.hpp"
#include "raster/statistics.hpp"

namespace raster {

namespace detail {

// The binner's output for one chunk of primitives, filled by the geometry stages (GS, clip, setup,
// bin) on one thread: the vertices and setups of its primitives and, per tile, which of them touch
// it. Aligned to a cache line: neighbouring chunks are filled by different threads at once.
template <class V>
struct alignas(64) Chunk {
    std::vector<V> vertices;  // clip-space vertices the setups refer to
    std::vector<TriangleSetup> triangles;
    std::vector<LineSetup> lines;
    std::vector<PointSetup> points;
    std::vector<RectSetup> rects;
    std::vector<std::vector<uint32_t>> bins;  // per tile, bin entries in primitive order
    PipelineStatistics stats;
    int gsOverflow = 0;
    uint32_t gsOverflowPrimitive = 0;
    // Trace records (only while a trace with geometry is set, draw_hooks.hpp), at most traceCap of each.
    bool tracing = false;
    uint32_t traceCap = 0;
    std::vector<TraceGsVertex> traceGs;
    std::vector<TracePrimitive> tracePrimitives;
    uint64_t traceGsTotal = 0, tracePrimitivesTotal = 0;

    void reset(uint32_t tiles) {
        vertices.clear(), triangles.clear(), lines.clear(), points.clear(), rects.clear();
        bins.resize(tiles);
        for (auto& b : bins) b.clear();
        stats = {};
        gsOverflow = 0;
        tracing = false;
        traceGs.clear(), tracePrimitives.clear();
        traceGsTotal = tracePrimitivesTotal = 0;
    }
    // Notes what happened to a primitive (s: its screen vertices, n of them; none if rejected early).
    void trace(uint32_t primitive, PrimitiveKind kind, PrimitiveFate fate, bool clipped,
               const ScreenVertex* s, int n, const float* w = nullptr) {
        if (!tracing) return;
        if (tracePrimitivesTotal++ >= traceCap) return;
        TracePrimitive t{primitive, kind, fate, clipped, uint8_t(n), {}};
        for (int i = 0; i < n; ++i)
            t.screen[i] = glm::vec4(float(s[i].x) / kSubpixelOne, float(s[i].y) / kSubpixelOne, s[i].z,
                                    w ? w[i] : (s[i].invW != 0.0f ? 1.0f / s[i].invW : 0.0f));
        tracePrimitives.push_back(t);
    }
};

// Where a draw's primitives go after the geometry shader: the clip planes (the guard band), the
// viewport transform to 16.8 fixed-point pixels, the pixels that may be written, and the tiles.
struct PrimitiveSpace {
    PixelRect clip;
    TileGrid grid;
    ClipPlanes planes;
    ViewportTransform viewport;
    // A draw with a lab's coverage rule (DrawHooks::coverage, draw_hooks.hpp): each triangle goes to
    // every tile of its box, since the lab's test, not the library's edges, decides which pixels it
    // covers.
    bool binWholeBoxes = false;
};

// A billboard quad from the geometry shader (a four-vertex strip) set up as one screen rectangle
// when it is one (setupRectangle) and lies inside the clip planes, then binned. False where it is not
// such a rectangle: the strip's two triangles then go through clipSetupAndBin.
template <class V>
bool setupAndBinRectangle(const V* const* quad, uint32_t primitive_id, const PrimitiveSpace& plan,
                          const RasterizerState& rs, Chunk<V>& chunk) {
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
                    culled          ? PrimitiveFate::Culled
                    : r.box.empty() ? PrimitiveFate::NoPixels
                                    : PrimitiveFate::Rectangle,
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

// A line (clipped: a piece of a cut primitive) set up and binned, or counted as drawing no pixel.
template <class V>
void setupAndBinLine(const ScreenVertex (&s)[2], const uint32_t (&idx)[2], uint32_t primitive_id,
                     bool clipped, const PrimitiveSpace& plan, Chunk<V>& chunk) {
    PipelineStatistics& st = chunk.stats;
    LineSetup l;
    if (!setupLine(s, idx, primitive_id, plan.clip, l)) {
        ++st.primitivesNoPixels;
        chunk.trace(primitive_id, PrimitiveKind::Line, PrimitiveFate::NoPixels, clipped, s, 2);
        return;
    }
    chunk.trace(primitive_id, PrimitiveKind::Line, PrimitiveFate::Rasterized, clipped, s, 2);
    const uint32_t index = uint32_t(chunk.lines.size());
    chunk.lines.push_back(l);
    st.tilesBinned += binBox(l.box, plan.grid, [&](uint32_t tile) {
        chunk.bins[tile].push_back(binEntry(PrimitiveKind::Line, index));
    });
}

// A triangle whose vertices are chunk.vertices[base, base + 3) set up and binned; culled,
// degenerate or pixel-less ones counted and their vertices dropped again.
template <class V>
void setupAndBinTriangle(const ScreenVertex (&s)[3], const uint32_t (&idx)[3], uint32_t base,
                         uint32_t primitive_id, bool clipped, const PrimitiveSpace& plan,
                         const RasterizerState& rs, Chunk<V>& chunk) {
    PipelineStatistics& st = chunk.stats;
    TriangleSetup t;
    const SetupResult result = setupTriangle(s, idx, primitive_id, rs, plan.clip, t);
    if (chunk.tracing) {
        constexpr PrimitiveFate kFates[] = {PrimitiveFate::Rasterized, PrimitiveFate::Culled,
                                            PrimitiveFate::Degenerate, PrimitiveFate::NoPixels};
        chunk.trace(primitive_id, PrimitiveKind::Triangle, kFates[int(result)], clipped, s, 3);
    }
    switch (result) {
        case SetupResult::Culled:
            ++st.primitivesCulled;
            break;
        case SetupResult::Degenerate:
            ++st.primitivesDegenerate;
            break;
        case SetupResult::NoPixels:
            ++st.primitivesNoPixels;
            break;
        case SetupResult::Ok: {
            const uint32_t index = uint32_t(chunk.triangles.size());
            chunk.triangles.push_back(t);
            if (plan.binWholeBoxes) {
                st.tilesBinned += binBox(t.box, plan.grid, [&](uint32_t tile) {
                    chunk.bins[tile].push_back(binEntry(PrimitiveKind::Triangle, index));
                });
                return;
            }
            binTriangle(
                t, plan.grid,
                [&](uint32_t tile) { chunk.bins[tile].push_back(binEntry(PrimitiveKind::Triangle, index)); },
                st.tilesBinned, st.tilesRejected);
            return;
        }
    }
    chunk.vertices.resize(base);
}

// A wireframe triangle: culled as a solid one would be, then its three edges as lines.
template <class V>
void setupAndBinWireframe(const ScreenVertex (&s)[3], const uint32_t (&idx)[3], uint32_t primitive_id,
                          bool clipped, const PrimitiveSpace& plan, const RasterizerState& rs,
                          Chunk<V>& chunk) {
    TriangleSetup t;  // for culling only
    const SetupResult r = setupTriangle(s, idx, primitive_id, rs, plan.clip, t);
    if (r == SetupResult::Culled) ++chunk.stats.primitivesCulled;
    if (r == SetupResult::Culled || r == SetupResult::Degenerate) {
        chunk.trace(primitive_id, PrimitiveKind::Triangle,
                    r == SetupResult::Culled ? PrimitiveFate::Culled : PrimitiveFate::Degenerate, clipped, s,
                    3);
        return;
    }
    for (int e = 0; e < 3; ++e) {
        const int e1 = (e + 1) % 3;
        setupAndBinLine({s[e], s[e1]}, {idx[e], idx[e1]}, primitive_id, clipped, plan, chunk);
    }
}

// A point set up and binned (its vertex is chunk.vertices[idx]), or counted as drawing no pixel.
template <class V>
void setupAndBinPoint(const ScreenVertex& s, uint32_t idx, uint32_t primitive_id, bool clipped,
                      const PrimitiveSpace& plan, Chunk<V>& chunk) {
    PipelineStatistics& st = chunk.stats;
    PointSetup pt;
    const bool has_pixels = setupPoint(s, idx, primitive_id, plan.clip, pt);
    chunk.trace(primitive_id, PrimitiveKind::Point,
                has_pixels ? PrimitiveFate::Rasterized : PrimitiveFate::NoPixels, clipped, &s, 1);
    if (!has_pixels) {
        ++st.primitivesNoPixels;
        chunk.vertices.resize(idx);
        return;
    }
    const uint32_t index = uint32_t(chunk.points.size());
    chunk.points.push_back(pt);
    const PixelRect box{pt.px, pt.py, pt.px, pt.py};
    st.tilesBinned += binBox(box, plan.grid, [&](uint32_t tile) {
        chunk.bins[tile].push_back(binEntry(PrimitiveKind::Point, index));
    });
}

// One primitive inside the clip planes (a whole one, or a piece the clipper cut): its vertices kept
// in the chunk, taken to 16.8 fixed-point screen space, set up and binned.
template <class V>
void setupAndBin(PrimitiveKind kind, const V* const* pv, uint32_t primitive_id, bool clipped,
                 const PrimitiveSpace& plan, const RasterizerState& rs, Chunk<V>& chunk) {
    ++chunk.stats.cPrimitives;
    const int n = int(kind);
    const uint32_t base = uint32_t(chunk.vertices.size());
    ScreenVertex s[3];
    uint32_t idx[3];
    for (int i = 0; i < n; ++i) {
        chunk.vertices.push_back(*pv[i]);
        s[i] = toScreen(pv[i]->position, plan.viewport);
        idx[i] = base + uint32_t(i);
    }
    switch (kind) {
        case PrimitiveKind::Triangle:
            if (rs.fillMode == FillMode::Wireframe)
                setupAndBinWireframe(s, idx, primitive_id, clipped, plan, rs, chunk);
            else
                setupAndBinTriangle(s, idx, base, primitive_id, clipped, plan, rs, chunk);
            return;
        case PrimitiveKind::Line:
            setupAndBinLine({s[0], s[1]}, {idx[0], idx[1]}, primitive_id, clipped, plan, chunk);
            return;
        case PrimitiveKind::Point:
            setupAndBinPoint(s[0], idx[0], primitive_id, clipped, plan, chunk);
            return;
    }
}

// One primitive through the clipper (stages/4_clipper.hpp: trivial accept and reject by outcodes, or
// cut against the planes), then each whole primitive or piece through setupAndBin. Counts and traces
// what happened to it.
template <class V>
void clipSetupAndBin(PrimitiveKind kind, const V* const* v, uint32_t primitive_id, const PrimitiveSpace& plan,
                     const RasterizerState& rs, Chunk<V>& chunk) {
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
    auto emit = [&](const V* const* pv) { setupAndBin(kind, pv, primitive_id, cut != 0, plan, rs, chunk); };
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

}  // namespace detail

}  // namespace raster
