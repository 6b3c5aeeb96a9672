// Metaballs: a volume model made of simple implicit blobs (NOTES.md, part 1, "Térfogati
// adatmodellek"), and the box that bounds a medium, as the benchmark scene `media` defines them
// (../shared/bench/SCENES.md, "Scene media").
//
// Density ρ(x) = Σ_k (1 − u_k)² over the balls with u_k = |x − c_k|²/r_k² < 1, else 0: smooth (its
// gradient vanishes at each ball's surface), exactly 0 outside every ball, at most 1 per ball. The
// scene's extinction is μ(x) = 4·ρ(x) per metre.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <utility>

#include "raster/simd.hpp"

namespace raster::media {

struct Metaball {
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
};

// An axis-aligned box [lo, hi] (metres).
struct Box {
    glm::vec3 lo{0.0f}, hi{0.0f};
};

// The slab test: the ray o + t·d meets the box for t in [first, second] (first > second where it
// misses). d's components may be 0: the slab then holds the whole line (o inside it, bounds
// included) or none of it. T is float, Float8 or Float8x2 (one ray per lane, the same origin): the
// same operations per lane, so the eight-wide pixel shader and the scalar one agree bit for bit.
template <class T>
std::pair<T, T> slabInterval(const Box& box, const glm::vec3& o, const glm::vec<3, T>& d) {
    T t_near(-INFINITY), t_far(INFINITY);
    for (int a = 0; a < 3; ++a) {
        const T inv = T(1.0f) / d[a];
        const T t_a = T(box.lo[a] - o[a]) * inv, t_b = T(box.hi[a] - o[a]) * inv;
        const auto swapped = t_b < t_a;
        const T lo = select(swapped, t_b, t_a), hi = select(swapped, t_a, t_b);
        const bool inside = o[a] >= box.lo[a] && o[a] <= box.hi[a];
        const auto parallel = d[a] == T(0.0f);
        t_near = select(parallel, inside ? t_near : T(INFINITY), select(t_near < lo, lo, t_near));
        t_far = select(parallel, inside ? t_far : T(-INFINITY), select(hi < t_far, hi, t_far));
    }
    return {t_near, t_far};
}

// One ball's contribution (1 − u)² where u = |x − c|²/r² < 1, else 0.
inline float metaballTerm(const Metaball& ball, const glm::vec3& x) {
    const glm::vec3 v = x - ball.centre;
    const float u = glm::dot(v, v) / (ball.radius * ball.radius);
    return u < 1.0f ? (1.0f - u) * (1.0f - u) : 0.0f;
}

template <size_t N>
float metaballDensity(const std::array<Metaball, N>& balls, const glm::vec3& x) {
    float rho = 0.0f;
    for (const Metaball& ball : balls) rho += metaballTerm(ball, x);
    return rho;
}

// The upper bound of metaballDensity over a box: each ball contributes (1 − d²/r²)² with d the
// distance from its centre to the box (0 inside), its largest value there. Exact 0 where no ball
// reaches the box, which is what empty-space skipping needs: a majorant of 0 means every density
// sample in the box is 0. The radius is widened by 1e-5 relative so that float rounding of a sample's
// u cannot put a point the bound calls outside inside a ball.
template <size_t N>
float metaballMajorant(const std::array<Metaball, N>& balls, const Box& box) {
    float bound = 0.0f;
    for (const Metaball& ball : balls) {
        const glm::vec3 nearest = glm::clamp(ball.centre, box.lo, box.hi);
        const glm::vec3 v = nearest - ball.centre;
        const float r = ball.radius * (1.0f + 1e-5f);
        const float u = glm::dot(v, v) / (r * r);
        if (u < 1.0f) bound += (1.0f - u) * (1.0f - u);
    }
    return bound;
}

// The `media` scene's six balls: c_j = frac(0.5 + (k+1)·a_j) with the particle scene's R3 constants,
// in double, rounded to float; centre ((2c1−1)·0.7, (2c2−1)·0.45 + 0.2, (2c3−1)·0.7), radius
// 0.35 + 0.3·c3.
inline std::array<Metaball, 6> mediaSceneMetaballs() {
    constexpr double kA[3] = {0.8191725133961645, 0.6710436067037894, 0.5497004779019704};
    std::array<Metaball, 6> balls;
    for (int k = 0; k < 6; ++k) {
        double c[3];
        for (int j = 0; j < 3; ++j) {
            const double v = 0.5 + (k + 1) * kA[j];
            c[j] = v - std::floor(v);
        }
        balls[k].centre = glm::vec3(float((2 * c[0] - 1) * 0.7), float((2 * c[1] - 1) * 0.45 + 0.2),
                                    float((2 * c[2] - 1) * 0.7));
        balls[k].radius = float(0.35 + 0.3 * c[2]);
    }
    return balls;
}

// The `media` scene's box of medium.
inline Box mediaSceneBox() {
    return {{-1.2f, -0.8f, -1.2f}, {1.2f, 1.2f, 1.2f}};
}

}  // namespace raster::media
