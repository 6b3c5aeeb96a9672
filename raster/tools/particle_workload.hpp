// The particle simulation's benchmark workload, shared by `raster bench particles-sim` and
// raster-microbench's Particles benchmarks (docs/PERFORMANCE.md's goals: one step of 1 000 000
// particles under gravity, wind and drag in at most 5 ms on 2 cores; with curl-noise turbulence, at
// most 40 ms).
#pragma once

#include <cstdint>

#include "raster/particles.hpp"

namespace raster::tools {

// `count` particles alive for the whole run: one burst at time 0 from a 10 × 2 × 10 box, lives of
// 10⁶ s, speeds 0.5–2 units/s in a cone of 1 rad about +y; gravity, wind (2, 0, 1) at 0.5, drag 0.1,
// and with `turbulence` curl noise of strength 1 at scale 0.7 drifting upwards.
inline ParticleSystemDesc particleWorkload(uint32_t count, bool turbulence) {
    Emitter box = Emitter::box({0, 1, 0}, {5, 1, 5});
    box.bursts = {{0.0f, count, 0.0f}};
    box.velocity = {{0, 1, 0}, 1.0f, 0.5f, 2.0f};
    box.lifespanMin = box.lifespanMax = 1e6f;
    ParticleSystemDesc d;
    d.maxParticles = count;
    d.seed = 1;
    d.emitters = {box};
    d.effectors = {Gravity{}, Wind{{2, 0, 1}, 0.5f}, Drag{0.1f}};
    if (turbulence) d.effectors.push_back(Turbulence{1.0f, 0.7f, {0, 0.3f, 0}, 0.0f, 0});
    return d;
}

}  // namespace raster::tools
