// Participating media (raster/media/): the phase functions' normalisation, mean cosine and sampling,
// the lecture's errata as failing cases, and the numerical stability of ψ, φ and the closed forms
// against a long-double reference (media/reference.hpp).
//
// The same source is compiled twice (tests/CMakeLists.txt): media_test at the tests' -Og with
// -ffp-contract=off, as the library, and media_contracted_test at -O3 -march=native
// -ffp-contract=fast (RASTER_MEDIA_CONTRACTED), so that no guard depends on the compiler keeping
// a·b + c unfused. The contracted build has the guards and the accuracy bounds (sampling in range,
// ψ and φ, the adversarial grid); the statistics, the checks that Float8 and float agree bit for bit
// (they may fuse differently there) and the shader's are in the first only, to keep its -O3 compile
// small.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "raster/media/exprel.hpp"
#include "raster/media/height_fog.hpp"
#include "raster/media/homogeneous.hpp"
#include "raster/media/phase_functions.hpp"
#include "raster/media/reference.hpp"
#ifndef RASTER_MEDIA_CONTRACTED
#include <functional>

#include "raster/shaders/fog.hpp"
#endif

namespace raster {
namespace {

using media::reference::Real;

#ifdef RASTER_MEDIA_CONTRACTED
constexpr bool kSameBitsAsFloat = false;
#else
constexpr bool kSameBitsAsFloat = true;
#endif

constexpr double kPi = 3.14159265358979323846;

TEST(PhaseFunctions, HenyeyGreensteinKeepsItsPeakAsGNearsOne) {
    // At g = 1 − 1e-6 the peak is (1 + g)/(4π(1 − g)²) = 1.59e11 per steradian; the written
    // denominator 1 + g² − 2g loses it entirely in float.
    const float g = 1 - 1e-6f;  // the float nearest: 0.99999899
    const double a = double(g), expected = (1 + a) / (4 * kPi * (1 - a) * (1 - a));
    EXPECT_NEAR(media::henyeyGreenstein(g, 1.0f) / expected, 1, 1e-6);
    EXPECT_NEAR(media::henyeyGreenstein(-g, -1.0f) / expected, 1, 1e-6);
    EXPECT_NEAR(media::henyeyGreenstein(double(g), 1.0) / expected, 1, 1e-14);
    // g = ±1 exactly: the nearest g inside, finite everywhere, a needle at the peak.
    for (const float c : {-1.0f, 0.0f, 0.999f, 1.0f}) {
        EXPECT_TRUE(std::isfinite(media::henyeyGreenstein(1.0f, c))) << c;
        EXPECT_TRUE(std::isfinite(media::henyeyGreenstein(-1.0f, -c))) << c;
    }
    EXPECT_EQ(media::henyeyGreenstein(0.0f, 0.3f), media::isotropic());
}

double hgCdf(double g, double c) {
    const Real gl = g, cl = c;
    const Real base =
        g >= 0 ? (1 - gl) * (1 - gl) + 2 * gl * (1 - cl) : (1 + gl) * (1 + gl) - 2 * gl * (1 + cl);
    const Real root = std::sqrt(base);
    return double((1 - gl) * (1 + cl) / (root * (1 + gl + root)));
}

TEST(PhaseFunctions, SamplingIsFiniteAndInRangeForEveryG) {
    const float kAlmostOne = 1 - 0x1p-24f;
    std::vector<float> gs = {-1, -kAlmostOne, -0.999999f, -0.99f, -0.5f, -1e-3f, -1e-7f,    -1e-30f,    -0.0f,
                             0,  1e-30f,      1e-7f,      1e-3f,  0.5f,  0.99f,  0.999999f, kAlmostOne, 1};
    for (int i = 0; i <= 200; ++i) gs.push_back(-1 + i / 100.0f);
    for (const float g : gs)
        for (const float u : {0.0f, 0x1p-24f, 0.25f, 0.5f, 0.75f, kAlmostOne}) {
            const media::HenyeyGreensteinSample<float> s = media::sampleHenyeyGreensteinFull(g, u);
            ASSERT_TRUE(std::fabs(s.cosTheta) <= 1) << "g " << g << " u " << u << ": " << s.cosTheta;
            ASSERT_TRUE(s.sinThetaSquared >= 0 && s.sinThetaSquared <= 1.0000005f) << g << " " << u;
            const double d = media::sampleHenyeyGreenstein(double(g), double(u));
            ASSERT_TRUE(std::fabs(d) <= 1) << "g " << g << " u " << u;
        }
    // u = 0 is the CDF's bottom, cos θ = −1, for every g; u = 1 its top.
    for (const float g : gs) {
        EXPECT_EQ(media::sampleHenyeyGreenstein(g, 0.0f), -1.0f) << g;
        EXPECT_EQ(media::sampleHenyeyGreenstein(g, 1.0f), 1.0f) << g;
    }
}

// The sampler inverts the CDF: F(sample(g, u)) = u to double's precision where F is steep enough,
// and continuously through g = 0 (no switch to the isotropic formula below some |g|).
TEST(PhaseFunctions, SamplingInvertsTheCdf) {
    for (const double g : {-0.999999, -0.95, -0.3, -1e-5, -1e-9, 0.0, 1e-9, 1e-5, 0.3, 0.7, 0.95, 0.999999})
        for (int i = 1; i < 100; ++i) {
            const double u = i / 100.0, c = media::sampleHenyeyGreenstein(g, u);
            // |dF/dc| = 2π·p(c): an ulp of c moves F by up to 2π·p·1.1e-16.
            const double slack = 2 * kPi * media::henyeyGreenstein(g, c) * 4e-16 + 1e-14;
            ASSERT_NEAR(hgCdf(g, c), u, slack) << "g " << g << " u " << u;
            // float: within a few roundings of 1 of the double sampler at the same inputs.
            const float cf = media::sampleHenyeyGreenstein(float(g), float(u));
            const double cd = media::sampleHenyeyGreenstein(double(float(g)), double(float(u)));
            ASSERT_NEAR(cf, cd, 8 * 6e-8) << "g " << g << " u " << u;
        }
}

// Pearson's χ² over 100 bins of equal probability (edges by bisection of the double CDF above,
// independent of the sampler), 10⁶ float samples from a seeded generator. The critical value at
// significance 1e-3 for 99 degrees of freedom, by the Wilson–Hilferty approximation, is 148.3: a
// correct sampler fails this test with probability 1e-3, for a given seed never.
// ---- ψ and φ --------------------------------------------------------------------------------------

// |v − ref| in units of the ulp of float at ref (2⁻¹⁴⁹ below the normal range; ∞ for a non-finite
// v where ref is finite).
double ulpError(float v, Real ref) {
    if (std::isnan(v)) return INFINITY;
    const Real a = std::fabs(ref);
    if (a > Real(FLT_MAX)) return std::isinf(v) ? 0 : INFINITY;
    if (std::isinf(v)) return INFINITY;
    int e = 0;
    std::frexp(double(float(ref)), &e);
    const Real ulp = a < Real(FLT_MIN) ? 0x1p-149L : std::ldexp(1.0L, e - 24);
    return double(std::fabs(Real(v) - ref) / ulp);
}

// The arguments where ψ's evaluation switches branch or its reduction switches k (exprel.hpp), and
// where it overflows: each with the 2¹² floats on either side, both signs.
std::vector<float> psiBranchNeighbourhoods() {
    std::vector<float> xs;
    for (const float edge :
         {media::detail::kSeriesBelow, 0.34657359f /* ln2/2 */, media::detail::kUnreducedBelow,
          media::detail::kGrowingAbove, 88.72f, 93.2f, media::detail::kOverflowAbove})
        for (const float sign : {1.0f, -1.0f}) {
            const uint32_t bits = std::bit_cast<uint32_t>(edge);
            for (uint32_t i = bits - 8192; i <= bits + 8192; ++i)
                xs.push_back(sign * std::bit_cast<float>(i));
        }
    return xs;
}

// Every 8191st float of either sign (prime, so every binade and many positions in one), and the
// neighbourhoods: 0.6 million arguments. `raster bench fog-accuracy --exhaustive` checks every float
// (docs/ACCURACY.md).
std::vector<float> psiSweep() {
    std::vector<float> xs = psiBranchNeighbourhoods();
    for (uint32_t bits = 0; bits < 0x7F800000u; bits += 8191) {
        xs.push_back(std::bit_cast<float>(bits));
        xs.push_back(-std::bit_cast<float>(bits));
    }
    return xs;
}

TEST(Exprel, PsiIsWithinTwoUlpOverADenseSweep) {
    const std::vector<float> xs = psiSweep();
    double worst = 0;
    float worst_at = 0;
    for (size_t i = 0; i < xs.size(); i += 8) {
        Float8 x8;
        for (int j = 0; j < 8; ++j) x8.set(j, xs[std::min(i + j, xs.size() - 1)]);
        const Float8 v8 = media::psi(x8);
        for (int j = 0; j < 8 && i + j < xs.size(); ++j) {
            const float x = xs[i + j], v = media::psi(x);
            const double e = ulpError(v, media::reference::psi(x));
            if (e > worst) worst = e, worst_at = x;
            if (kSameBitsAsFloat) {
                ASSERT_EQ(std::bit_cast<uint32_t>(v8[j]), std::bit_cast<uint32_t>(v)) << x;
            }
            ASSERT_EQ(std::bit_cast<uint32_t>(media::phi(-x)), std::bit_cast<uint32_t>(v))
                << "φ(z) = ψ(−z) at " << -x;
        }
    }
    std::printf("psi: %zu arguments, at most %.3f ulp (at %.9g)\n", xs.size(), worst, double(worst_at));
    EXPECT_LE(worst, 2.0) << "at " << worst_at;
}

// Across each switch (the two floats on either side): the computed step is the true step to 2 ulp.
TEST(Exprel, PsiHasNoJumpWhereItsEvaluationSwitches) {
    for (const float edge : {media::detail::kSeriesBelow, 0.34657359f, media::detail::kUnreducedBelow,
                             media::detail::kGrowingAbove, media::detail::kOverflowAbove})
        for (const float sign : {1.0f, -1.0f}) {
            const uint32_t bits = std::bit_cast<uint32_t>(edge);
            for (uint32_t i = bits - 4; i <= bits + 4; ++i) {
                const float a = sign * std::bit_cast<float>(i), b = sign * std::bit_cast<float>(i + 1);
                const Real true_step = media::reference::psi(b) - media::reference::psi(a);
                const Real step = Real(media::psi(b)) - Real(media::psi(a));
                if (!std::isfinite(step)) continue;  // past the overflow
                const Real ulp = std::ldexp(1.0L, std::ilogb(media::psi(a)) - 23);
                EXPECT_LE(double(std::fabs(step - true_step) / ulp), 2.0) << "between " << a << " and " << b;
            }
        }
}

TEST(Exprel, ReferencePipelineAndDoubleAreAccurateToo) {
    std::mt19937 rng(46);
    std::uniform_int_distribution<uint32_t> bits(0, 0x7F7FFFFFu);
    double worst_reference = 0, worst_double = 0;
    detail::tReferenceMode = true;
    for (int n = 0; n < 100000; ++n) {
        const float x = (n & 1 ? -1.0f : 1.0f) * std::bit_cast<float>(bits(rng));
        worst_reference = std::max(worst_reference, ulpError(media::psi(x), media::reference::psi(x)));
        const double xd = double(x) * (1 + 0x1p-30), vd = media::psi(xd);
        const Real ref = media::reference::psi(xd);
        if (std::fabs(ref) < Real(DBL_MAX)) {
            worst_double = std::max(worst_double, double(std::fabs(vd - ref) / (std::fabs(ref) * 0x1p-53L)));
        }
    }
    detail::tReferenceMode = false;
    std::printf("psi: reference pipeline at most %.3f ulp, double at most %.3f double ulp\n", worst_reference,
                worst_double);
    EXPECT_LE(worst_reference, 2.0);
    EXPECT_LE(worst_double, 8.0);
}

TEST(Exprel, LimitsAndSpecialValues) {
    const float inf = INFINITY;
    for (const float zero : {0.0f, -0.0f}) {
        EXPECT_EQ(media::psi(zero), 1.0f);
        EXPECT_EQ(media::phi(zero), 1.0f);
        EXPECT_EQ(media::psi(double(zero)), 1.0);
    }
    EXPECT_EQ(media::psi(1e-30f), 1.0f);
    EXPECT_EQ(media::psi(inf), 0.0f);
    EXPECT_EQ(media::psi(-inf), inf);
    EXPECT_EQ(media::phi(inf), inf);
    EXPECT_EQ(media::psi(-93.0f), float(media::reference::psi(-93.0L)));  // e^93/93 = 2.6e38, a float
    EXPECT_EQ(media::psi(-94.0f), inf);
    EXPECT_EQ(media::psi(1e30f), 1e-30f);
    EXPECT_TRUE(std::isnan(media::psi(NAN)));
    EXPECT_TRUE(std::isnan(media::psi(Float8(NAN))[3]));
    // ℓ(μ, s): s for μ = 0 (also at s = ∞), 1/μ for s = ∞, s·ψ(μs) between.
    EXPECT_EQ(media::attenuatedLength(0.0f, 7.0f), 7.0f);
    EXPECT_EQ(media::attenuatedLength(0.0f, inf), inf);
    EXPECT_EQ(media::attenuatedLength(4.0f, inf), 0.25f);
    EXPECT_EQ(media::attenuatedLength(1e-30f, 1e6f), 1e6f);
    EXPECT_EQ(media::attenuatedLength(0.0, 0.0), 0.0);
    EXPECT_EQ(media::attenuatedLength(Float8(0.0f), Float8(inf))[0], inf);
}

// ---- The closed forms over the adversarial grid -------------------------------------------------

// A float result against its long-double reference: within kUlps·(1 + κ) float ulps (relative to
// the reference) plus an absolute floor, 2⁻¹²⁶ unless said (the fast exp flushes results below
// float's normal range to 0), +∞ where the reference is past FLT_MAX (or within the tolerance of it),
// never NaN.
constexpr double kUlps = 8;

struct Tally {
    double worst = 0;  // max (|v − ref| − floor)/(u·(1 + κ)·|ref|) over finite nonzero float refs
    int cases = 0;
};

// kappa() gives the condition number; it is evaluated only where the error could need it (the
// tolerance or the tally), as it costs a reference evaluation per input.
template <class Kappa>
bool accurate(float v, Real ref, Kappa kappa, Tally& tally, Real floor = 0x1p-126L) {
    constexpr Real u = media::reference::kFloatUnitRoundoff;
    ++tally.cases;
    if (std::isnan(v) || std::isnan(ref)) return false;
    const Real error = std::fabs(Real(v) - ref), magnitude = std::fabs(ref);
    const bool finite = std::isfinite(v) && magnitude <= Real(FLT_MAX);
    const Real excess = std::max(error - floor, 0.0L);
    if (finite && excess <= kUlps * u * magnitude && excess <= tally.worst * u * magnitude) return true;
    const Real k = kappa();
    const Real tolerance = kUlps * u * (1 + k);
    if (magnitude > Real(FLT_MAX)) return v == INFINITY || Real(v) >= Real(FLT_MAX) * (1 - tolerance);
    if (std::isinf(v)) return magnitude * (1 + tolerance) > Real(FLT_MAX) && v > 0;
    if (magnitude >= Real(FLT_MIN))
        tally.worst = std::max(tally.worst, double(excess / (u * (1 + k) * magnitude)));
    return excess <= tolerance * magnitude;
}

using Grid = media::reference::AdversarialGrid;

TEST(HomogeneousMedium, ClosedFormOverTheAdversarialGrid) {
    Tally tally;
    for (const float mu : Grid::kExtinction)
        for (const float q : Grid::kSource)
            for (const float L0 : Grid::kSurface)
                for (const float s : Grid::kDistance) {
                    const float L = media::radiance(L0, mu, q, s);
                    auto f = [](const std::array<Real, 4>& x) {
                        return media::reference::radiance(x[0], x[1], x[2], x[3]);
                    };
                    const std::array<Real, 4> in = {L0, mu, q, s};
                    const Real ref = f(in);
                    ASSERT_TRUE(accurate(
                        L, ref, [&] { return media::reference::relativeCondition(f, in); }, tally))
                        << "L0 " << L0 << " μ " << mu << " q " << q << " s " << s << ": " << L
                        << ", reference " << double(ref);
                    if (kSameBitsAsFloat) {
                        ASSERT_EQ(std::bit_cast<uint32_t>(
                                      media::radiance(Float8(L0), Float8(mu), Float8(q), Float8(s))[2]),
                                  std::bit_cast<uint32_t>(L));
                    }
                    const float T = media::transmittance(mu, s);
                    ASSERT_TRUE(T >= 0 && T <= 1) << mu << " " << s;
                    const double Ld = media::radiance(double(L0), double(mu), double(q), double(s));
                    ASSERT_TRUE(std::fabs(Ld - double(ref)) <= 1e-14 * std::fabs(double(ref)) + 1e-300 ||
                                Ld == double(ref))
                        << "double: L0 " << L0 << " μ " << mu << " q " << q << " s " << s;
                }
    std::printf("homogeneous: %d cases, at most %.3f ulp·(1 + κ)\n", tally.cases, tally.worst);
}

TEST(HeightFog, OpticalDepthOverTheAdversarialGrid) {
    Tally tally;
    for (const float b : Grid::kFalloff)
        for (const float y0 : Grid::kHeight)
            for (const float dy : Grid::kDirectionY)
                for (const float s : Grid::kDistance) {
                    const float tau = media::heightFogOpticalDepth(b, y0, dy, s);
                    auto f = [](const std::array<Real, 4>& x) {
                        return media::reference::heightFogOpticalDepth(x[0], x[1], x[2], x[3]);
                    };
                    const std::array<Real, 4> in = {b, y0, dy, s};
                    const Real ref = f(in);
                    ASSERT_TRUE(accurate(
                        tau, ref, [&] { return media::reference::relativeCondition(f, in); }, tally))
                        << "b " << b << " y0 " << y0 << " dy " << dy << " s " << s << ": " << tau
                        << ", reference " << double(ref);
                    if (std::isinf(s)) {
                        ASSERT_EQ(std::bit_cast<uint32_t>(media::heightFogOpticalDepthToInfinity(b, y0, dy)),
                                  std::bit_cast<uint32_t>(tau));
                    }
                    if (kSameBitsAsFloat) {
                        ASSERT_EQ(std::bit_cast<uint32_t>(media::heightFogOpticalDepth(
                                      Float8(b), Float8(y0), Float8(dy), Float8(s))[6]),
                                  std::bit_cast<uint32_t>(tau));
                    }
                }
    std::printf("height fog τ: %d cases, at most %.3f ulp·(1 + κ)\n", tally.cases, tally.worst);
}

// L for every extinction, source and surface radiance of the grid over every ray of it. τ is a float:
// where it is below 2⁻¹²⁶ (flushed to 0) the gathered q·τ loses up to q·2⁻¹²⁶ (height_fog.hpp).
TEST(HeightFog, RadianceOverTheAdversarialGrid) {
    Tally tally;
    for (const float b : Grid::kFalloff)
        for (const float y0 : Grid::kHeight)
            for (const float dy : Grid::kDirectionY)
                for (const float s : Grid::kDistance) {
                    const float tau = media::heightFogOpticalDepth(b, y0, dy, s);
                    for (const float sigma : Grid::kExtinction)
                        for (const float q : Grid::kSource)
                            for (const float L0 : Grid::kSurface) {
                                const float L = media::radiance(L0, sigma, q, tau);
                                auto f = [](const std::array<Real, 7>& x) {
                                    return media::reference::heightFogRadiance(x[0], x[1], x[2], x[3], x[4],
                                                                               x[5], x[6]);
                                };
                                const std::array<Real, 7> in = {L0, sigma, q, b, y0, dy, s};
                                const Real ref = f(in);
                                auto kappa = [&] { return media::reference::relativeCondition(f, in); };
                                ASSERT_TRUE(accurate(L, ref, kappa, tally, 0x1p-126L * (1 + Real(q))))
                                    << "L0 " << L0 << " σ " << sigma << " q " << q << " b " << b << " y0 "
                                    << y0 << " dy " << dy << " s " << s << ": " << L << ", reference "
                                    << double(ref) << " (τ " << tau << ")";
                            }
                }
    std::printf("height fog L: %d cases, at most %.3f ulp·(1 + κ)\n", tally.cases, tally.worst);
}

// Through a horizontal ray: d_y = ±0 give the same bits, and rays grazing it by 1e-30 or 1e-38 the
// value of the horizontal one to within its tolerance (no 0/0, no switch that jumps).
TEST(HeightFog, ContinuousAcrossAHorizontalRay) {
    Tally tally;
    for (const float b : Grid::kFalloff)
        for (const float y0 : Grid::kHeight)
            for (const float s : Grid::kDistance) {
                if (std::isinf(s)) continue;  // τ(∞) is ∞ on the horizontal and finite above it: a true jump
                const float flat = media::heightFogOpticalDepth(b, y0, 0.0f, s);
                ASSERT_EQ(std::bit_cast<uint32_t>(media::heightFogOpticalDepth(b, y0, -0.0f, s)),
                          std::bit_cast<uint32_t>(flat));
                const Real flat_ref = media::reference::heightFogOpticalDepth(b, y0, 0, s);
                for (const float dy : {1e-30f, -1e-30f, 1e-38f, -1e-38f}) {
                    const float tau = media::heightFogOpticalDepth(b, y0, dy, s);
                    auto f = [](const std::array<Real, 4>& x) {
                        return media::reference::heightFogOpticalDepth(x[0], x[1], x[2], x[3]);
                    };
                    const std::array<Real, 4> in = {b, y0, dy, s};
                    const Real kappa = media::reference::relativeCondition(f, in);
                    ASSERT_TRUE(accurate(
                        tau, f(in), [&] { return kappa; }, tally))
                        << "b " << b << " y0 " << y0 << " dy " << dy << " s " << s;
                    const Real step = std::fabs(Real(tau) - Real(flat)),
                               true_step = std::fabs(f(in) - flat_ref);
                    if (std::isfinite(flat_ref) && flat_ref <= Real(FLT_MAX)) {
                        ASSERT_LE(step, true_step +
                                            2 * kUlps * media::reference::kFloatUnitRoundoff * (1 + kappa) *
                                                flat_ref +
                                            0x1p-126L)
                            << "b " << b << " y0 " << y0 << " dy " << dy << " s " << s;
                    }
                }
            }
}

// FogMedium (shaders/fog.hpp, the benchmark scene's shader) takes its optical depth from media/.
#ifndef RASTER_MEDIA_CONTRACTED
// ---- Not in the contracted build: statistics, bit-for-bit agreement, the shader ----------------

// ---- Quadrature ---------------------------------------------------------------------------------

// Gauss–Legendre nodes and weights on [−1, 1] (Newton's method on P_n).
struct GaussLegendre {
    std::vector<double> x, w;
    explicit GaussLegendre(int n) {
        for (int i = 0; i < n; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= n; ++k)
                    std::tie(p0, p1) = std::pair(p1, ((2 * k - 1) * z * p1 - (k - 1) * p0) / k);
                dp = n * (z * p1 - p0) / (z * z - 1);
                const double dz = p1 / dp;
                z -= dz;
                if (std::fabs(dz) < 1e-16) break;
            }
            x.push_back(z);
            w.push_back(2 / ((1 - z * z) * dp * dp));
        }
    }
};

