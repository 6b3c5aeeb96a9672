// libFuzzer target: the fog formulas of shaders/fog.hpp (FogMedium::apply, opticalDepth,
// applyOpticalDepth and PsSky's background), the scalar float path and the Float8 path, against a
// long-double reference written from the physics (fog.hpp's header, ../shared/lecture/NOTES.md):
//
//   L = L0·T + (q/σ)·(1 − T),  T = e^{−σ·τ}                 (σ → 0: L = L0 + q·τ)
//   constant fog  τ(s) = s
//   height fog    τ(s) = e^{b·y0}·(e^{k·s} − 1)/k,  k = b·d_y  (k → 0: e^{b·y0}·s)
//   s = ∞         τ = e^{b·y0}/(−k) for k < 0, else ∞ (constant fog: ∞)
//
// Inputs, every one a finite float in a physical domain: σ, q in {0} ∪ [1e-30, 1e4] per channel,
// L0 in [0, 1], s in {0, ∞} ∪ [1e-30, 1e7], d_y in [−1, 1] (the direction a unit vector), b in
// {0} ∪ ±[1e-6, 1e2] and y0 with |b·y0| ≤ 200 (so e^{b·y0} over- and underflows float).
//
// The contract checked, for each colour channel:
//  - L is not NaN; where L_ref > FLT_MAX (σ = 0, q > 0 and τ huge) it is +∞, and where σ = 0 and
//    τ_ref > FLT_MAX, which float cannot hold, +∞ is accepted too;
//  - otherwise |L − L_ref| ≤ 8·u·(κ + 1)·|L_ref| + 1e-6, u = 2^-24 (float's unit roundoff). κ is
//    L_ref's condition number for the float computation, estimated in long double: the sum over
//    every input and every intermediate the float code rounds (b·y0, k, k·s, e^{b·y0}, (e^x − 1)/x,
//    τ, σ·τ, T, 1 − T, q/σ) of |ΔL|/(u·|L|) when that one quantity is scaled by 1 + u. The factor 8
//    covers the library's exp (1 ulp) and expm1 (2 ulp, simd.hpp) and a few roundings in a row;
//    the absolute 1e-6 is far below 1/255 for the displayed range L ≤ 1, and covers what float
//    cannot hold (a T below 2^-126, flushed to 0 by the fast exp);
//  - opticalDepth's τ is not NaN and not negative, and within the same kind of tolerance of τ_ref
//    where e^{b·y0} is a normal float (|b·y0| ≤ 87) and 1e-30 ≤ τ_ref ≤ FLT_MAX/4;
//  - the Float8 path (opticalDepth<Float8>, opticalDepthToInfinity<Float8>, applyOpticalDepth<Float8>,
//    PsSky over Float8) gives, lane by lane, the same bits as the scalar path (simd.hpp's promise).
// Then, from the bytes left, raster/media/'s functions (against media/reference.hpp):
//  - ψ and φ at an arbitrary finite float: within 2 ulp, ∞ only past FLT_MAX, NaN never;
//  - the homogeneous closed form media::radiance (μ, q, L0, s as above, each channel's) and the height
//    fog's media::heightFogOpticalDepth over the same rays, and the radiance from that τ: within
//    8 ulp·(1 + κ) (κ by perturbing the inputs, reference::relativeCondition) plus 2⁻¹²⁶·(1 + q)
//    absolute (a τ below float's range loses q·τ), or, where τ is past FLT_MAX, the limit at τ = ∞;
//    transmittance in [0, 1];
//  - the phase functions at g ∈ [−1, 1] (edges and tiny |g| favoured) and cos θ, u ∈ [0, 1]:
//    Henyey–Greenstein finite and > 0, within 16 ulp·(1 + κ) of its long-double value where |g| < 1;
//    a sample's cos θ in [−1, 1], never NaN, and the CDF at it within 8 ulp of 1 times the density of
//    u; Rayleigh within 4 ulp;
//  - each at eight lanes of Float8 gives the scalar's bits.
// A broken contract prints the inputs and aborts, which libFuzzer reports as a crash.
#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>

