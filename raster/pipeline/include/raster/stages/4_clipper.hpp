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
// Precision: distances are signed exactly (double), and a cut's new position is computed from
// exact sums of products (detail::intersect), so any finite input, up to ±3.4e38, is cut where the
// exact plane crosses its edge, to float's last bits: no half-plane is lost to cancellation.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "raster/check.hpp"
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

// A plane's signed distance d(p) = P·p + k, positive inside (P and k below); in double, where the
// product of two floats is exact and the one rounding of the sum cannot change its sign, so the
// outcode and the clipper agree on which side a vertex lies for any finite input.
struct ClipPlane {
    double p[4] = {0, 0, 0, 0};  // coefficients of x, y, z, w (each 0, ±1 or ±g, a float)
    double k = 0;                // constant term (−kMinW for the w plane, else 0)
};

inline ClipPlane clipPlane(int plane, const ClipPlanes& c) {
    const double gx = c.guardX, gy = c.guardY;
    switch (plane) {
        case 0: return {{0, 0, 1, 0}, 0};
        case 1: return {{0, 0, -1, 1}, 0};
        case 2: return {{1, 0, 0, gx}, 0};
        case 3: return {{-1, 0, 0, gx}, 0};
        case 4: return {{0, 1, 0, gy}, 0};
        case 5: return {{0, -1, 0, gy}, 0};
        default: return {{0, 0, 0, 1}, -double(kMinW)};
    }
}

inline double clipDistance(const glm::vec4& p, int plane, const ClipPlanes& c) {
    switch (plane) {
        case 0: return p.z;
        case 1: return double(p.w) - p.z;
        case 2: return p.x + double(c.guardX) * p.w;
        case 3: return double(c.guardX) * p.w - p.x;
        case 4: return p.y + double(c.guardY) * p.w;
        case 5: return double(c.guardY) * p.w - p.y;
        default: return double(p.w) - double(kMinW);
    }
}

inline uint32_t outcode(const glm::vec4& p, const ClipPlanes& c) {
    uint32_t code = 0;
    for (int plane = 0; plane < 7; ++plane) {
        if (plane == 1 && !c.depthClip) continue;
        if (!(clipDistance(p, plane, c) >= 0.0)) code |= 1u << plane;
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

// A sum of doubles kept exactly, as an expansion: terms of increasing magnitude whose bits do not
// overlap, each new term added by TwoSum (Shewchuk 1997, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates"). Cancellation between huge terms then loses
// nothing, and value() is the sum rounded (within 2 ulp). The clipper's intersections use it.
class ExactSum {
  public:
    static constexpr int kMaxTerms = 24;
    void add(double x) {
        int m = 0;
        for (int i = 0; i < n_; ++i) {  // TwoSum(x, term): s + err is exactly x + term
            const double s = x + term_[i];
            const double b_virtual = s - x;
            const double err = (x - (s - b_virtual)) + (term_[i] - b_virtual);
            if (err != 0.0) term_[m++] = err;
            x = s;
        }
        if (x != 0.0) term_[m++] = x;
        n_ = m;
        RASTER_DCHECK(n_ < kMaxTerms);
    }
    // a·b exactly: the rounded product and its rounding error (one FMA).
    void addProduct(double a, double b) {
        const double p = a * b;
        add(std::fma(a, b, -p));
        add(p);
    }
    double value() const {
        double s = 0.0;
        for (int i = 0; i < n_; ++i) s += term_[i];
        return s;
    }

  private:
    double term_[kMaxTerms];
    int n_ = 0;
};

// Where the edge from `inside` (distance ≥ 0) to `outside` (< 0) crosses the plane. The position
// is v = (d_b·a − d_a·b) / (d_b − d_a), its numerator and denominator summed exactly from products
// of the coordinates (the plane's coefficients are floats, so each product is two doubles at most):
// for an edge between vertices at ±1e38 the result is right to the last bits of float, where
// a + t·(b − a) would cancel to nothing (a triangle with a vertex at 1e15 lost half the screen
// that way). The other attributes are interpolated in double with t = d_a / (d_a − d_b).
template <class V>
V intersect(const V& inside, const V& outside, const ClipPlane& plane) {
    const glm::vec4 &a = inside.position, &b = outside.position;
    ExactSum den, dist_a;  // d_b − d_a, and d_a
    for (int j = 0; j < 4; ++j) {
        if (plane.p[j] == 0.0) continue;
        den.addProduct(plane.p[j], b[j]);
        den.addProduct(-plane.p[j], a[j]);
        dist_a.addProduct(plane.p[j], a[j]);
    }
    dist_a.add(plane.k);
    const double d = den.value();  // < 0: d_b < 0 ≤ d_a
    const double t = -dist_a.value() / d;
    V r;
    const float* fa = asFloats(inside);
    const float* fb = asFloats(outside);
    float* o = asFloats(r);
    for (uint32_t i = 0; i < kVertexFloats<V>; ++i) o[i] = float(fa[i] + t * (double(fb[i]) - fa[i]));
    for (int i = 0; i < 4; ++i) {
        ExactSum num;  // Σ_j P_j·(b_j·a_i − a_j·b_i) + k·(a_i − b_i)
        for (int j = 0; j < 4; ++j) {
            if (plane.p[j] == 0.0 || j == i) continue;  // the j = i minor is 0
            num.addProduct(plane.p[j] * b[j], a[i]);    // P_j·b_j is exact: a float times a float
            num.addProduct(-plane.p[j] * a[j], b[i]);
        }
        if (plane.k != 0.0) {
            num.addProduct(plane.k, a[i]);
            num.addProduct(-plane.k, b[i]);
        }
        r.position[i] = float(num.value() / d);
    }
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
        const ClipPlane cp = clipPlane(plane, planes);
        auto inside = [&](const V& v) { return clipDistance(v.position, plane, planes) >= 0.0; };
        int out = 0;
        if constexpr (N == 2) {
            const bool in0 = inside(src[0]), in1 = inside(src[1]);
            if (in0 && in1) {
                dst[0] = src[0], dst[1] = src[1], out = 2;
            } else if (in0) {
                dst[0] = src[0], dst[1] = detail::intersect(src[0], src[1], cp), out = 2;
            } else if (in1) {
                dst[0] = detail::intersect(src[1], src[0], cp), dst[1] = src[1], out = 2;
            }
        } else {
            for (int i = 0; i < count; ++i) {
                const V& p = src[i];
                const V& q = src[(i + 1) % count];
                const bool p_in = inside(p), q_in = inside(q);
                if (p_in) dst[out++] = p;
                if (p_in != q_in) dst[out++] = p_in ? detail::intersect(p, q, cp) : detail::intersect(q, p, cp);
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