// ∫ p dω over the sphere of a function of cos θ with its peak (if any) at cos θ = peak (±1):
// 2π·∫ f(peak·(1 − t)) dt over t ∈ [0, 2], on panels graded geometrically toward t = 0 from a first
// panel of `width`, each integrated by 20-point Gauss–Legendre. With width a small fraction of the
// peak's own width (1 − |g|)², each panel sees a smooth, slowly varying piece of the integrand.
double sphereIntegral(const std::function<double(double)>& f, double peak, double width) {
    static const GaussLegendre gl(20);
    double sum = 0, lo = 0, hi = std::min(width, 2.0);
    while (lo < 2) {
        const double mid = (lo + hi) / 2, half = (hi - lo) / 2;
        for (size_t i = 0; i < gl.x.size(); ++i)
            sum += gl.w[i] * half * f(peak * (1 - (mid + half * gl.x[i])));
        lo = hi;
        hi = std::min(2.0, hi * 2);
    }
    return 2 * kPi * sum;
}

const double kAnisotropies[] = {0, 0.5, -0.5, 0.9, -0.9, 0.99, -0.99, 0.999, -0.999, 0.999999, -0.999999};

double peakWidth(double g) {
    return std::max((1 - std::fabs(g)) * (1 - std::fabs(g)), 1e-14) / 16;
}

