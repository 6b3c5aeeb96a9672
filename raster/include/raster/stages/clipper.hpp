// Stage 4, clipping in homogeneous clip space (before the divide by w).
//
// Planes, a point p = (x, y, z, w) being inside when every distance is >= 0:
//   near   z            (D3D's depth range starts at z = 0)
//   far    w - z        (only when the rasterizer state's depthClipEnable is on)
//   guard  x + g·w, g·w - x, y + g·w, g·w - y, where g puts the guard band kGuardBandPixels
//          beyond the viewport on every side: triangles that merely cross the viewport's edges
//          are not cut (the rasteriser's viewport rectangle trims them for free); only those that
//          reach past the guard band are, which keeps screen positions inside 16.8 fixed point.
//   w      w - kMinW    (so the divide by w is always defined)
// A primitive whose vertices all lie outside one plane, or all outside one side of the viewport
// (|x| > w or |y| > w on the same side), is rejected whole. A cut edge's new vertex is always
// computed from its inside end towards its outside end, so two triangles sharing an edge get the
// bit-identical point and the mesh stays watertight. A polygon that results is split into a fan.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "raster/shader.hpp"

namespace raster {

constexpr float kGuardBandPixels = 16384.0f;
constexpr float kMinW = 1e-20f;

struct ClipPlanes {
    float guardX = 1, guardY = 1;  // g above, per axis
    bool depthClip = true;
};

enum ClipBit : uint32_t {
    kClipNear = 1u << 0,
    kClipFar = 1u << 1,
    kClipGuardLeft = 1u << 2,
    kClipGuardRight = 1u << 3,
    kClipGuardBottom = 1u << 4,
    kClipGuardTop = 1u << 5,
    kClipW = 1u << 6,
    kClipPlanesMask = (1u << 7) - 1,
    // Outside the viewport itself: used only to reject, never to cut.
    kOutLeft = 1u << 8,
    kOutRight = 1u << 9,
    kOutBottom = 1u << 10,
    kOutTop = 1u << 11,
};

inline float clipDistance(const glm::vec4& p, int plane, const ClipPlanes& c) {
    switch (plane) {
        case 0: return p.z;
        case 1: return p.w - p.z;
        case 2: return p.x + c.guardX * p.w;
        case 3: return c.guardX * p.w - p.x;
        case 4: return p.y + c.guardY * p.w;
        case 5: return c.guardY * p.w - p.y;
        default: return p.w - kMinW;
    }
}

inline uint32_t outcode(const glm::vec4& p, const ClipPlanes& c) {
    uint32_t code = 0;
    for (int plane = 0; plane < 7; ++plane) {
        if (plane == 1 && !c.depthClip) continue;
        if (!(clipDistance(p, plane, c) >= 0.0f)) code |= 1u << plane;
    }
    if (p.x < -p.w) code |= kOutLeft;
    if (p.x > p.w) code |= kOutRight;
    if (p.y < -p.w) code |= kOutBottom;
    if (p.y > p.w) code |= kOutTop;
    return code;
}

inline bool isFinite(const glm::vec4& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}

namespace detail {

template <class V>
V lerpFromInside(const V& inside, const V& outside, float d_in, float d_out) {
    const float t = d_in / (d_in - d_out);
    V r;
    const float* a = asFloats(inside);
    const float* b = asFloats(outside);
    float* o = asFloats(r);
    for (uint32_t i = 0; i < kVertexFloats<V>; ++i) o[i] = a[i] + t * (b[i] - a[i]);
    return r;
}

}  // namespace detail

// Clips the triangle (or, with N = 2, the line) against the planes in `cut` (ClipBit bits) and
// calls emit(const V*[N]) for each resulting primitive. Returns the number emitted.
template <int N, class V, class Emit>
int clipPrimitive(const V* const (&in)[N], uint32_t cut, const ClipPlanes& planes, Emit&& emit) {
    constexpr int kMax = N + 7;
    V buf[2][kMax];
    int count = N;
    for (int i = 0; i < N; ++i) buf[0][i] = *in[i];
    int cur = 0;
    for (int plane = 0; plane < 7 && count > 0; ++plane) {
        if (!(cut & (1u << plane))) continue;
        const V* src = buf[cur];
        V* dst = buf[cur ^ 1];
        int out = 0;
        if constexpr (N == 2) {
            const float d0 = clipDistance(src[0].position, plane, planes);
            const float d1 = clipDistance(src[1].position, plane, planes);
            const bool in0 = d0 >= 0, in1 = d1 >= 0;
            if (in0 && in1) {
                dst[0] = src[0], dst[1] = src[1], out = 2;
            } else if (in0) {
                dst[0] = src[0], dst[1] = detail::lerpFromInside(src[0], src[1], d0, d1), out = 2;
            } else if (in1) {
                dst[0] = detail::lerpFromInside(src[1], src[0], d1, d0), dst[1] = src[1], out = 2;
            }
        } else {
            for (int i = 0; i < count; ++i) {
                const V& p = src[i];
                const V& q = src[(i + 1) % count];
                const float dp = clipDistance(p.position, plane, planes);
                const float dq = clipDistance(q.position, plane, planes);
                const bool p_in = dp >= 0, q_in = dq >= 0;
                if (p_in) dst[out++] = p;
                if (p_in != q_in)
                    dst[out++] = p_in ? detail::lerpFromInside(p, q, dp, dq) : detail::lerpFromInside(q, p, dq, dp);
            }
        }
        count = out;
        cur ^= 1;
    }
    if constexpr (N == 2) {
        if (count < 2) return 0;
        const V* line[2] = {&buf[cur][0], &buf[cur][1]};
        emit(line);
        return 1;
    } else {
        int emitted = 0;
        for (int i = 1; i + 1 < count; ++i) {
            const V* tri[3] = {&buf[cur][0], &buf[cur][i], &buf[cur][i + 1]};
            emit(tri);
            ++emitted;
        }
        return emitted;
    }
}

}  // namespace raster
