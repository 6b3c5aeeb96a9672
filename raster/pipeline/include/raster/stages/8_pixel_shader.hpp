// Stage 8, the pixel shader: interpolate the vertices' attributes at a pixel centre and run the
// student's functor, a 2×2 quad at a time.
//
// Interpolation rules (Direct3D 11):
//  - depth is linear in screen space: z = Σ b_k z_k with the screen-space barycentrics
//    b_k = E_{k+1} / area2 taken from the exact integer edge functions, then clamped to the
//    viewport's [minDepth, maxDepth];
//  - every other attribute is perspective-correct: a = Σ b_k a_k / w_k ÷ Σ b_k / w_k;
//  - SV_Position arrives as (pixel centre x, pixel centre y, depth, w).
// The fast pipeline does this in float, the reference pipeline in double (rounded to float once,
// when the value is handed to the shader).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>

#include "raster/shader.hpp"
#include "raster/shader_context.hpp"
#include "raster/stages/5_setup.hpp"
#include "raster/stages/7_rasterizer.hpp"
#include "raster/statistics.hpp"

namespace raster {

// Per-triangle constants of interpolation.
template <class Real>
struct TriangleInterpolant {
    Real invArea;
    Real z[3], invW[3];
    explicit TriangleInterpolant(const TriangleSetup& t) : invArea(Real(1) / Real(t.area2)) {
        for (int k = 0; k < 3; ++k) z[k] = Real(t.z[k]), invW[k] = Real(t.invW[k]);
    }
};

// Screen-space barycentrics of the lane whose edge functions are e.
template <class Real>
struct Barycentrics {
    Real b[3];
};

template <class Real>
Barycentrics<Real> barycentrics(const TriangleInterpolant<Real>& ti, int64_t e0, int64_t e1, int64_t e2) {
    return {{Real(e1) * ti.invArea, Real(e2) * ti.invArea, Real(e0) * ti.invArea}};
}

// Depth is computed in double in both pipelines, from the exact edge functions, and rounded to
// float once: the depth test then gives the same answer in the fast and the reference pipeline,
// which matters where a billboard of constant depth cuts through a sloped surface.
//
// A triangle of one depth Z (TriangleSetup::flatDepth) gets Z, clamped, without the arithmetic.
// Inside it that is the formula's own result: the three products have one sign and sum to
// Z·area2·(1 + δ), |δ| < 2^-50, which rounds to the float Z. Outside (a block's helper lanes) the
// formula could lose digits to cancellation; there Z is the exact value it approximates.
inline float flatDepth(const TriangleSetup& t, float min_depth, float max_depth) {
    float z = t.z[0];
    z = z < min_depth ? min_depth : z;  // std::clamp's order: below lo → lo, then above hi → hi
    return max_depth < z ? max_depth : z;
}

template <class Real>
Real interpolateDepth(const TriangleSetup& t, int64_t e0, int64_t e1, int64_t e2, float min_depth, float max_depth) {
    if (t.flatDepth) return Real(flatDepth(t, min_depth, max_depth));
    const double z = (double(e1) * t.z[0] + double(e2) * t.z[1] + double(e0) * t.z[2]) * t.invArea2;
    return Real(float(std::clamp(z, double(min_depth), double(max_depth))));
}

// Fills `out` (the pixel shader's input) for pixel (px, py) with depth z.
template <class Real, class V>
void interpolateAttributes(const TriangleInterpolant<Real>& ti, const Barycentrics<Real>& b, const V* const (&v)[3],
                           int32_t px, int32_t py, Real z, V& out) {
    Real f0 = b.b[0] * ti.invW[0], f1 = b.b[1] * ti.invW[1], f2 = b.b[2] * ti.invW[2];
    const Real w = Real(1) / (f0 + f1 + f2);
    f0 *= w, f1 *= w, f2 *= w;
    const float* a0 = asFloats(*v[0]);
    const float* a1 = asFloats(*v[1]);
    const float* a2 = asFloats(*v[2]);
    float* o = asFloats(out);
    o[0] = float(px) + 0.5f;
    o[1] = float(py) + 0.5f;
    o[2] = float(z);
    o[3] = float(w);
    for (uint32_t i = 4; i < kVertexFloats<V>; ++i) o[i] = float(f0 * Real(a0[i]) + f1 * Real(a1[i]) + f2 * Real(a2[i]));
}

// Fills `out` for a pixel of a line at parameter t (0 at vertex 0) or of a point (one vertex).
template <class Real, class V>
void interpolateLine(const LineSetup& l, const V* const (&v)[2], int32_t px, int32_t py, double t, float min_depth,
                     float max_depth, V& out, Real& z) {
    const Real s = Real(t);
    z = std::clamp(Real(l.z[0]) + s * (Real(l.z[1]) - Real(l.z[0])), Real(min_depth), Real(max_depth));
    Real f0 = (Real(1) - s) * Real(l.invW[0]), f1 = s * Real(l.invW[1]);
    const Real w = Real(1) / (f0 + f1);
    f0 *= w, f1 *= w;
    const float* a0 = asFloats(*v[0]);
    const float* a1 = asFloats(*v[1]);
    float* o = asFloats(out);
    o[0] = float(px) + 0.5f, o[1] = float(py) + 0.5f, o[2] = float(z), o[3] = float(w);
    for (uint32_t i = 4; i < kVertexFloats<V>; ++i) o[i] = float(f0 * Real(a0[i]) + f1 * Real(a1[i]));
}

template <class Color>
bool isDiscarded(const Color&) { return false; }
template <class Color>
bool isDiscarded(const std::optional<Color>& c) { return !c.has_value(); }
template <class Color>
const Color& colorsOf(const Color& c) { return c; }
template <class Color>
const Color& colorsOf(const std::optional<Color>& c) { return *c; }

// Runs a pixel shader over quads. While a QuadShader is active on a thread, ddx/ddy and
// Texture2D::Sample in the shader read this quad's derivatives (shader_context.hpp).
template <class PS>
class QuadShader {
public:
    using In = PixelShaderInput<PS>;
    using Out = PixelShaderOutput<PS>;