// ---- Phase functions ----------------------------------------------------------------------------

TEST(PhaseFunctions, IntegrateToOneAndHaveMeanCosineG) {
    EXPECT_NEAR(sphereIntegral([](double) { return media::isotropic<double>(); }, 1, 1), 1, 1e-12);
    EXPECT_NEAR(sphereIntegral([](double c) { return media::rayleigh(c); }, 1, 1), 1, 1e-12);
    EXPECT_NEAR(sphereIntegral([](double c) { return c * media::rayleigh(c); }, 1, 1), 0, 1e-12);
    for (const double g : kAnisotropies) {
        const double peak = g < 0 ? -1 : 1;
        auto p = [g](double c) { return media::henyeyGreenstein(g, c); };
        EXPECT_NEAR(sphereIntegral(p, peak, peakWidth(g)), 1, 1e-6) << "g " << g;
        EXPECT_NEAR(sphereIntegral([&](double c) { return c * p(c); }, peak, peakWidth(g)), g, 1e-6)
            << "g " << g;
    }
}

// The float instantiation (and Float8, the same bits) integrates to 1 as well where float's cos θ
// resolves the peak: its steps of 6e-8 near ±1 against a peak (1 − |g|)² wide (at |g| = 0.99 the
// quadrature of the float-quantised integrand is 1.5e-6 off).
TEST(PhaseFunctions, FloatEvaluationIntegratesToOne) {
    for (const double g : {0.0, 0.5, -0.5, 0.9, -0.9}) {
        auto p = [g](double c) { return double(media::henyeyGreenstein(float(g), float(c))); };
        EXPECT_NEAR(sphereIntegral(p, g < 0 ? -1 : 1, peakWidth(g)), 1, 1e-6) << "g " << g;
    }
    EXPECT_NEAR(sphereIntegral([](double c) { return double(media::rayleigh(float(c))); }, 1, 1), 1, 1e-6);
}

