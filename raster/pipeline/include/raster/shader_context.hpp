// What a pixel shader can ask of the pipeline besides its input: screen-space derivatives of any
// value (HLSL ddx/ddy), which Texture2D::Sample uses for its level of detail.
//
// A GPU runs the pixel shader on 2×2 quads in lock step, so ddx is the difference between
// neighbouring lanes. raster runs the scalar C++ functor once per pixel, so it replays: the first
// pass over a quad records the k-th derivative argument of every lane (derivatives read as zero);
// the next pass answers the k-th call with the finite difference of the recorded values, and so on
// until the recorded arguments no longer change (a dependent chain of derivatives needs one pass
// per link; at most kMaxPasses). A shader that never asks for a derivative runs once per pixel,
// and a quad's uncovered "helper" lanes run only when it does ask.
//
// Derivatives are "fine" (D3D11 ddx_fine / ddy_fine): ddx pairs lanes within the pixel's own row,
// ddy within its own column.
#pragma once

#include <glm/glm.hpp>

namespace raster {

// The derivative of v along screen x and y, in units of v per pixel.
template <class T>
struct Gradient {
    T ddx{};
    T ddy{};
};

namespace detail {

struct QuadContext {
    static constexpr int kMaxCalls = 16;  // derivative calls one invocation may make
    static constexpr int kMaxPasses = 4;
    int lane = 0;  // 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right
    int pass = 0;  // 0: record only; > 0: answer from the previous pass's records
    int call = 0;  // derivative calls so far in this invocation
    bool used = false;      // some lane asked for a derivative
    bool changed = false;   // this pass recorded a value that differs from the previous pass
    bool overflow = false;  // more than kMaxCalls calls: the rest read as zero
    glm::vec4 previous[4][kMaxCalls]{};
    glm::vec4 current[4][kMaxCalls]{};
};

// The quad the calling thread's pixel shader is running in, or nullptr outside a pixel shader.
inline thread_local QuadContext* tCurrentQuad = nullptr;
// True while the calling thread runs the reference (double-precision) pipeline.
inline thread_local bool tReferenceMode = false;

inline Gradient<glm::vec4> quadGradient4(const glm::vec4& v) {
    QuadContext* q = tCurrentQuad;
    if (!q) return {};
    q->used = true;
    const int k = q->call++;
    if (k >= QuadContext::kMaxCalls) {
        q->overflow = true;
        return {};
    }
    q->current[q->lane][k] = v;
    if (q->pass == 0) return {};
    if (q->previous[q->lane][k] != v) q->changed = true;
    const int row = q->lane & 2, col = q->lane & 1;
    return {q->previous[row | 1][k] - q->previous[row][k], q->previous[2 | col][k] - q->previous[col][k]};
}

}  // namespace detail

inline bool inReferenceMode() { return detail::tReferenceMode; }

inline Gradient<float> quadGradient(float v) {
    auto g = detail::quadGradient4(glm::vec4(v, 0, 0, 0));
    return {g.ddx.x, g.ddy.x};
}
inline Gradient<glm::vec2> quadGradient(const glm::vec2& v) {
    auto g = detail::quadGradient4(glm::vec4(v, 0, 0));
    return {glm::vec2(g.ddx), glm::vec2(g.ddy)};
}
inline Gradient<glm::vec3> quadGradient(const glm::vec3& v) {
    auto g = detail::quadGradient4(glm::vec4(v, 0));
    return {glm::vec3(g.ddx), glm::vec3(g.ddy)};
}
inline Gradient<glm::vec4> quadGradient(const glm::vec4& v) { return detail::quadGradient4(v); }

// HLSL's ddx / ddy. Each call is one derivative call (see above); call quadGradient to get both at once.
template <class T>
T ddx(const T& v) { return quadGradient(v).ddx; }
template <class T>
T ddy(const T& v) { return quadGradient(v).ddy; }

}  // namespace raster
