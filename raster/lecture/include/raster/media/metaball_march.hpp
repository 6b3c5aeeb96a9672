// The `media` scene's march (../shared/bench/SCENES.md, "Scene media"; NOTES.md part 1,
// "Sugármenetelés"): single scattering of a directional or a point light (VolumeLight,
// volume_light.hpp) in a metaball medium, with shadow rays, an isotropic ambient term and the
// exponential step, front to back from the eye. The loop over the samples is scatter_march.hpp's,
// the one the ray-marching lab steps too; this file fills its places (MetaballPlaces) and integrates
// from the eye (FromTheEye).
//
// Per view ray o + t·d (d unit length, t in metres): the box's entry and exit t0 = max(t_near, 0),
// t1 = t_far; N steps of Δs = (t1 − t0)/N sampled at their midpoints x_i. At a sample with μ_i > 0:
//   shadow ray   τ_l = Σ_j μ(x_i + l·(j + ½)·Δl)·Δl, M steps of Δl = t_l/M to the box's exit along l
//                (a point light's: l = (P − x_i)/r, t_l = min(exit, r): it ends at the light)
//   source       S_i = albedo·(p(cos θ)·e^{−τ_l}·E + A)        (radiance; p per steradian, cos θ = d·l;
//                a point light's E = I/r² and cos θ per sample)
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
#include "raster/media/scatter_march.hpp"
#include "raster/media/volume_light.hpp"
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