// The slide's forms fail the same test: 2/(16π) for Rayleigh's constant (∫ = 2/3), and the
// exponent 2/3 for Henyey–Greenstein's denominator (normalised only for g = 0).
TEST(PhaseFunctions, TheSlidesFormsAreNotNormalised) {
    const double rayleigh = sphereIntegral([](double c) { return 2 / (16 * kPi) * (1 + c * c); }, 1, 1);
    EXPECT_NEAR(rayleigh, 2.0 / 3.0, 1e-12);
    for (const double g : kAnisotropies) {
        auto slide = [g](double c) {
            return (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g * c, 2.0 / 3.0));
        };
        const double integral = sphereIntegral(slide, g < 0 ? -1 : 1, peakWidth(g));
        if (g == 0) {
            EXPECT_NEAR(integral, 1, 1e-12);
        } else {
            EXPECT_GT(std::fabs(integral - 1), 1e-3) << "g " << g << ": the slide's exponent normalises";
        }
    }
}

TEST(PhaseFunctions, EightWideIsTheScalarLaneByLane) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> cos_dist(-1, 1), g_dist(-1, 1);
    for (int trial = 0; trial < 1000; ++trial) {
        Float8 g, c, u;
        for (int i = 0; i < 8; ++i)
            g.set(i, g_dist(rng)), c.set(i, cos_dist(rng)), u.set(i, (cos_dist(rng) + 1) / 2);
        const Float8 hg = media::henyeyGreenstein(g, c), ray = media::rayleigh(c);
        const Float8 sample = media::sampleHenyeyGreenstein(g, u);
        for (int i = 0; i < 8; ++i) {
            ASSERT_EQ(std::bit_cast<uint32_t>(hg[i]),
                      std::bit_cast<uint32_t>(media::henyeyGreenstein(g[i], c[i])));
            ASSERT_EQ(std::bit_cast<uint32_t>(ray[i]), std::bit_cast<uint32_t>(media::rayleigh(c[i])));
            ASSERT_EQ(std::bit_cast<uint32_t>(sample[i]),
                      std::bit_cast<uint32_t>(media::sampleHenyeyGreenstein(g[i], u[i])));
        }
    }
}