#include "raster/media/exprel.hpp"
#include "raster/media/height_fog.hpp"
#include "raster/media/homogeneous.hpp"
#include "raster/media/phase_functions.hpp"
#include "raster/media/reference.hpp"
#include "raster/shaders/fog.hpp"
#include "raster/simd.hpp"

namespace {

using raster::Float8;
using raster::shaders::FogMedium;
using raster::shaders::PsSky;
using raster::shaders::SkyVertexT;

using Real = long double;
constexpr Real kU = 0x1p-24L;  // float's unit roundoff
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- Inputs -------------------------------------------------------------------------------------

float logUniform(FuzzedDataProvider& in, float lo, float hi) {
    const double t = in.ConsumeProbability<double>();
    return float(std::exp(std::log(double(lo)) + t * (std::log(double(hi)) - std::log(double(lo)))));
}

float sigmaOrQ(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            return 0.0f;
        case 1:
            return 1e-30f;
        case 2:
            return in.ConsumeFloatingPointInRange<float>(0.0f, 1.0f);
        default:
            return logUniform(in, 1e-30f, 1e4f);
    }
}

float distance(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            return 0.0f;
        case 1:
            return kInf;
        case 2:
            return in.ConsumeFloatingPointInRange<float>(0.0f, 100.0f);
        default:
            return logUniform(in, 1e-30f, 1e7f);
    }
}

float directionY(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            return 0.0f;
        case 1:
            return in.ConsumeBool() ? 1.0f : -1.0f;
        case 2:
            return (in.ConsumeBool() ? 1.0f : -1.0f) * logUniform(in, 1e-30f, 1e-3f);
        default:
            return in.ConsumeFloatingPointInRange<float>(-1.0f, 1.0f);
    }
}

struct Medium {
    FogMedium fog;
    float y0 = 0.0f;
};

Medium medium(FuzzedDataProvider& in) {
    Medium m;
    for (int c = 0; c < 3; ++c) m.fog.sigma[c] = sigmaOrQ(in);
    for (int c = 0; c < 3; ++c) m.fog.q[c] = sigmaOrQ(in);
    m.fog.height = in.ConsumeIntegralInRange<int>(0, 3) != 0;
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
        case 0:
            m.fog.b = 0.0f;
            break;
        case 1:
            m.fog.b = in.ConsumeFloatingPointInRange<float>(-2.0f, 2.0f);
            break;
        default:
            m.fog.b = (in.ConsumeBool() ? 1.0f : -1.0f) * logUniform(in, 1e-6f, 1e2f);
    }
    // b·y0, edges included: 0, ±87.3 and ±88.7 (where float's e^x ends), ±200.
    float p;
    switch (in.ConsumeIntegralInRange<int>(0, 7)) {
        case 0:
            p = 0.0f;
            break;
        case 1:
            p = in.ConsumeBool() ? 200.0f : -200.0f;
            break;
        case 2:
            p = in.ConsumeBool() ? 88.72f : -87.3f;
            break;
        case 3:
            p = in.ConsumeFloatingPointInRange<float>(-5.0f, 5.0f);
            break;
        default:
            p = in.ConsumeFloatingPointInRange<float>(-200.0f, 200.0f);
    }
    m.y0 = m.fog.b != 0.0f ? p / m.fog.b : in.ConsumeFloatingPointInRange<float>(-1e4f, 1e4f);
    if (!std::isfinite(m.y0)) m.y0 = 0.0f;
    // Rounding may put b·y0 a hair past ±200: pulled back in.
    while (std::fabs(Real(m.fog.b) * Real(m.y0)) > 200.0L) m.y0 = std::nextafter(m.y0, 0.0f);
    return m;
}

// ---- The reference ------------------------------------------------------------------------------

// What the reference computes for one channel; `perturbed` names the quantity scaled by 1 + u
// (kNone: none), for the condition number.
enum Quantity {
    kL0,
    kSigma,
    kQ,
    kS,
    kY0,
    kB,
    kDy,  // inputs
    kBy0,
    kK,
    kKs,
    kExpBy0,
    kGrowth,
    kTau,  // intermediates of τ
    kSigmaTau,
    kT,
    kOneMinusT,
    kQOverSigma,  // of L
    kQuantities,
    kNone = kQuantities
};

struct Channel {
    Real L0, sigma, q, s, y0, b, dy;
    bool height;
};

