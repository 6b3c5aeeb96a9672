// The `media` scene's march (../shared/bench/SCENES.md, "Scene media"; NOTES.md part 1,
// "Sugármenetelés"): single scattering of a directional light in a metaball medium, with shadow rays,
// an isotropic ambient term and the exponential step, front to back from the eye.
//
// Per view ray o + t·d (d unit length, t in metres): the box's entry and exit t0 = max(t_near, 0),
// t1 = t_far; N steps of Δs = (t1 − t0)/N sampled at their midpoints x_i. At a sample with μ_i > 0:
//   shadow ray   τ_l = Σ_j μ(x_i + l·(j + ½)·Δl)·Δl, M steps of Δl = t_l/M to the box's exit along l
//   source       S_i = albedo·(p(cos θ)·e^{−τ_l}·E + A)        (radiance; p per steradian, cos θ = d·l)
//   step         L += T·S_i·(1 − e^{−μ_iΔs}),  T *= e^{−μ_iΔs} (exact for μ, S constant over the step),
//                one expm1 giving both (simd.hpp's exp and expm1: 1 and 2 ulp, the C library's in the
//                reference pipeline)
// and the pixel is L + T·L_bg. Samples with μ_i = 0 add nothing and leave T alone.
//
// Skipping what is empty (MarchSettings::skip), each exact: every term left out is exactly +0, so the
// result is the same bits as the march that evaluates every sample and every ball
// (tests/ray_march_test.cpp checks whole images):
//   none   every sample of the box, every ball: the definition.
//   balls  per view ray, the six balls' intervals along it (radius widened by 1e-3): only the samples
//          from the first interval's start to the last one's end are evaluated. Six ray–sphere tests
//          per ray; the scene's default.
//   grid   a grid over the box keeps, per cell, the balls that reach it (radius widened by 1e-5,
//          metaballs.hpp); the march walks the grid (3D DDA, majorant_grid.hpp), evaluates only the
//          samples in cells some ball reaches, and sums only that cell's balls. The general mechanism:
//          it needs only a bound per cell, as a voxel grid has.
// Densities are evaluated eight samples at a time (Float8, the same operations per lane as the
// scalar metaballTerm: the same bits), along the view ray and along every shadow ray.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "raster/media/majorant_grid.hpp"
#include "raster/media/metaballs.hpp"
#include "raster/media/phase_functions.hpp"
#include "raster/pixel_march.hpp"
#include "raster/simd.hpp"

namespace raster::media {

// The medium: six metaballs in a box, extinction μ = scale·ρ per metre.
struct MetaballVolume {
    std::array<Metaball, 6> balls{};
    Box box;
    float extinctionScale = 4.0f;  // μ = scale·ρ, 1/m
    MajorantGrid majorant;         // per cell: an upper bound of μ there (0: no ball reaches it)
    std::vector<uint8_t> ballMask;  // per cell: bit k set where ball k reaches the cell
    // The balls side by side for the eight-wide sums and the per-ray intervals: centres, radius², and
    // radius² widened by 1e-3 of the radius; lanes 6 and 7 empty (widened radius² −1: nothing is
    // inside them).
    std::array<float, 8> centreX{}, centreY{}, centreZ{}, radius2{}, widenedRadius2{};

