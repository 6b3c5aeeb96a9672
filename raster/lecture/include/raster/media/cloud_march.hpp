// The `cloud` scene's march: single scattering of a directional or a point light (VolumeLight,
// metaball_march.hpp) in a voxel medium (voxel_grid.hpp),
// with shadow rays through the medium, an isotropic ambient term and the exponential step, front to back
// from the eye; empty space skipped through a coarse majorant grid walked by the 3D DDA
// (majorant_grid.hpp).
//
// Units: the march works in voxel units. Voxel (i, j, k) has its centre at (i + ½, j + ½, k + ½), the
// medium's box is [0, dims], and the density at p is the grid's trilinear value there (voxel_grid.hpp's
// convention: clamped to the edge voxels inside the box, 0 outside it). Distances s, Δs, Δl are in
// voxels and the extinction μ = extinctionScale·ρ is per voxel, so μΔs is the optical depth of a step.
// The scene maps the world to voxels by one uniform scale and a shift (the view ray's direction is the
// same in both).
//
// Per view ray o + s·d (d unit length) over its stretch [s0, s1] inside the box: N = ⌈(s1 − s0)/step⌉
// steps of Δs = (s1 − s0)/N sampled at their midpoints s_i = s0 + (i + ½)·Δs. At a sample with μ_i > 0:
//   shadow ray   τ_l = Σ_j μ(x_i + l·(j + ½)·Δl)·Δl, M = ⌈t_l/shadowStep⌉ steps of Δl = t_l/M to the
//                box's exit t_l along l (towards the light); a point light's l = (P − x_i)/r and its
//                shadow ray ends at the light where that comes first: t_l = min(exit, r)
//   source       S_i = albedo·(p(cos θ)·e^{−τ_l}·E + A)     (cos θ = d·l, Henyey–Greenstein; a point
//                light's E = I/r² and cos θ per sample)
//   step         L += T·S_i·(1 − e^{−μ_iΔs}),  T *= e^{−μ_iΔs} (exact for μ, S constant over the step)
// and the pixel is L + T·L_bg. Samples with μ_i = 0 add nothing and leave T alone.
//
// What is skipped, and what it costs (each knob in CloudMarchSettings, its bound in cloudErrorBound):
//   empty space   CloudMarchSettings::skip: the view ray and every shadow ray walk the majorant grid and
//                 evaluate only the samples in cells whose majorant is above 0. Every skipped sample has
//                 μ = 0 exactly (the majorant bounds the trilinear field over the whole cell), so it
//                 would add +0: the same bits as evaluating every sample (tests/cloud_test.cpp).
//   early termination  the view ray stops once T < minTransmittance. What is dropped is T times the
//                 radiance behind, which lies between 0 and max(S_max, L_bg): error ≤ minTransmittance ·
//                 max(S_max, 1) for a background ≤ 1 (an 8-bit target's), S_max = albedo·(p_max·E + A).
//   shadow termination  a shadow ray stops once τ_l > shadowMaxDepth: e^{−τ_l} is then too large by at
//                 most e^{−shadowMaxDepth}, and Σ T_i·(1 − e^{−μ_iΔs}) ≤ 1, so the error is at most
//                 e^{−shadowMaxDepth}·albedo·p·E.
//   shadow rays that cannot matter  a sample's shadow ray changes L by at most
//                 b_i = T·(1 − e^{−μ_iΔs})·albedo·p·E (e^{−τ_l} lies in [0, 1]). The ray is not cast, and
//                 e^{−τ_l} taken as ½ (error ≤ b_i/2), while the running sum of those halves stays within
//                 shadowBudget: the error of all skipped shadow rays together is at most shadowBudget.
// Errors are per colour channel, in radiance (1 = white on an 8-bit target).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "raster/media/majorant_grid.hpp"
#include "raster/media/metaball_march.hpp"
#include "raster/media/voxel_grid.hpp"

namespace raster::media {

// A voxel grid as a medium, in voxel units (header), with its majorant grid.
struct CloudVolume {
    VoxelGrid grid;
    Box box;                      // [0, dims], voxels
    float extinctionScale = 1.0f;  // μ = scale·ρ per voxel
    int cellVoxels = 16;          // majorant cells' edge at most, voxels: ⌈dims/cellVoxels⌉ equal cells an axis
    MajorantGrid majorant;        // per cell: an upper bound of μ there (0: empty)