// The Henyey–Greenstein CDF of cos θ, F(c) = (1 − g²)/(2g)·(1/√B − 1/(1 + g)), B = 1 + g² − 2g·c, in
// long double and without its cancellation as g → 0: F(c) = (1 − g)(1 + c)/(√B·(1 + g + √B)), with B
// as (1 − g)² + 2g(1 − c) for g ≥ 0 and (1 + g)² − 2g(1 + c) for g < 0.
double chiSquareCritical(int dof) {
    const double z = 3.090232;  // the standard normal's 1 − 1e-3 quantile
    const double h = 2.0 / (9.0 * dof);
    return dof * std::pow(1 - h + z * std::sqrt(h), 3);
}

TEST(PhaseFunctions, SamplesPassChiSquare) {
    constexpr int kBins = 100, kSamples = 1000000;
    for (const float g : {0.0f, 0.7f, -0.95f}) {
        std::vector<double> edges;
        for (int i = 1; i < kBins; ++i) {
            double lo = -1, hi = 1;
            for (int it = 0; it < 100; ++it)
                (hgCdf(g, (lo + hi) / 2) < double(i) / kBins ? lo : hi) = (lo + hi) / 2;
            edges.push_back((lo + hi) / 2);
        }
        std::mt19937 rng(20261204);
        std::vector<int> count(kBins, 0);
        for (int n = 0; n < kSamples; ++n) {
            const float u = float(rng() >> 8) * 0x1p-24f;
            const float c = media::sampleHenyeyGreenstein(g, u);
            ++count[std::upper_bound(edges.begin(), edges.end(), double(c)) - edges.begin()];
        }
        double chi2 = 0;
        const double expected = double(kSamples) / kBins;
        for (const int o : count) chi2 += (o - expected) * (o - expected) / expected;
        EXPECT_LT(chi2, chiSquareCritical(kBins - 1)) << "g " << g;
    }
}