    // μ at x, summing the balls of `mask` in ball order (all six: 0x3f): metaballDensity's terms.
    float extinction(const glm::vec3& x, uint32_t mask) const {
        float rho = 0.0f;
        for (uint32_t k = 0; k < balls.size(); ++k)
            if (mask >> k & 1u) rho += metaballTerm(balls[k], x);
        return extinctionScale * rho;
    }
    // μ at eight points, summing the balls of `mask` (default all): per lane the operations of
    // extinction(x, mask), bit for bit.
    Float8 extinction8(Float8 px, Float8 py, Float8 pz, uint32_t mask = 0x3fu) const {
        Float8 rho(0.0f);
        for (; mask != 0; mask &= mask - 1) {
            const int k = __builtin_ctz(mask);
            const Float8 vx = px - Float8(centreX[k]), vy = py - Float8(centreY[k]), vz = pz - Float8(centreZ[k]);
            const Float8 u = (vx * vx + vy * vy + vz * vz) / Float8(radius2[k]);
            const Float8 w = Float8(1.0f) - u;
            rho = rho + select(u < Float8(1.0f), w * w, Float8(0.0f));
        }
        return Float8(extinctionScale) * rho;
    }
    uint32_t maskAt(const glm::vec3& x) const { return ballMask[majorant.frame.index(majorant.frame.cellAt(x))]; }
};

// The volume over `box` with a grid of `cells` per axis (1 to 1024) for SkipMethod::grid.
inline MetaballVolume makeMetaballVolume(const std::array<Metaball, 6>& balls, const Box& box, float extinction_scale,
                                         int cells) {
    MetaballVolume v;
    v.balls = balls, v.box = box, v.extinctionScale = extinction_scale;
    v.majorant = makeMajorantGrid(box, glm::ivec3(cells),
                                  [&](const Box& b) { return extinction_scale * metaballMajorant(balls, b); });
    for (size_t k = 0; k < balls.size(); ++k) {
        v.centreX[k] = balls[k].centre.x, v.centreY[k] = balls[k].centre.y, v.centreZ[k] = balls[k].centre.z;
        v.radius2[k] = balls[k].radius * balls[k].radius;
        const float widened = balls[k].radius * (1.0f + 1e-3f);
        v.widenedRadius2[k] = widened * widened;
    }
    for (size_t k = balls.size(); k < 8; ++k) v.radius2[k] = 1.0f, v.widenedRadius2[k] = -1.0f;
    v.ballMask.resize(v.majorant.frame.cellCount());
    for (int z = 0; z < cells; ++z)
        for (int y = 0; y < cells; ++y)
            for (int x = 0; x < cells; ++x) {
                const glm::ivec3 c{x, y, z};
                uint8_t mask = 0;
                for (uint32_t k = 0; k < balls.size(); ++k)
                    if (metaballMajorant(std::array<Metaball, 1>{balls[k]}, v.majorant.frame.cellBox(c)) > 0.0f)
                        mask |= uint8_t(1u << k);
                v.ballMask[v.majorant.frame.index(c)] = mask;
            }
    return v;
}

// The light: one directional or point light, plus isotropic ambient in-scattering.
//
// Directional: the irradiance E = sun arrives along −toLight everywhere; a shadow ray from x runs
// along toLight to the medium's exit. Point: from `position`, radiant intensity I = intensity (per
// steradian, RGB), so the irradiance at x (facing the light, in a vacuum) is I/r², r = |position − x|
// (inverse-square falloff); a shadow ray from x runs along (position − x)/r and ends at the light
// (at r, or at the medium's exit if that comes first). Either way the phase function's angle is
// cos θ = d·l for a view ray d (from the eye) and l the unit vector from the sample towards the light:
// the light travels along −l and leaves towards the eye along −d, and phase_functions.hpp's cos θ is
// dot(travel, scattered) = (−l)·(−d), so g > 0 makes a light behind the medium (l ≈ d) shine through.
enum class LightKind : uint8_t { directional, point };

struct VolumeLight {
    glm::vec3 toLight{0.0f, 1.0f, 0.0f};  // directional: unit vector towards the light
    glm::vec3 sun{1.0f};                  // directional: irradiance E
    glm::vec3 ambient{0.0f};              // A: in-scattered radiance from all directions
    float g = 0.0f;                       // Henyey–Greenstein asymmetry (phase_functions.hpp)
    float albedo = 1.0f;                  // single-scattering albedo μs/μ
    LightKind kind = LightKind::directional;
    glm::vec3 position{0.0f};             // point: where the light is (the march's units)
    glm::vec3 intensity{0.0f};            // point: radiant intensity I, irradiance I/r² at distance r
};

// What a point x receives from the light: the unit direction towards it, how far the shadow ray may
// run (∞ for a directional light; r for a point light) and the irradiance before any medium on the
// way (E, or I/r²: +∞ at the light's own position, r = 0, where the direction is NaN).
struct LightAtPoint {
    glm::vec3 toLight;
    float distance;
    glm::vec3 irradiance;
};

inline LightAtPoint lightAt(const VolumeLight& light, const glm::vec3& x) {
    if (light.kind == LightKind::directional) return {light.toLight, INFINITY, light.sun};
    const glm::vec3 v = light.position - x;
    const float r2 = glm::dot(v, v), r = std::sqrt(r2);
    return {v / r, r, light.intensity / r2};
}

// The light and phase of SCENES.md's `media` (its scene and `raster bench error` march with it).
inline VolumeLight mediaSceneLight() {
    VolumeLight light;
    light.toLight = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
    light.sun = {14.0f, 13.0f, 11.0f};
    light.ambient = {0.10f, 0.12f, 0.18f};
    light.g = 0.4f;
    light.albedo = 0.9f;
    return light;
}

enum class SkipMethod : uint8_t { none, balls, grid };

inline const char* skipMethodName(SkipMethod m) {
    switch (m) {
        case SkipMethod::none: return "none";
        case SkipMethod::balls: return "balls";
        case SkipMethod::grid: return "grid";
    }
    return "?";
}

struct MarchSettings {
    uint32_t steps = 32;                  // N along the view ray (≥ 1)
    uint32_t shadowSteps = 6;             // M along each shadow ray (≥ 1)
    SkipMethod skip = SkipMethod::balls;  // header: every method gives the same bits
};

struct MarchResult {
    glm::vec3 radiance{0.0f};  // L, without the background
    float transmittance = 1.0f;
    uint32_t densityEvaluations = 0;  // μ(x) evaluated, view and shadow rays
};

struct NoMarchObserver {
    void operator()(const MarchSample&) const {}
};

namespace detail {

// The samples t_i = t0 + (i + ½)·dt, i < n, of the ray o + t·d that may lie inside some ball: [first,
// last] (first > last: none). Conservative: each ball widened by 1e-3 of its radius (its disc
// b² − a·c then exceeds float's rounding of it by two orders of magnitude wherever the ball itself is
// touched), its interval widened by one sample on each side.
inline std::pair<int32_t, int32_t> ballSpan(const MetaballVolume& v, const glm::vec3& o, const glm::vec3& d, float t0,
                                            float dt, uint32_t n) {
    int32_t first = int32_t(n), last = -1;
    const float a = d.x * d.x + d.y * d.y + d.z * d.z;
    if (!(a > 0.0f)) return {first, last};
    const float to_u = 1.0f / (a * dt), u0 = t0 / dt;  // u = (t − t0)/dt
    for (size_t k = 0; k < v.balls.size(); ++k) {
        const float ox = o.x - v.centreX[k], oy = o.y - v.centreY[k], oz = o.z - v.centreZ[k];
        const float b = ox * d.x + oy * d.y + oz * d.z, c = ox * ox + oy * oy + oz * oz - v.widenedRadius2[k];
        const float disc = b * b - a * c;
        if (!(disc >= 0.0f)) continue;
        const float root = std::sqrt(disc);
        const float lo = std::ceil((-b - root) * to_u - u0 - 1.5f), hi = std::floor((-b + root) * to_u - u0 + 0.5f);
        if (hi < 0.0f || lo > float(n) - 1.0f) continue;
        first = std::min(first, int32_t(std::max(lo, 0.0f)));
        last = std::max(last, int32_t(std::min(hi, float(n) - 1.0f)));
    }
    return {first, last};
}

// The eight sample positions o + d·(t0 + (i + ½)·dt), i = i0 .. i0 + 7: per lane the scalar's operations.
inline std::array<Float8, 3> samplePositions8(const glm::vec3& o, const glm::vec3& d, float t0, float dt, uint32_t i0) {
    const Float8 half_index(simd::F32x8{0.5f, 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f, 7.5f});
    const Float8 s = Float8(t0) + (half_index + Float8(float(i0))) * Float8(dt);
    return {Float8(o.x) + Float8(d.x) * s, Float8(o.y) + Float8(d.y) * s, Float8(o.z) + Float8(d.z) * s};
}

// slabInterval(box, x, d).second for x inside the box, given inv = 1/d per axis (computed once per
// light: the same reciprocals slabInterval computes per call, so the same bits).
inline float exitDistance(const Box& box, const glm::vec3& x, const glm::vec3& d, const glm::vec3& inv) {
    float t_far = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0f) continue;
        const float t_lo = (box.lo[a] - x[a]) * inv[a], t_hi = (box.hi[a] - x[a]) * inv[a];
        t_far = std::min(t_far, std::max(t_lo, t_hi));
    }
    return t_far;
}