struct Reference {
    Real tau, L, by0;
};

Reference reference(const Channel& c, int perturbed) {
    auto p = [&](Quantity q, Real v) { return q == perturbed ? v * (1.0L + kU) : v; };
    const Real L0 = p(kL0, c.L0), sigma = p(kSigma, c.sigma), q = p(kQ, c.q), s = p(kS, c.s),
               y0 = p(kY0, c.y0), b = p(kB, c.b), dy = p(kDy, c.dy);
    Real tau, by0 = 0;
    if (!c.height) {
        tau = s;
    } else {
        by0 = p(kBy0, b * y0);
        const Real k = p(kK, b * dy);
        // e^{b·y0} and (e^x − 1)/x as factors of their own, so that each can be perturbed alone.
        const Real e = p(kExpBy0, 1.0L), grow = p(kGrowth, 1.0L);
        if (std::isinf(s)) {
            tau = k < 0 ? e * std::exp(by0) / -k : Real(INFINITY);
        } else if (s == 0) {
            tau = 0;
        } else {
            const Real x = p(kKs, k * s);
            if (x > 0) {
                // In logarithms, so that e^{b·y0} = e^-200 times e^x = e^20000 is no 0·∞:
                // ln((e^x − 1)/x) = x + ln(1 − e^{−x}) − ln x.
                const Real log_g = x + std::log(-std::expm1(-x)) - std::log(x);
                tau = e * grow * std::exp(by0 + std::log(s) + log_g);
            } else {
                const Real g = x == 0 ? 1.0L : std::expm1(x) / x;
                tau = e * std::exp(by0) * s * grow * g;
            }
        }
    }
    tau = p(kTau, tau);
    Real L;
    if (sigma == 0) {
        L = q == 0 ? L0 : L0 + q * tau;
    } else {
        const Real st = p(kSigmaTau, sigma * tau);
        const Real T = p(kT, std::exp(-st)), one_minus_t = p(kOneMinusT, -std::expm1(-st));
        L = L0 * T + p(kQOverSigma, q / sigma) * one_minus_t;
    }
    return {tau, L, by0};
}

// Σ over quantities of |Δv|/(u·|v|) for v = L (which = 0) or τ (which = 1).
Real condition(const Channel& c, int which) {
    const Reference r = reference(c, kNone);
    const Real v = which == 0 ? r.L : r.tau;
    if (v == 0 || !std::isfinite(v)) return 0;
    Real kappa = 0;
    for (int q = 0; q < kQuantities; ++q) {
        const Reference rq = reference(c, q);
        const Real vq = which == 0 ? rq.L : rq.tau;
        if (std::isfinite(vq)) kappa += std::fabs(vq - v) / (kU * std::fabs(v));
    }
    return kappa;
}

// ---- Checks -------------------------------------------------------------------------------------

std::string describe(const Channel& c) {
    char text[400];
    std::snprintf(text, sizeof text, "L0=%.9g sigma=%.9g q=%.9g s=%.9g y0=%.9g b=%.9g dy=%.9g height=%d",
                  double(c.L0), double(c.sigma), double(c.q), double(c.s), double(c.y0), double(c.b),
                  double(c.dy), int(c.height));
    return text;
}

[[noreturn]] void finding(const char* what, const Channel& c, double got, double want) {
    std::fprintf(stderr, "fuzz_fog: contract broken: %s: got %.9g, reference %.12g\n  %s\n", what, got, want,
                 describe(c).c_str());
    std::abort();
}

void checkRadiance(const char* what, const Channel& c, float L) {
    const Reference r = reference(c, kNone);
    if (std::isnan(L)) finding(what, c, L, double(r.L));
    if (r.L > Real(FLT_MAX)) {
        if (L != kInf) finding(what, c, L, double(r.L));
        return;
    }
    if (c.sigma == 0 && r.tau > Real(FLT_MAX) && L == kInf) return;
    const Real tol = 8 * kU * (condition(c, 0) + 1) * std::fabs(r.L) + 1e-6L;
    if (!(std::fabs(Real(L) - r.L) <= tol)) finding(what, c, L, double(r.L));
}