    // μ at p (voxel units): the trilinear density times the scale, 0 outside the box. The eight
    // voxels read straight from the grid's storage (VoxelGrid::voxel's values, without its per-voxel
    // type test).
    float extinction(const glm::vec3& p) const {
        const glm::ivec3 n = grid.dims();
        if (!(p.x >= 0.0f && p.y >= 0.0f && p.z >= 0.0f && p.x <= float(n.x) && p.y <= float(n.y) &&
              p.z <= float(n.z)))
            return 0.0f;
        int i0[3], step[3];
        float t[3];
        for (int a = 0; a < 3; ++a) {
            const float u = std::clamp(p[a] - 0.5f, 0.0f, float(n[a] - 1));
            i0[a] = std::min(int(u), n[a] - 1);
            step[a] = i0[a] + 1 < n[a] ? 1 : 0;
            t[a] = u - float(i0[a]);
        }
        const size_t sx = size_t(step[0]), sy = size_t(step[1]) * size_t(n.x),
                     sz = size_t(step[2]) * size_t(n.x) * size_t(n.y);
        const size_t at = size_t(i0[0]) + size_t(n.x) * (size_t(i0[1]) + size_t(n.y) * size_t(i0[2]));
        auto lerp = [](float a, float b, float s) { return a + (b - a) * s; };
        auto trilinear = [&](auto value) {
            auto row = [&](size_t r) { return lerp(value(r), value(r + sx), t[0]); };
            const float z0 = lerp(row(at), row(at + sy), t[1]);
            const float z1 = lerp(row(at + sz), row(at + sz + sy), t[1]);
            return lerp(z0, z1, t[2]);
        };
        if (grid.type() == VoxelType::Float32) {
            const float* v = grid.floatData();
            return extinctionScale * trilinear([v](size_t i) { return v[i]; });
        }
        const uint8_t* b = grid.byteData();
        const float unit = grid.densityScale() / 255.0f;
        return extinctionScale * trilinear([b, unit](size_t i) { return float(b[i]) * unit; });
    }