// The balls the shadow ray x + t·l, t ≥ 0, may meet (l unit length): those whose centre c lies within
// the widened radius R of the ray's line, |w|² − (w·l)² < R² with w = c − x, and not wholly behind x,
// w·l > −R. Eight balls' tests at once. Conservative: R² exceeds r² by 2e-3·r², far above the
// float rounding of the difference, so a ball left out adds exactly +0 at every shadow sample.
inline uint32_t shadowBallMask(const MetaballVolume& v, const glm::vec3& x, const glm::vec3& l) {
    const Float8 wx = Float8::load(v.centreX.data()) - Float8(x.x);
    const Float8 wy = Float8::load(v.centreY.data()) - Float8(x.y);
    const Float8 wz = Float8::load(v.centreZ.data()) - Float8(x.z);
    const Float8 r2 = Float8::load(v.widenedRadius2.data());
    const Float8 along = wx * Float8(l.x) + wy * Float8(l.y) + wz * Float8(l.z);
    const Float8 across2 = wx * wx + wy * wy + wz * wz - along * along;
    const Mask8 near = (across2 < r2) & ((Float8(0.0f) < along) | (along * along < r2));
    return near.bits();
}

// τ_l along the shadow ray from x to the box's exit towards the light: Σ_j μ(p_j)·Δl in j's order, as
// the definition sums it, eight samples' densities at a time over the balls the ray may meet (the
// others add +0 at every sample: the same bits).
inline float shadowDepth(const MetaballVolume& v, const VolumeLight& light, const glm::vec3& inv_light,
                         const MarchSettings& settings, const glm::vec3& x, MarchResult& result) {
    const float dl = exitDistance(v.box, x, light.toLight, inv_light) / float(settings.shadowSteps);
    const uint32_t balls = shadowBallMask(v, x, light.toLight);
    float tau = 0.0f;
    if (balls == 0) return tau;  // no ball on the way: every sample's μ is 0
    for (uint32_t j0 = 0; j0 < settings.shadowSteps; j0 += 8) {
        const auto [px, py, pz] = samplePositions8(x, light.toLight, 0.0f, dl, j0);
        const Float8 mu = v.extinction8(px, py, pz, balls);
        const uint32_t lanes = std::min(8u, settings.shadowSteps - j0);
        result.densityEvaluations += lanes;
        for (uint32_t j = 0; j < lanes; ++j) tau += mu[int(j)] * dl;
    }
    return tau;
}