void checkDepth(const Channel& c, float tau) {
    const Reference r = reference(c, kNone);
    if (std::isnan(tau) || tau < 0) finding("opticalDepth", c, tau, double(r.tau));
    if (!c.height || std::fabs(r.by0) <= 87) {
        if (r.tau >= 1e-30L && r.tau <= Real(FLT_MAX) / 4) {
            const Real tol = 8 * kU * (condition(c, 1) + 1) * r.tau;
            if (!(std::fabs(Real(tau) - r.tau) <= tol)) finding("opticalDepth", c, tau, double(r.tau));
        }
    }
}

bool sameBits(float a, float b) {
    uint32_t x, y;
    std::memcpy(&x, &a, 4);
    std::memcpy(&y, &b, 4);
    return x == y || (std::isnan(a) && std::isnan(b));
}

void checkLane(const char* what, const Channel& c, float scalar, float wide) {
    if (!sameBits(scalar, wide)) {
        std::fprintf(stderr, "fuzz_fog: contract broken: %s: Float8 lane %.9g, scalar %.9g\n  %s\n", what,
                     double(wide), double(scalar), describe(c).c_str());
        std::abort();
    }
}

// ---- raster/media/ ------------------------------------------------------------------------------

[[noreturn]] void mediaFinding(const char* what, const std::string& inputs, double got, double want) {
    std::fprintf(stderr, "fuzz_fog: contract broken: %s: got %.9g, reference %.12g\n  %s\n", what, got, want,
                 inputs.c_str());
    std::abort();
}

std::string numbers(std::initializer_list<std::pair<const char*, double>> named) {
    std::string text;
    for (const auto& [name, value] : named) {
        char item[64];
        std::snprintf(item, sizeof item, "%s=%.9g ", name, value);
        text += item;
    }
    return text;
}

// |v − ref| within ulps·(1 + κ) of float's unit roundoff relative to ref, plus floor; +∞ where ref is
// past FLT_MAX (or within the tolerance of it); NaN never.
bool withinCondition(float v, Real ref, Real kappa, Real ulps, Real floor) {
    if (std::isnan(v) || std::isnan(ref)) return false;
    const Real tolerance = ulps * kU * (1 + kappa);
    if (std::fabs(ref) > Real(FLT_MAX))
        return std::isinf(v) || std::fabs(Real(v)) >= Real(FLT_MAX) * (1 - tolerance);
    if (std::isinf(v)) return std::fabs(ref) * (1 + tolerance) > Real(FLT_MAX);
    return std::fabs(Real(v) - ref) <= tolerance * std::fabs(ref) + floor;
}

// |v − ref| in ulps of float at ref (2⁻¹⁴⁹ below the normal range); 0 for +∞ where ref is past
// FLT_MAX; ∞ for NaN or for ∞ where ref is a float.
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

float anyFloat(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 3)) {
        case 0:
            return std::bit_cast<float>(in.ConsumeIntegral<uint32_t>() & 0xFF7FFFFFu);  // any finite float
        case 1:
            return in.ConsumeFloatingPointInRange<float>(-1.0f, 1.0f);
        default:
            return (in.ConsumeBool() ? 1.0f : -1.0f) * logUniform(in, 1e-30f, 100.0f);
    }
}

void checkExprel(FuzzedDataProvider& in) {
    Float8 x8;
    for (int i = 0; i < 8; ++i) x8.set(i, anyFloat(in));
    const Float8 psi8 = raster::media::psi(x8), phi8 = raster::media::phi(x8);
    for (int i = 0; i < 8; ++i) {
        const float x = x8[i], psi = raster::media::psi(x), phi = raster::media::phi(x);
        const std::string inputs = numbers({{"x", x}});
        if (!(ulpError(psi, raster::media::reference::psi(x)) <= 2))
            mediaFinding("psi", inputs, psi, double(raster::media::reference::psi(x)));
        if (!(ulpError(phi, raster::media::reference::phi(x)) <= 2))
            mediaFinding("phi", inputs, phi, double(raster::media::reference::phi(x)));
        if (!sameBits(psi, psi8[i]) || !sameBits(phi, phi8[i]))
            mediaFinding("psi/phi Float8 lane", inputs, psi8[i], psi);
    }
}