    explicit QuadShader(const PS& ps) : ps_(ps), previous_(detail::tCurrentQuad) { detail::tCurrentQuad = &ctx_; }
    ~QuadShader() { detail::tCurrentQuad = previous_; }
    QuadShader(const QuadShader&) = delete;
    QuadShader& operator=(const QuadShader&) = delete;

    // Shades the `live` lanes of in[4] into out[4]. If the shader asks for a derivative, the other
    // lanes are filled by fill_helper(lane, in[lane]) and everything is replayed (see
    // shader_context.hpp); otherwise each live lane runs exactly once.
    template <class FillHelper>
    void shade(In (&in)[4], uint32_t live, Out (&out)[4], FillHelper&& fill_helper, PipelineStatistics& stats) {
        ctx_.used = false;
        ctx_.pass = 0;
        for (uint32_t m = live; m; m &= m - 1) {
            const int lane = __builtin_ctz(m);
            ctx_.lane = lane;
            ctx_.call = 0;
            out[lane] = ps_(in[lane]);
        }
        if (!ctx_.used) return;
        for (int lane = 0; lane < 4; ++lane) {
            if (live & (1u << lane)) continue;
            fill_helper(lane, in[lane]);
            ctx_.lane = lane;
            ctx_.call = 0;
            (void)ps_(in[lane]);
            ++stats.helperInvocations;
        }
        for (int pass = 1; pass <= detail::QuadContext::kMaxPasses; ++pass) {
            std::copy(&ctx_.current[0][0], &ctx_.current[0][0] + 4 * detail::QuadContext::kMaxCalls,
                      &ctx_.previous[0][0]);
            ctx_.pass = pass;
            ctx_.changed = false;
            for (int lane = 0; lane < 4; ++lane) {
                ctx_.lane = lane;
                ctx_.call = 0;
                Out o = ps_(in[lane]);
                if (live & (1u << lane)) out[lane] = o;
                ++stats.derivativeReplays;
            }
            if (!ctx_.changed) break;
        }
    }

    // A single pixel (lines and points): no quad, so derivatives read as zero.
    Out shadeSingle(const In& in) {
        detail::tCurrentQuad = nullptr;
        Out o = ps_(in);
        detail::tCurrentQuad = &ctx_;
        return o;
    }

private:
    const PS& ps_;
    detail::QuadContext ctx_;
    detail::QuadContext* previous_;
};

}  // namespace raster
