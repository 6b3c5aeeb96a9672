// Ratio tracking (Novák, Selle and Jarosz 2014): an unbiased estimate of the transmittance
// T = e^{−∫μ ds} of a heterogeneous medium, the reference a march is measured against where no
// closed form exists.
//
// With a majorant μ̄ ≥ μ(s) over the interval, tentative collisions are drawn as a Poisson process of
// rate μ̄ (free paths −ln(1 − u)/μ̄); the estimate is the product over them of (1 − μ(s_k)/μ̄). Its
// expectation is T exactly, for any μ̄ ≥ max μ; a tighter μ̄ means fewer lookups and less variance
// (majorant_grid.hpp gives one per cell). Seeded: the same seed gives the same estimate, bit for bit.
#pragma once

#include <cmath>
#include <cstdint>

namespace raster::media {

// splitmix64 (Steele, Lea and Flood 2014): a 64-bit state advanced by a constant, mixed on output;
// uniform doubles in [0, 1) with 53 random bits.
struct SplitMix64 {
    uint64_t state;

    explicit SplitMix64(uint64_t seed) : state(seed) {}
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * 0x1p-53; }
};

// One ratio-tracking estimate of e^{−∫_{t0}^{t1} μ(s) ds} with the constant majorant mu_bar ≥ μ over
// [t0, t1]. mu(s) is the extinction at ray parameter s. mu_bar = 0 returns 1 (no medium).
template <class Extinction>
double ratioTrackingTransmittance(Extinction&& mu, double t0, double t1, double mu_bar, SplitMix64& rng) {
    if (!(mu_bar > 0.0)) return 1.0;
    double estimate = 1.0, s = t0;
    for (;;) {
        s += -std::log1p(-rng.uniform()) / mu_bar;
        if (s >= t1) return estimate;
        estimate *= 1.0 - mu(s) / mu_bar;
    }
}

}  // namespace raster::media