// The homogeneous closed form and the height fog's optical depth and radiance through media/.
void checkClosedForms(FuzzedDataProvider& in, const Medium& m) {
    using raster::media::reference::relativeCondition;
    namespace ref = raster::media::reference;
    const float b = m.fog.b, y0 = m.y0;
    Float8 L08, mu8, q8, s8, dy8;
    float L0[8], mu[8], q[8], s[8], dy[8];
    for (int i = 0; i < 8; ++i) {
        L0[i] = in.ConsumeFloatingPointInRange<float>(0.0f, 1.0f), mu[i] = sigmaOrQ(in), q[i] = sigmaOrQ(in);
        s[i] = distance(in), dy[i] = directionY(in);
        L08.set(i, L0[i]), mu8.set(i, mu[i]), q8.set(i, q[i]), s8.set(i, s[i]), dy8.set(i, dy[i]);
    }
    const Float8 constant8 = raster::media::radiance(L08, mu8, q8, s8);
    const Float8 tau8 = raster::media::heightFogOpticalDepth(Float8(b), Float8(y0), dy8, s8);
    for (int i = 0; i < 8; ++i) {
        const std::string inputs = numbers(
            {{"L0", L0[i]}, {"mu", mu[i]}, {"q", q[i]}, {"s", s[i]}, {"b", b}, {"y0", y0}, {"dy", dy[i]}});
        const float L = raster::media::radiance(L0[i], mu[i], q[i], s[i]);
        auto constant = [](const std::array<Real, 4>& x) { return ref::radiance(x[0], x[1], x[2], x[3]); };
        const std::array<Real, 4> c_in = {L0[i], mu[i], q[i], s[i]};
        if (!withinCondition(L, constant(c_in), relativeCondition(constant, c_in), 8,
                             0x1p-126L * (1 + Real(q[i]))))
            mediaFinding("media::radiance", inputs, L, double(constant(c_in)));
        const float T = raster::media::transmittance(mu[i], s[i]);
        if (!(T >= 0 && T <= 1)) mediaFinding("media::transmittance", inputs, T, 0);
        const float tau = raster::media::heightFogOpticalDepth(b, y0, dy[i], s[i]);
        auto depth = [](const std::array<Real, 4>& x) {
            return ref::heightFogOpticalDepth(x[0], x[1], x[2], x[3]);
        };
        const std::array<Real, 4> d_in = {b, y0, dy[i], s[i]};
        if (!withinCondition(tau, depth(d_in), relativeCondition(depth, d_in), 8, 0x1p-126L))
            mediaFinding("media::heightFogOpticalDepth", inputs, tau, double(depth(d_in)));
        const float Lh = raster::media::radiance(L0[i], mu[i], q[i], tau);
        auto height = [](const std::array<Real, 7>& x) {
            return ref::heightFogRadiance(x[0], x[1], x[2], x[3], x[4], x[5], x[6]);
        };
        const std::array<Real, 7> h_in = {L0[i], mu[i], q[i], b, y0, dy[i], s[i]};
        // τ is a float: past FLT_MAX it is +∞, and L the limit at τ = ∞ (height_fog.hpp).
        if (depth(d_in) > Real(FLT_MAX)) {
            const Real limit = ref::radiance(L0[i], mu[i], q[i], INFINITY);
            if (std::isinf(tau) && !withinCondition(Lh, limit, 0, 8, 0x1p-126L))
                mediaFinding("media::radiance of the height fog at τ = ∞", inputs, Lh, double(limit));
        } else if (!withinCondition(Lh, height(h_in), relativeCondition(height, h_in), 8,
                                    0x1p-126L * (1 + Real(q[i])))) {
            mediaFinding("media::radiance of the height fog", inputs, Lh, double(height(h_in)));
        }
        if (!sameBits(L, constant8[i]) || !sameBits(tau, tau8[i]))
            mediaFinding("closed forms Float8 lane", inputs, L, constant8[i]);
    }
}

float anisotropy(FuzzedDataProvider& in) {
    switch (in.ConsumeIntegralInRange<int>(0, 5)) {
        case 0:
            return in.ConsumeBool() ? 1.0f : -1.0f;
        case 1:
            return (in.ConsumeBool() ? 1.0f : -1.0f) * (1.0f - logUniform(in, 0x1p-24f, 1e-2f));
        case 2:
            return (in.ConsumeBool() ? 1.0f : -1.0f) * logUniform(in, 1e-30f, 1e-2f);
        case 3:
            return 0.0f;
        default:
            return in.ConsumeFloatingPointInRange<float>(-1.0f, 1.0f);
    }
}