    // Bytes the voxels take, and bytes the volume holds in all (voxels, the grid object, the majorant).
    uint64_t voxelBytes() const { return grid.voxelBytes(); }
    uint64_t memoryBytes() const {
        return grid.memoryBytes() - sizeof(VoxelGrid) + sizeof(*this) + majorant.bound.capacity() * sizeof(float);
    }
};

// The volume of `grid` with extinction scale·ρ per voxel and majorant cells of cell_voxels voxels
// (1 to 1024 cells per axis: Error(InvalidArgument) otherwise).
inline CloudVolume makeCloudVolume(VoxelGrid grid, float extinction_scale, int cell_voxels) {
    RASTER_REQUIRE(cell_voxels >= 1, InvalidArgument, "cloud volume: majorant cells of fewer than 1 voxel");
    CloudVolume v;
    v.grid = std::move(grid);
    const glm::ivec3 n = v.grid.dims();
    v.box = {glm::vec3(0.0f), glm::vec3(n)};
    v.extinctionScale = extinction_scale;
    v.cellVoxels = cell_voxels;
    const glm::ivec3 cells = (n + cell_voxels - 1) / cell_voxels;
    const VoxelBox& world = v.grid.bounds();
    const glm::vec3 world_per_voxel = v.grid.cellSize();
    v.majorant = makeMajorantGrid(v.box, cells, [&](const Box& b) {
        return extinction_scale * v.grid.maxInBox(world.lo + b.lo * world_per_voxel, world.lo + b.hi * world_per_voxel);
    });
    return v;
}

struct CloudMarchSettings {
    float step = 2.0f;                     // Δs along view rays at most, voxels
    float shadowStep = 4.0f;               // Δl along shadow rays at most, voxels
    float minTransmittance = 2e-4f;        // a view ray stops once T is below (0: never)
    float shadowMaxDepth = 9.0f;           // a shadow ray stops once τ_l exceeds (∞: never)
    float shadowBudget = 0.25f / 255.0f;   // radiance: skipped shadow rays' error in all (0: none skipped)
    bool skip = true;                      // empty-space skipping (header: the same bits)
};

// The largest error of the terminations and skipped shadow rays against the march without them, per
// channel, for a background ≤ 1 (header), for a directional light. (A point light's E is I/r² at the
// sample: the bound holds with E the largest irradiance over the box, unbounded for a light inside it;
// the skipped shadow rays' share, shadowBudget, holds for either light: each sample's bound uses its E.)
inline float cloudErrorBound(const VolumeLight& light, const CloudMarchSettings& s) {
    const float e_max = std::max({light.sun.x, light.sun.y, light.sun.z});
    const float a_max = std::max({light.ambient.x, light.ambient.y, light.ambient.z});
    const float p_max = (1.0f + std::abs(light.g)) / (4.0f * float(M_PI) * (1.0f - std::abs(light.g)) *
                                                      (1.0f - std::abs(light.g)));
    const float s_max = light.albedo * (p_max * e_max + a_max);
    return s.minTransmittance * std::max(s_max, 1.0f) + std::exp(-s.shadowMaxDepth) * light.albedo * p_max * e_max +
           s.shadowBudget;
}

namespace detail {

// Calls visit(i) for the samples i < n of the ray o + (t0 + (i + ½)·dt)·d in order, each where skipping
// may not leave it out; visit returns false to stop.
template <class Visit>
void forCloudSamples(const CloudVolume& v, bool skip, const glm::vec3& o, const glm::vec3& d, float t0, float dt,
                     uint32_t n, Visit&& visit) {
    if (skip) {
        forEachOccupiedSample(v.majorant, o, d, t0, dt, n, [&](uint32_t i, const glm::ivec3&) { return visit(i); });
        return;
    }
    for (uint32_t i = 0; i < n; ++i)
        if (!visit(i)) return;
}

// τ along the ray x + t·l over [t0, t1] (l unit length; voxel units): M = ⌈(t1 − t0)/shadowStep⌉ steps
// of Δl = (t1 − t0)/M sampled at their midpoints, Σ μ_j·Δl in j's order over the samples skipping keeps,
// stopped once it exceeds the settings' depth (header: shadow termination).
inline float cloudOpticalDepth(const CloudVolume& v, const CloudMarchSettings& s, const glm::vec3& x,
                               const glm::vec3& l, float t0, float t1, MarchResult& result) {
    const uint32_t m = std::max(1u, uint32_t(std::ceil((t1 - t0) / s.shadowStep)));
    const float dl = (t1 - t0) / float(m);
    float tau = 0.0f;
    forCloudSamples(v, s.skip, x, l, t0, dl, m, [&](uint32_t j) {
        ++result.densityEvaluations;
        tau += v.extinction(x + l * (t0 + (float(j) + 0.5f) * dl)) * dl;
        return !(tau > s.shadowMaxDepth);
    });
    return tau;
}

// τ_l from x to the box's exit towards the light (header), stopped once it exceeds the settings' depth.
inline float cloudShadowDepth(const CloudVolume& v, const VolumeLight& light, const glm::vec3& inv_light,
                              const CloudMarchSettings& s, const glm::vec3& x, MarchResult& result) {
    const float exit = exitDistance(v.box, x, light.toLight, inv_light);
    if (!(exit > 0.0f)) return 0.0f;
    return cloudOpticalDepth(v, s, x, light.toLight, 0.0f, exit, result);
}

// τ from x to the point light or the box's exit, whichever comes first (at = lightAt(light, x)).
inline float cloudPointShadowDepth(const CloudVolume& v, const CloudMarchSettings& s, const glm::vec3& x,
                                   const LightAtPoint& at, MarchResult& result) {
    const float end = std::min(exitDistance(v.box, x, at.toLight, 1.0f / at.toLight), at.distance);
    if (!(end > 0.0f)) return 0.0f;
    return cloudOpticalDepth(v, s, x, at.toLight, 0.0f, end, result);
}

// A sample's single-scattered light before the shadow ray: albedo·p(cos θ)·E, its largest channel
// (the bound of a skipped shadow ray, header) and the light seen from the sample.
struct ScatteredLight {
    glm::vec3 scattered;
    float largest;
    LightAtPoint at;
};

// The same for a point light at the sample x on the view ray d: cos θ = d·l (metaball_march.hpp's
// VolumeLight: the convention), E = I/r².
inline ScatteredLight pointLightSample(const VolumeLight& light, const glm::vec3& d, const glm::vec3& x) {
    const LightAtPoint at = lightAt(light, x);
    const glm::vec3 scattered = light.albedo * henyeyGreenstein(light.g, glm::dot(d, at.toLight)) * at.irradiance;
    return {scattered, std::max({scattered.x, scattered.y, scattered.z}), at};
}

}  // namespace detail

// The transmittance e^{−τ} from a point x anywhere (inside the box or outside it: a surface under the
// cloud) towards the light along l (unit length), through the cloud: the shadow ray clipped to the
// box and to `distance` (a point light's; ∞ for a directional light), marched as the view ray's
// shadow rays are (majorant skipping, shadow termination). Exactly 1 where the ray misses the box:
// nothing evaluated.
inline float cloudShadowTransmittance(const CloudVolume& v, const CloudMarchSettings& s, const glm::vec3& x,
                                      const glm::vec3& l, float distance = INFINITY) {
    const auto [t_near, t_far] = slabInterval(v.box, x, l);
    const float t0 = std::max(t_near, 0.0f), t1 = std::min(t_far, distance);
    if (!(t1 > t0)) return 1.0f;
    MarchResult unused;
    return raster::exp(-detail::cloudOpticalDepth(v, s, x, l, t0, t1, unused));
}

// The radiance and transmittance of one view ray over its stretch [s0, s1] inside the box (voxel units,
// header); the caller clips: s0 = max(s_near, 0), s1 = s_far of slabInterval(v.box, eye, d).
template <class Observer = NoMarchObserver>
MarchResult marchCloud(const CloudVolume& v, const VolumeLight& light, const CloudMarchSettings& s,
                       const glm::vec3& eye, const glm::vec3& d, float s0, float s1, Observer&& observe = {}) {
    MarchResult result;
    if (!(s1 > s0)) return result;
    const uint32_t n = std::max(1u, uint32_t(std::ceil((s1 - s0) / s.step)));
    const float ds = (s1 - s0) / float(n);
    const bool point = light.kind == LightKind::point;
    const glm::vec3 inv_light = 1.0f / light.toLight;
    // A directional light's phase and scattered irradiance are the same at every sample; a point
    // light's are recomputed per sample (detail::pointLightSample).
    const float phase = point ? 0.0f : henyeyGreenstein(light.g, glm::dot(d, light.toLight));
    const glm::vec3 sun_scattered = light.albedo * phase * light.sun;
    const float sun_max = std::max({sun_scattered.x, sun_scattered.y, sun_scattered.z});
    float skipped = 0.0f;  // the skipped shadow rays' error so far (header)
    detail::forCloudSamples(v, s.skip, eye, d, s0, ds, n, [&](uint32_t i) {
        const float t = s0 + (float(i) + 0.5f) * ds;
        const glm::vec3 x = eye + d * t;
        ++result.densityEvaluations;
        const float mu = v.extinction(x);
        MarchSample sample{i, t, mu, mu * ds, result.transmittance, 1.0f, glm::vec3(0.0f)};
        if (mu > 0.0f) {
            const float e = raster::expm1(-(mu * ds));  // e^{−μΔs} − 1
            const detail::ScatteredLight lit = point ? detail::pointLightSample(light, d, x)
                                                     : detail::ScatteredLight{sun_scattered, sun_max, {}};
            const float half_bound = 0.5f * result.transmittance * -e * lit.largest;
            float shadow_t = 0.5f;
            if (skipped + half_bound <= s.shadowBudget)
                skipped += half_bound;
            else if (point)
                shadow_t = raster::exp(-detail::cloudPointShadowDepth(v, s, x, lit.at, result));
            else
                shadow_t = raster::exp(-detail::cloudShadowDepth(v, light, inv_light, s, x, result));
            sample.shadowTransmittance = shadow_t;
            const glm::vec3 source = shadow_t * lit.scattered + light.albedo * light.ambient;
            sample.added = result.transmittance * source * -e;
            result.radiance += sample.added;
            result.transmittance *= 1.0f + e;
        }
        observe(sample);
        return !(result.transmittance < s.minTransmittance);
    });
    return result;
}

// The same from the eye: the ray clipped to the box first.
template <class Observer = NoMarchObserver>
MarchResult marchCloud(const CloudVolume& v, const VolumeLight& light, const CloudMarchSettings& s,
                       const glm::vec3& eye, const glm::vec3& d, Observer&& observe = {}) {
    const auto [t_near, t_far] = slabInterval(v.box, eye, d);
    return marchCloud(v, light, s, eye, d, std::max(t_near, 0.0f), t_far, observe);
}

}  // namespace raster::media