// Directions: unit length, the sampled angle to `travel`, and a uniform azimuth (χ² over 8 sectors
// of each of 10 equal-probability cos θ bands, 2·10⁵ samples, significance 1e-3).
TEST(PhaseFunctions, DirectionSamplerIsUnitWithUniformAzimuth) {
    const glm::vec3 travel = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    const glm::vec3 e1 = glm::normalize(glm::cross(travel, glm::vec3(0, 1, 0))), e2 = glm::cross(travel, e1);
    const float g = 0.7f;
    constexpr int kBands = 10, kSectors = 8, kSamples = 200000;
    std::vector<int> count(kBands * kSectors, 0);
    std::mt19937 rng(1204);
    for (int n = 0; n < kSamples; ++n) {
        const glm::vec2 u(float(rng() >> 8) * 0x1p-24f, float(rng() >> 8) * 0x1p-24f);
        const glm::vec3 w = media::sampleHenyeyGreensteinDirection(travel, g, u);
        ASSERT_NEAR(glm::length(w), 1.0f, 1e-6f);
        ASSERT_NEAR(glm::dot(w, travel), media::sampleHenyeyGreenstein(g, u.x), 2e-6f);
        const int band =
            std::min(kBands - 1, int(hgCdf(g, std::clamp(double(glm::dot(w, travel)), -1.0, 1.0)) * kBands));
        const double azimuth = std::atan2(double(glm::dot(w, e2)), double(glm::dot(w, e1))) + kPi;
        const int sector = std::min(kSectors - 1, int(azimuth / (2 * kPi) * kSectors));
        ++count[band * kSectors + sector];
    }
    double chi2 = 0;
    const double expected = double(kSamples) / (kBands * kSectors);
    for (const int o : count) chi2 += (o - expected) * (o - expected) / expected;
    EXPECT_LT(chi2, chiSquareCritical(kBands * kSectors - 1));
    // Straight up or down, and g = ±1: still unit vectors.
    for (const glm::vec3 t : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0)})
        for (const float gg : {-1.0f, 0.0f, 1.0f}) {
            const glm::vec3 w = media::sampleHenyeyGreensteinDirection(t, gg, glm::vec2(0.3f, 0.6f));
            EXPECT_NEAR(glm::length(w), 1.0f, 1e-6f);
        }
}