// The Henyey–Greenstein density and CDF in long double (the CDF without its cancellation at g → 0:
// (1 − g)(1 + c)/(√B·(1 + g + √B)), B = 1 + g² − 2g·c as a sum of non-negative terms).
Real hgDensity(Real g, Real c) {
    const Real base = g >= 0 ? (1 - g) * (1 - g) + 2 * g * (1 - c) : (1 + g) * (1 + g) - 2 * g * (1 + c);
    return (1 - g) * (1 + g) / (4 * 3.14159265358979323846264338327950288L * base * std::sqrt(base));
}
Real hgCdf(Real g, Real c) {
    const Real base = g >= 0 ? (1 - g) * (1 - g) + 2 * g * (1 - c) : (1 + g) * (1 + g) - 2 * g * (1 + c);
    const Real root = std::sqrt(base);
    return (1 - g) * (1 + c) / (root * (1 + g + root));
}

void checkPhaseFunctions(FuzzedDataProvider& in) {
    using raster::media::reference::relativeCondition;
    Float8 g8, c8, u8;
    for (int i = 0; i < 8; ++i) {
        g8.set(i, anisotropy(in));
        c8.set(i, in.ConsumeBool()
                      ? (in.ConsumeBool() ? 1.0f : -1.0f) * (1.0f - logUniform(in, 0x1p-24f, 1.0f))
                      : in.ConsumeFloatingPointInRange<float>(-1.0f, 1.0f));
        u8.set(i, in.ConsumeBool() ? float(in.ConsumeIntegralInRange<uint32_t>(0, (1u << 24) - 1)) * 0x1p-24f
                                   : in.ConsumeProbability<float>());
    }
    const Float8 hg8 = raster::media::henyeyGreenstein(g8, c8),
                 sample8 = raster::media::sampleHenyeyGreenstein(g8, u8);
    const Float8 rayleigh8 = raster::media::rayleigh(c8);
    for (int i = 0; i < 8; ++i) {
        const float g = g8[i], c = c8[i], u = u8[i];
        const std::string inputs = numbers({{"g", g}, {"cos", c}, {"u", u}});
        const float p = raster::media::henyeyGreenstein(g, c);
        if (!(p > 0) || std::isinf(p)) mediaFinding("henyeyGreenstein", inputs, p, double(hgDensity(g, c)));
        if (std::fabs(g) < 1) {
            auto density = [](const std::array<Real, 2>& x) { return hgDensity(x[0], x[1]); };
            const std::array<Real, 2> p_in = {g, c};
            if (!withinCondition(p, density(p_in), relativeCondition(density, p_in), 16, 0))
                mediaFinding("henyeyGreenstein", inputs, p, double(density(p_in)));
        }
        const float r = raster::media::rayleigh(c);
        const Real r_ref = 3 / (16 * 3.14159265358979323846264338327950288L) * (1 + Real(c) * c);
        if (!withinCondition(r, r_ref, 0, 4, 0)) mediaFinding("rayleigh", inputs, r, double(r_ref));
        const float cos_theta = raster::media::sampleHenyeyGreenstein(g, u);
        if (!(std::fabs(cos_theta) <= 1)) mediaFinding("sampleHenyeyGreenstein range", inputs, cos_theta, 0);
        if (std::fabs(g) < 1) {
            // An ulp of 1 in cos θ moves the CDF by 2π·p(cos θ) of it: 8 of those, and 8 ulp of u.
            const Real slack =
                8 * kU * (2 * 3.14159265358979323846264338327950288L * hgDensity(g, cos_theta) + 1);
            const Real cdf = hgCdf(g, cos_theta);
            if (!(std::fabs(cdf - u) <= slack))
                mediaFinding("sampleHenyeyGreenstein inverts the CDF", inputs, double(cdf), u);
        }
        if (!sameBits(p, hg8[i]) || !sameBits(cos_theta, sample8[i]) || !sameBits(r, rayleigh8[i]))
            mediaFinding("phase functions Float8 lane", inputs, hg8[i], p);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    FuzzedDataProvider in(data, size);
    const Medium m = medium(in);
    const FogMedium& fog = m.fog;
    const glm::vec3 eye(0.0f, m.y0, 0.0f);

    // Eight view rays: surface radiance, distance, direction.
    glm::vec3 L0[8];
    float s[8], dy[8];
    Float8 s8, dy8;
    glm::vec<3, Float8> L08;
    for (int i = 0; i < 8; ++i) {
        for (int c = 0; c < 3; ++c) L0[i][c] = in.ConsumeFloatingPointInRange<float>(0.0f, 1.0f);
        s[i] = distance(in);
        dy[i] = directionY(in);
        s8.set(i, s[i]);
        dy8.set(i, dy[i]);
        for (int c = 0; c < 3; ++c) L08[c].set(i, L0[i][c]);
    }
    // The Float8 path as PsFog takes it (finite s), and to infinity as PsSky does.
    const Float8 tau_finite = fog.opticalDepth<Float8>(m.y0, dy8, s8);
    const Float8 tau_infinite = fog.opticalDepthToInfinity<Float8>(m.y0, dy8);
    Float8 tau8;
    for (int i = 0; i < 8; ++i) tau8.set(i, std::isinf(s[i]) ? tau_infinite[i] : tau_finite[i]);
    const glm::vec<3, Float8> L8 = fog.applyOpticalDepth(L08, tau8);

    for (int i = 0; i < 8; ++i) {
        const float dx = std::sqrt(std::max(0.0f, 1.0f - dy[i] * dy[i]));
        const glm::vec3 dir(dx, dy[i], 0.0f);
        const glm::vec3 L = fog.apply(L0[i], eye, dir, s[i]);
        const float tau = fog.opticalDepth(m.y0, dy[i], s[i]);
        for (int c = 0; c < 3; ++c) {
            const Channel ch{L0[i][c], fog.sigma[c], fog.q[c], s[i], m.y0, fog.b, dy[i], fog.height};
            if (c == 0) {
                checkDepth(ch, tau);
                checkLane("opticalDepth", ch, tau, tau8[i]);
            }
            checkRadiance("apply", ch, L[c]);
            checkLane("applyOpticalDepth", ch, L[c], L8[c][i]);
        }
    }

    // The background (PsSky): L0 = 0 to s = ∞ along a ray of any length, normalised in the shader.
    PsSky sky;
    sky.fog = fog;
    sky.eye = eye;
    SkyVertexT<Float8> wide;
    glm::vec3 rays[8];
    for (int i = 0; i < 8; ++i) {
        const float y = directionY(in);
        const float scale = logUniform(in, 1e-3f, 1e3f);
        const float azimuth = in.ConsumeFloatingPointInRange<float>(0.0f, 6.2831853f);
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        rays[i] = glm::vec3(r * std::cos(azimuth), y, r * std::sin(azimuth)) * scale;
        if (rays[i] == glm::vec3(0.0f)) rays[i] = glm::vec3(0.0f, scale, 0.0f);
        for (int c = 0; c < 3; ++c) wide.ray[c].set(i, rays[i][c]);
        for (int c = 0; c < 4; ++c) wide.position[c].set(i, 0.0f);
    }
    const glm::vec<4, Float8> sky8 = sky(wide);
    for (int i = 0; i < 8; ++i) {
        const glm::vec4 L = sky(SkyVertexT<float>{glm::vec4(0.0f), rays[i]});
        const Real len = std::sqrt(Real(rays[i].x) * rays[i].x + Real(rays[i].y) * rays[i].y +
                                   Real(rays[i].z) * rays[i].z);
        for (int c = 0; c < 3; ++c) {
            const Channel ch{0.0L,  fog.sigma[c],          fog.q[c],  Real(INFINITY), m.y0,
                             fog.b, Real(rays[i].y) / len, fog.height};
            checkRadiance("PsSky", ch, L[c]);
            checkLane("PsSky", ch, L[c], sky8[c][i]);
        }
    }

    // raster/media/, from the bytes left (the inputs before these bytes decode as they always did).
    checkExprel(in);
    checkClosedForms(in, m);
    checkPhaseFunctions(in);
    return 0;
}
