// Stage 3, the geometry shader: one invocation per input primitive; its output strips are cut
// into primitives here (a strip of n vertices gives n - 2 triangles with alternating winding,
// n - 1 lines, or n points). Without a geometry shader (NoGeometryShader) this file is not used.
#pragma once

#include <array>

#include "raster/shader.hpp"

namespace raster {

// Runs gs on the primitive `in` and calls emit(kind, vertices) for each primitive it produced.
// A single strip of exactly four vertices is first offered whole to emit_quad(vertices[4]) (the
// billboard case, see setupRectangle); if that returns true its two triangles are not emitted.
// Returns how many vertices the shader appended past its [maxvertexcount] (they were dropped).
template <class GS, class Emit, class EmitQuad>
int runGeometryShader(const GS& gs, const std::array<GeometryShaderInput<GS>, size_t(kGeometryShaderInputKind<GS>)>& in,
                      GeometryShaderStream<GS>& stream, Emit&& emit, EmitQuad&& emit_quad) {
    using Stream = GeometryShaderStream<GS>;
    using Out = typename Stream::Vertex;
    stream.reset();
    gs(in, stream);
    const int n = stream.size();
    if constexpr (Stream::kKind == PrimitiveKind::Triangle && Stream::kMaxVertices >= 4) {
        if (n == 4 && !stream.startsStrip(1) && !stream.startsStrip(2) && !stream.startsStrip(3)) {
            const Out* quad[4] = {&stream.vertex(0), &stream.vertex(1), &stream.vertex(2), &stream.vertex(3)};
            if (emit_quad(quad)) return stream.overflow();
        }
    }
    int strip_begin = 0;
    for (int end = 1; end <= n; ++end) {
        if (end < n && !stream.startsStrip(end)) continue;
        const int len = end - strip_begin;
        for (int i = 0; i < len; ++i) {
            const int v = strip_begin + i;
            if constexpr (Stream::kKind == PrimitiveKind::Point) {
                const Out* p[1] = {&stream.vertex(v)};
                emit(PrimitiveKind::Point, p);
            } else if constexpr (Stream::kKind == PrimitiveKind::Line) {
                if (i + 1 >= len) break;
                const Out* p[2] = {&stream.vertex(v), &stream.vertex(v + 1)};
                emit(PrimitiveKind::Line, p);
            } else {
                if (i + 2 >= len) break;
                const bool odd = i % 2 == 1;
                const Out* p[3] = {&stream.vertex(v), &stream.vertex(odd ? v + 2 : v + 1),
                                   &stream.vertex(odd ? v + 1 : v + 2)};
                emit(PrimitiveKind::Triangle, p);
            }
        }
        strip_begin = end;
    }
    return stream.overflow();
}

template <class GS, class Emit>
int runGeometryShader(const GS& gs, const std::array<GeometryShaderInput<GS>, size_t(kGeometryShaderInputKind<GS>)>& in,
                      GeometryShaderStream<GS>& stream, Emit&& emit) {
    return runGeometryShader(gs, in, stream, emit, [](const auto*) { return false; });
}

}  // namespace raster