TEST(HeightFog, FogMediumUsesTheMediaFunctions) {
    shaders::FogMedium fog;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> y(-50, 200), d(-1, 1), dist(0, 500);
    for (int n = 0; n < 10000; ++n) {
        const float y0 = y(rng), dy = d(rng), s = dist(rng);
        ASSERT_EQ(std::bit_cast<uint32_t>(fog.opticalDepth(y0, dy, s)),
                  std::bit_cast<uint32_t>(media::heightFogOpticalDepth(fog.b, y0, dy, s)));
        ASSERT_EQ(std::bit_cast<uint32_t>(fog.opticalDepth(y0, dy, INFINITY)),
                  std::bit_cast<uint32_t>(media::heightFogOpticalDepthToInfinity(fog.b, y0, dy)));
    }
}

TEST(HomogeneousMedium, RgbChannelsAndLimits) {
    media::HomogeneousMedium m;
    m.absorption = {0.5f, 0.0f, 0.0f};
    m.scattering = {0.25f, 0.0f, 0.0f};
    m.emission = {0.1f, 0.2f, 0.0f};
    const glm::vec3 L0(0.3f, 0.4f, 0.5f);
    // Red absorbs, scatters and emits; green only emits (L0 + ε·s, unbounded at s = ∞); blue is empty.
    const glm::vec3 L = m.radiance(L0, 2.0f, glm::vec3(1.0f));
    const double mu = 0.75, q = 0.1 + 0.25;
    EXPECT_NEAR(L.r, 0.3 * std::exp(-mu * 2) + q / mu * -std::expm1(-mu * 2), 1e-6);
    EXPECT_NEAR(L.g, 0.4f + 0.2f * 2.0f, 1e-6);
    EXPECT_EQ(L.b, 0.5f);
    const glm::vec3 far = m.radiance(L0, float(INFINITY), glm::vec3(1.0f));
    EXPECT_NEAR(far.r, q / mu, 1e-6);
    EXPECT_EQ(far.g, INFINITY);
    EXPECT_EQ(far.b, 0.5f) << "no extinction: the background itself, however far";
    EXPECT_EQ(m.transmittance(float(INFINITY)), glm::vec3(0.0f, 1.0f, 1.0f));
    EXPECT_EQ(m.radiance(L0, 0.0f), L0);
    m.validate();
    m.scattering.g = -1;
    try {
        m.validate();
        ADD_FAILURE() << "a negative coefficient passed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("scattering: -1 is negative"), std::string::npos) << e.what();
    }
    m.scattering.g = NAN;
    EXPECT_THROW(m.validate(), Error);
    m.scattering.g = INFINITY;
    EXPECT_THROW(m.validate(), Error);
}

#endif  // RASTER_MEDIA_CONTRACTED

}  // namespace
}  // namespace raster
