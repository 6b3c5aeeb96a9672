// The lecture's fog (shaders/fog.hpp) at the edges of its domain: no NaN and no wrong limit for
// any finite input, against a long-double evaluation of the same physics. The ordinary cases
// (numerical integration, the horizontal ray, the background) are in scenes_test.cpp.
#include "raster/shaders/fog.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace raster {
namespace {

using shaders::FogMedium;

// τ per unit σ, in long double: s for constant fog, e^{b·y0}·(e^{k·s} − 1)/k for height fog.
long double referenceDepth(const FogMedium& fog, long double y0, long double dy, long double s) {
    if (!fog.height) return s;
    const long double k = (long double)fog.b * dy;
    if (std::isinf(s)) return k < 0 ? std::exp((long double)fog.b * y0) / -k : INFINITY;
    if (k == 0 || s == 0) return std::exp((long double)fog.b * y0) * s;
    // e^{b·y0 + k·s} − e^{b·y0} over k, exponents combined so that long double neither overflows nor
    // underflows in between for |b·y0|, |k·s| below 11000.
    const long double e = (long double)fog.b * y0;
    return k > 0 ? std::exp(e + k * s) * -std::expm1(-k * s) / k : std::exp(e) * -std::expm1(k * s) / -k;
}

// L = L0·T + (q/σ)(1 − T), T = e^{−σ·τ}; L0 + q·τ for σ = 0.
long double referenceRadiance(const FogMedium& fog, int c, long double L0, long double tau) {
    const long double sigma = fog.sigma[c], q = fog.q[c];
    if (sigma == 0) return q == 0 ? L0 : L0 + q * tau;
    return L0 * std::exp(-sigma * tau) + q / sigma * -std::expm1(-sigma * tau);
}

glm::vec3 apply(const FogMedium& fog, glm::vec3 L0, float y0, glm::vec3 dir, float s) {
    return fog.apply(L0, glm::vec3(0.0f, y0, 0.0f), dir, s);
}

TEST(FogMedium, ZeroExtinctionIsTheLimitOfThinFog) {
    for (const bool height : {false, true}) {
        FogMedium fog;
        fog.height = height;
        fog.sigma = {0.0f, 0.07f, 0.0f};
        fog.q = {0.03f, 0.05f, 0.0f};  // red: σ = 0, q > 0 (L0 + q·τ); blue: σ = q = 0 (L0)
        const glm::vec3 L0(0.25f, 0.5f, 0.75f), dir = glm::normalize(glm::vec3(0.0f, -0.3f, -1.0f));
        for (const float s : {0.0f, 1e-3f, 2.0f, 40.0f}) {
            const glm::vec3 L = apply(fog, L0, 1.5f, dir, s);
            const double tau = double(referenceDepth(fog, 1.5, dir.y, s));
            EXPECT_NEAR(L.r, L0.r + fog.q.r * tau, 1e-6 * (1 + tau)) << "height " << height << ", s " << s;
            EXPECT_EQ(L.b, L0.b) << "no extinction and no source leave L0 as it is";
            EXPECT_TRUE(std::isfinite(L.g));
        }
        // To s = ∞: looking down τ = ∞, so with q = 0 the radiance is L0 (not 0·∞), with q > 0 it grows
        // without bound (+∞, not NaN); looking up into thinning height fog τ is finite.
        const glm::vec3 down = apply(fog, L0, 1.5f, glm::vec3(0, -1, 0), INFINITY);
        EXPECT_EQ(down.b, L0.b);
        EXPECT_EQ(down.r, INFINITY);
        if (height) {
            const glm::vec3 up = apply(fog, L0, 1.5f, glm::vec3(0, 1, 0), INFINITY);
            const double tau = double(referenceDepth(fog, 1.5, 1.0, INFINITY));
            EXPECT_NEAR(up.r, L0.r + fog.q.r * tau, 1e-6 * (1 + tau));
        }
    }
}

TEST(FogMedium, SkyWithZeroExtinctionIsFinite) {
    shaders::PsSky sky;
    sky.fog.sigma = {0.0f, 0.07f, 0.0f};
    sky.fog.q = {0.03f, 0.05f, 0.0f};
    sky.eye = {0.0f, 1.5f, 0.0f};
    const glm::vec4 up = sky(shaders::SkyVertex{{0, 0, 1, 1}, {0.0f, 2.0f, -1.0f}});
    const double tau = double(referenceDepth(sky.fog, 1.5, 2.0 / std::sqrt(5.0), INFINITY));
    EXPECT_NEAR(up.r, sky.fog.q.r * tau, 1e-6 * (1 + tau));
    EXPECT_EQ(up.b, 0.0f);
    const glm::vec4 down = sky(shaders::SkyVertex{{0, 0, 1, 1}, {0.0f, -1.0f, -1.0f}});
    EXPECT_EQ(down.b, 0.0f) << "q = 0: nothing shines, however far the ray goes";
    EXPECT_FALSE(std::isnan(down.r));
}

TEST(FogMedium, DenseLowFogSeenFromAboveIsNotZeroTimesInfinity) {
    // b = −2, eye at 50 m, looking straight down 50 m: e^{b·y0} = e^{−100} underflows float while
    // e^{k·s} = e^{100} overflows it; τ = (1 − e^{−100})/2 = 0.5.
    FogMedium fog;
    fog.b = -2.0f;
    EXPECT_NEAR(fog.opticalDepth(50.0f, -1.0f, 50.0f), 0.5f, 1e-6f);
    EXPECT_NEAR(fog.opticalDepth<Float8>(50.0f, Float8(-1.0f), Float8(50.0f))[3], 0.5f, 1e-6f);
    {
        detail::tReferenceMode = true;  // the C library's exp and expm1, as the reference pipeline
        EXPECT_NEAR(fog.opticalDepth(50.0f, -1.0f, 50.0f), 0.5f, 1e-6f);
        detail::tReferenceMode = false;
    }
    // The default b = −0.5 looking down from 180 m to the ground.
    FogMedium standard;
    for (const float s : {1.0f, 90.0f, 179.0f, 180.0f}) {
        const float tau = standard.opticalDepth(180.0f, -1.0f, s);
        const double expected = double(referenceDepth(standard, 180.0, -1.0, s));
        ASSERT_TRUE(std::isfinite(tau)) << s;
        EXPECT_NEAR(tau / expected, 1.0, 1e-5) << s;
        const glm::vec3 L = apply(standard, glm::vec3(0.4f), 180.0f, glm::vec3(0, -1, 0), s);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(L[c], double(referenceRadiance(standard, c, 0.4L, expected)), 1e-6) << s;
    }
}

TEST(FogMedium, NoDistanceIsNoFogWhateverTheDensity) {
    // b·y0 = +200: e^{b·y0} overflows float, but over s = 0 there is no medium to cross.
    FogMedium fog;
    fog.b = 2.0f;
    const glm::vec3 L0(0.1f, 0.6f, 0.9f);
    EXPECT_EQ(fog.opticalDepth(100.0f, -0.5f, 0.0f), 0.0f);
    EXPECT_EQ(apply(fog, L0, 100.0f, glm::normalize(glm::vec3(1, -0.5f, 0)), 0.0f), L0);
    const Float8 tau8 = fog.opticalDepth<Float8>(100.0f, Float8(-0.5f), Float8(0.0f));
    for (int i = 0; i < 8; ++i) EXPECT_EQ(tau8[i], 0.0f);
}

// Found by fuzz_fog on the first stable form (tests/fuzz, docs/RELIABILITY.md): e^{b·y0} close to
// float's ends, times a distance or an e^{k·s} − 1 that overflows before the other factor brings the
// product back. With the exponents combined, τ and L are finite and match long double.
TEST(FogMedium, ExponentsNearTheEndsOfFloatDoNotOverflowInBetween) {
    struct Case {
        float b, y0, dy, s, sigma;
    };
    // e^{87}·s overflows (s = 3.5e5) though τ = e^{87}/|k|; e^{72.9}·s (s = 1e7) likewise, with
    // σ·τ = 0.46; e^{−87} (still a float) times e^{107} − 1 (not one): τ = 4.9e8, σ·τ = 2.4e-22.
    for (const Case& c : {Case{1.0f, 87.0f, -1.0f, 3.5e5f, 1e-38f}, Case{0.1f, 729.0f, -1.0f, 1e7f, 1e-33f},
                          Case{1.0f, -87.0f, 1.0f, 107.0f, 5e-31f}}) {
        FogMedium fog;
        fog.b = c.b;
        fog.sigma = glm::vec3(c.sigma);
        fog.q = glm::vec3(c.sigma * 0.5f);
        const long double tau_ref = referenceDepth(fog, c.y0, c.dy, c.s);
        const glm::vec3 L0(0.441f, 0.2f, 0.9f);
        for (const bool reference_mode : {false, true}) {
            detail::tReferenceMode = reference_mode;
            const float tau = fog.opticalDepth(c.y0, c.dy, c.s);
            const Float8 tau8 = fog.opticalDepth<Float8>(c.y0, Float8(c.dy), Float8(c.s));
            const glm::vec3 L = apply(fog, L0, c.y0, glm::vec3(0.0f, c.dy, 0.0f), c.s);
            detail::tReferenceMode = false;
            ASSERT_TRUE(std::isfinite(tau)) << c.y0 << " reference mode " << reference_mode;
            EXPECT_NEAR(double(tau / tau_ref), 1.0, 1e-5) << c.y0;
            if (!reference_mode) {
                EXPECT_EQ(tau8[4], tau) << "eight-wide equals scalar";
            }
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(L[ch], double(referenceRadiance(fog, ch, L0[ch], tau_ref)), 1e-6) << c.y0 << " " << ch;
        }
    }
}

// Every finite input of a grid spanning the domain (thin to opaque fog, eye below the ground to
// 180 m, every direction, s from 0 to 10 km): finite, within a few ulp times the condition number
// of the long-double value, and the eight-wide path bit for bit the scalar one.
TEST(FogMedium, FiniteAndAccurateOverTheDomain) {
    int checked = 0;
    for (const float b : {-2.0f, -0.5f, -0.01f, 0.0f, 0.3f})
        for (const float y0 : {-50.0f, 0.0f, 2.0f, 50.0f, 180.0f})
            for (const float dy : {-1.0f, -0.5f, -1e-3f, 0.0f, 1e-3f, 0.5f, 1.0f})
                for (const float s : {0.0f, 1e-6f, 1.0f, 50.0f, 1e4f})
                    for (const float sigma : {0.0f, 1e-6f, 0.06f, 5.0f}) {
                        FogMedium fog;
                        fog.b = b;
                        fog.sigma = glm::vec3(sigma);
                        fog.q = glm::vec3(sigma * 0.7f);
                        const long double tau_ref = referenceDepth(fog, y0, dy, s);
                        const float tau = fog.opticalDepth(y0, dy, s);
                        const Float8 tau8 = fog.opticalDepth<Float8>(y0, Float8(dy), Float8(s));
                        ASSERT_EQ(std::bit_cast<uint32_t>(tau8[5]), std::bit_cast<uint32_t>(tau));
                        const glm::vec3 L = fog.applyOpticalDepth(glm::vec3(0.3f), tau);
                        const double ks = std::fabs(double(b) * dy * s), by0 = std::fabs(double(b) * y0);
                        // Relative condition of τ with respect to its inputs, and float's ulp.
                        const double kappa = 1 + by0 + ks;
                        if (tau_ref <= std::numeric_limits<float>::max()) {
                            ASSERT_TRUE(std::isfinite(tau)) << b << " " << y0 << " " << dy << " " << s;
                            EXPECT_LE(std::fabs(double(tau - tau_ref)), 8 * 6e-8 * kappa * double(tau_ref) + 1e-38)
                                << "b " << b << " y0 " << y0 << " dy " << dy << " s " << s;
                        }
                        for (int c = 0; c < 3; ++c) {
                            ASSERT_TRUE(std::isfinite(L[c])) << b << " " << y0 << " " << dy << " " << s;
                            const double L_ref = double(referenceRadiance(fog, c, 0.3L, tau_ref));
                            EXPECT_NEAR(L[c], L_ref, 1e-6 + 8 * 6e-8 * kappa * std::fabs(L_ref - 0.3))
                                << "b " << b << " y0 " << y0 << " dy " << dy << " s " << s << " σ " << sigma;
                        }
                        ++checked;
                    }
    EXPECT_EQ(checked, 5 * 5 * 7 * 5 * 4);
}

}  // namespace
}  // namespace raster