// τ_l along the shadow ray x + t·l, t in [0, length] (l unit length; length: to the box's exit towards
// the light, or to a point light where that is nearer): Σ_j μ(p_j)·Δl in j's order, as the definition
// sums it, eight samples' densities at a time over the balls the ray may meet (the others add +0 at
// every sample: the same bits).
inline float shadowDepth(const MetaballVolume& v, const MarchSettings& settings, const glm::vec3& x,
                         const glm::vec3& l, float length, MarchResult& result) {
    const float dl = length / float(settings.shadowSteps);
    const uint32_t balls = shadowBallMask(v, x, l);
    float tau = 0.0f;
    if (balls == 0) return tau;  // no ball on the way: every sample's μ is 0
    for (uint32_t j0 = 0; j0 < settings.shadowSteps; j0 += 8) {
        const auto [px, py, pz] = samplePositions8(x, l, 0.0f, dl, j0);
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

// A point light's shadow ray's length from x along at.toLight: to the box's exit, or to the light where
// it is nearer.
inline float pointShadowLength(const Box& box, const glm::vec3& x, const LightAtPoint& at) {
    return std::min(exitDistance(box, x, at.toLight, 1.0f / at.toLight), at.distance);
}

// The metaball medium's places in the march (scatter_march.hpp): its eight-wide densities, the span of
// samples its balls may reach (SkipMethod::balls), Henyey–Greenstein and its shadow rays.
template <LightKind Kind>
struct MetaballPlaces {
    const MetaballVolume& v;
    const MarchSettings& settings;
    MarchResult& result;  // counts the shadow rays' density evaluations
    float g;
    glm::vec3 to_light, inv_light;  // a directional light's toLight and 1/toLight

    Float8 extinction8(Float8 x, Float8 y, Float8 z) const { return v.extinction8(x, y, z); }
    float phase(float cos_theta) const { return henyeyGreenstein(g, cos_theta); }
    std::pair<int32_t, int32_t> span(const glm::vec3& o, const glm::vec3& d, float t0, float dt, uint32_t n) const {
        if (settings.skip == SkipMethod::balls) return ballSpan(v, o, d, t0, dt, n);
        return {0, int32_t(n) - 1};
    }
    // `at`: a point light's light at x (scatter_march.hpp; a directional light's is not set).
    float shadowDepthAt(const glm::vec3& x, const LightAtPoint& at) const {
        if constexpr (Kind == LightKind::directional)
            return shadowDepth(v, settings, x, to_light, exitDistance(v.box, x, to_light, inv_light), result);
        else return shadowDepth(v, settings, x, at.toLight, pointShadowLength(v.box, x, at), result);
    }
    Float8 shadowTransmittance8(const std::array<Float8, 3>& x, uint32_t lanes, const LightAtPoint* at) const {
        Float8 tau(0.0f);
        for (; lanes != 0; lanes &= lanes - 1) {
            const int l = __builtin_ctz(lanes);
            tau.set(l, shadowDepthAt({x[0][l], x[1][l], x[2][l]}, at[l]));
        }
        return exp8(-tau);
    }
};

// The exponential step summed from the eye (header): L += T·albedo·in·(1 − e^{−μΔs}), T *= e^{−μΔs},
// e^{−μΔs} − 1 prepared eight at a time; each evaluated sample handed to the observer.
template <class Observer>
struct FromTheEye {
    MarchResult& result;
    Observer& observe;
    float albedo;
    float ds = 0.0f;

    Float8 prepare(Float8 mu, float step_length) {
        ds = step_length;
        return expm18(-(mu * Float8(ds)));
    }
    void pass(uint32_t i, float s, float mu) {
        observe(MarchSample{i, s, mu, mu * ds, result.transmittance, 1.0f, glm::vec3(0.0f)});
    }
    // e = e^{−μΔs} − 1: −e is absorbed, 1 + e passes.
    void scatter(uint32_t i, float s, float mu, float e, float shadow_t, const glm::vec3& in) {
        MarchSample sample{i, s, mu, mu * ds, result.transmittance, shadow_t, glm::vec3(0.0f)};
        const glm::vec3 source = albedo * in;
        sample.added = result.transmittance * source * -e;
        result.radiance += sample.added;
        result.transmittance *= 1.0f + e;
        observe(sample);
    }
};

// marchMetaballs for a light of kind Kind (header).
template <LightKind Kind, class Observer>
MarchResult marchMetaballsLit(const MetaballVolume& v, const VolumeLight& light, const MarchSettings& settings,
                              const glm::vec3& eye, const glm::vec3& d, float t0, float t1, Observer& observe) {
    MarchResult result;
    if (!(t1 > t0)) return result;
    const MetaballPlaces<Kind> places{v, settings, result, light.g, light.toLight, 1.0f / light.toLight};
    FromTheEye<Observer> integrator{result, observe, light.albedo};
    if (settings.skip != SkipMethod::grid) {
        result.densityEvaluations +=
            marchScattering<MarchOrder::frontToBack, Kind>(places, light, eye, d, t0, t1, settings.steps, integrator);
        return result;
    }
    // The grid's samples one by one, each with its cell's balls: the same per-sample rule.
    const float ds = (t1 - t0) / float(settings.steps);
    integrator.ds = ds;
    SampleLight<Kind, MetaballPlaces<Kind>> lit{places, light, d};
    forEachOccupiedSample(v.majorant, eye, d, t0, ds, settings.steps, [&](uint32_t i, const glm::ivec3& cell) {
        ++result.densityEvaluations;
        const float s = t0 + (float(i) + 0.5f) * ds;
        const glm::vec3 x = eye + d * s;
        const float mu = v.extinction(x, v.ballMask[v.majorant.frame.index(cell)]);
        if (!(mu > 0.0f)) {
            integrator.pass(i, s, mu);
            return true;
        }
        const LightAtPoint at = lit.at(x);
        const float shadow_t = raster::exp(-places.shadowDepthAt(x, at));
        integrator.scatter(i, s, mu, raster::expm1(-(mu * ds)), shadow_t, lit.inScattered(at, shadow_t));
        return true;
    });
    return result;
}

}  // namespace detail

// The radiance and transmittance of one view ray over its stretch [t0, t1] inside the box (header:
// the rule and its skipping), for a directional or a point light. The caller clips: t0 = max(t_near, 0),
// t1 = t_far of slabInterval.
template <class Observer = NoMarchObserver>
MarchResult marchMetaballs(const MetaballVolume& v, const VolumeLight& light, const MarchSettings& settings,
                           const glm::vec3& eye, const glm::vec3& d, float t0, float t1, Observer&& observe = {}) {
    if (light.kind == LightKind::point)
        return detail::marchMetaballsLit<LightKind::point>(v, light, settings, eye, d, t0, t1, observe);
    return detail::marchMetaballsLit<LightKind::directional>(v, light, settings, eye, d, t0, t1, observe);
}

// The same from the eye: the ray clipped to the box first.
template <class Observer = NoMarchObserver>
MarchResult marchMetaballs(const MetaballVolume& v, const VolumeLight& light, const MarchSettings& settings,
                           const glm::vec3& eye, const glm::vec3& d, Observer&& observe = {}) {
    const auto [t_near, t_far] = slabInterval(v.box, eye, d);
    return marchMetaballs(v, light, settings, eye, d, std::max(t_near, 0.0f), t_far, observe);
}

}  // namespace raster::media