// raster::exp and raster::expm1 of eight values: the SIMD layer's, the same bits as its scalar ones;
// in the reference pipeline (shader_context.hpp) the C library's, lane by lane, as the scalar ones.
inline Float8 exp8(Float8 x) {
    if (!inReferenceMode()) return raster::exp(x);
    for (int l = 0; l < 8; ++l) x.set(l, raster::exp(x[l]));
    return x;
}
inline Float8 expm18(Float8 x) {
    if (!inReferenceMode()) return raster::expm1(x);
    for (int l = 0; l < 8; ++l) x.set(l, raster::expm1(x[l]));
    return x;
}

}  // namespace detail

// The radiance and transmittance of one view ray over its stretch [t0, t1] inside the box (header:
// the rule and its skipping). A directional light (its toLight and sun; the point light is the
// cloud march's, cloud_march.hpp). The caller clips: t0 = max(t_near, 0), t1 = t_far of slabInterval.
template <class Observer = NoMarchObserver>
MarchResult marchMetaballs(const MetaballVolume& v, const VolumeLight& light, const MarchSettings& settings,
                           const glm::vec3& eye, const glm::vec3& d, float t0, float t1, Observer&& observe = {}) {
    MarchResult result;
    if (!(t1 > t0)) return result;
    float phase = -1.0f;  // computed at the first sample that scatters (most rays have none)
    const glm::vec3 inv_light = 1.0f / light.toLight;
    const float ds = (t1 - t0) / float(settings.steps);
    // One sample's step, given μ, the shadow ray's transmittance e^{−τ_l} and e = e^{−μΔs} − 1 (−e is
    // absorbed, 1 + e passes): the exponentials come in eight at a time.
    auto step = [&](uint32_t i, float mu, float shadow_t, float e) {
        const float s = t0 + (float(i) + 0.5f) * ds;
        MarchSample sample{i, s, mu, mu * ds, result.transmittance, 1.0f, glm::vec3(0.0f)};
        if (mu > 0.0f) {
            if (phase < 0.0f) phase = henyeyGreenstein(light.g, glm::dot(d, light.toLight));
            sample.shadowTransmittance = shadow_t;
            const glm::vec3 source = light.albedo * (phase * shadow_t * light.sun + light.ambient);
            sample.added = result.transmittance * source * -e;
            result.radiance += sample.added;
            result.transmittance *= 1.0f + e;
        }
        observe(sample);
    };
    auto shadowDepthAt = [&](uint32_t i) {
        return detail::shadowDepth(v, light, inv_light, settings, eye + d * (t0 + (float(i) + 0.5f) * ds), result);
    };
    if (settings.skip == SkipMethod::grid) {
        forEachOccupiedSample(v.majorant, eye, d, t0, ds, settings.steps, [&](uint32_t i, const glm::ivec3& cell) {
            ++result.densityEvaluations;
            const float mu =
                v.extinction(eye + d * (t0 + (float(i) + 0.5f) * ds), v.ballMask[v.majorant.frame.index(cell)]);
            const float tau = mu > 0.0f ? shadowDepthAt(i) : 0.0f;
            step(i, mu, raster::exp(-tau), raster::expm1(-(mu * ds)));
            return true;
        });
        return result;
    }
    const auto [first, last] = settings.skip == SkipMethod::balls
                                   ? detail::ballSpan(v, eye, d, t0, ds, settings.steps)
                                   : std::pair<int32_t, int32_t>{0, int32_t(settings.steps) - 1};
    for (int32_t i0 = first; i0 <= last; i0 += 8) {
        const auto [px, py, pz] = detail::samplePositions8(eye, d, t0, ds, uint32_t(i0));
        const Float8 mu = v.extinction8(px, py, pz);
        const int32_t lanes = std::min(8, last - i0 + 1);
        result.densityEvaluations += uint32_t(lanes);
        Float8 tau(0.0f);
        for (int32_t l = 0; l < lanes; ++l)
            if (mu[l] > 0.0f) tau.set(l, shadowDepthAt(uint32_t(i0 + l)));
        const Float8 shadow_t = detail::exp8(-tau), e = detail::expm18(-(mu * Float8(ds)));
        for (int32_t l = 0; l < lanes; ++l) step(uint32_t(i0 + l), mu[l], shadow_t[l], e[l]);
    }
    return result;
}

// The same from the eye: the ray clipped to the box first.
template <class Observer = NoMarchObserver>
MarchResult marchMetaballs(const MetaballVolume& v, const VolumeLight& light, const MarchSettings& settings,
                           const glm::vec3& eye, const glm::vec3& d, Observer&& observe = {}) {
    const auto [t_near, t_far] = slabInterval(v.box, eye, d);
    return marchMetaballs(v, light, settings, eye, d, std::max(t_near, 0.0f), t_far, observe);
}

}  // namespace raster::media
