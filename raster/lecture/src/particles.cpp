#include "raster/particles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>

#include "raster/check.hpp"
#include "raster/simd/ops.hpp"
#include "raster/thread_pool.hpp"

namespace raster {

namespace {

// ---- Checks -----------------------------------------------------------------------------------------

std::string formatValue(double v) {
    char text[48];
    std::snprintf(text, sizeof text, "%.9g", v);
    return text;
}

std::string formatVec(glm::vec3 v) {
    return "(" + formatValue(v.x) + ", " + formatValue(v.y) + ", " + formatValue(v.z) + ")";
}

bool isFinite(float v) { return std::isfinite(v); }
bool isFinite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void requireFinite(float v, const std::string& name, const char* unit) {
    RASTER_REQUIRE(isFinite(v), InvalidArgument,
                   name + " is " + formatValue(v) + ": must be a finite number (" + unit + ")");
}
void requireFinite(glm::vec3 v, const std::string& name, const char* unit) {
    RASTER_REQUIRE(isFinite(v), InvalidArgument,
                   name + " is " + formatVec(v) + ": must be finite (" + unit + ")");
}
// Finite and ≥ lo; `rule` says so in words ("≥ 0", "≥ speedMin").
void requireAtLeast(float v, float lo, const std::string& name, const char* rule, const char* unit) {
    RASTER_REQUIRE(isFinite(v) && v >= lo, InvalidArgument,
                   name + " is " + formatValue(v) + ": must be finite and " + rule + " (" + unit + ")");
}
void requirePositive(float v, const std::string& name, const char* unit) {
    RASTER_REQUIRE(isFinite(v) && v > 0.0f, InvalidArgument,
                   name + " is " + formatValue(v) + ": must be finite and > 0 (" + unit + ")");
}
void requireDirection(glm::vec3 v, const std::string& name) {
    RASTER_REQUIRE(isFinite(v) && (v.x != 0.0f || v.y != 0.0f || v.z != 0.0f), InvalidArgument,
                   name + " is " + formatVec(v) + ": must be a finite nonzero vector (a direction)");
}

// The unit vector along v (finite, nonzero), normalised in double so that tiny or huge lengths
// neither underflow nor overflow.
glm::vec3 unit(glm::vec3 v) { return glm::vec3(glm::normalize(glm::dvec3(v))); }

// Two unit vectors that make an orthonormal basis with the unit vector n (Duff et al. 2017,
// "Building an orthonormal basis, revisited": no branch on a near-zero component).
void orthonormalBasis(glm::vec3 n, glm::vec3& b1, glm::vec3& b2) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

// ---- Counter-based random numbers -------------------------------------------------------------------
// SplitMix64's finaliser (Steele, Lea, Flood 2014), a bijection of 64-bit words whose output bits
// each depend on all input bits: hashing a counter with it gives independent-looking numbers
// without any sequential state, so any thread may draw particle n's numbers in any order.
constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ull;

uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Which of a particle's random numbers.
enum RandomDim : uint32_t {
    kRandLifespan, kRandSize, kRandSpeed, kRandCone, kRandAround, kRandPos0, kRandPos1, kRandPos2, kRandDims
};

// A uniform float in [0, 1) (24 bits, exact) for (emitter key, emission index, dim).
float uniform01(uint64_t emitter_key, uint64_t index, uint32_t dim) {
    const uint64_t h = mix64(emitter_key ^ mix64(index * kRandDims + dim));
    return float(h >> 40) * 0x1p-24f;
}

float lerp(float lo, float hi, float u) { return lo + (hi - lo) * u; }

// ---- Lanes: one source for scalar and eight-wide code -----------------------------------------------
// The effectors and the noise are written once, as templates over a "lane" type F: float, double, or
// eight floats (a GCC/Clang vector). Every operation on an eight-float vector is the IEEE operation
// on each lane, in the same order as the scalar code, so a particle gets the same bits whether it is
// in a group of eight or in a block's scalar tail (and the public scalar curlNoise is the one the
// simulation runs). Explicit vectors, because the compiler will not vectorise the selects of these
// loops by itself under the default -ftrapping-math (it may not speculate a floating-point operation
// that sits in one arm of a condition).
// The helpers are internal and inlined, so no vector crosses an ABI boundary: GCC's warning that
// 32-byte vectors are passed differently with and without AVX (a build without -march=native) does
// not apply.
#if defined(__GNUC__)  // GCC and Clang
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
using F8 = float __attribute__((vector_size(32)));
using I8 = int32_t __attribute__((vector_size(32)));
using U8 = uint32_t __attribute__((vector_size(32)));
constexpr uint32_t kLanes = 8;

template <class F>
struct Lane {
    using E = F;         // the element type
    using U = uint32_t;  // lattice coordinates and hashes
};
template <>
struct Lane<F8> {
    using E = float;
    using U = U8;
};

template <class F>
[[gnu::always_inline]] inline F splat(typename Lane<F>::E x) {
    if constexpr (std::is_same_v<F, F8>)
        return F8{x, x, x, x, x, x, x, x};
    else
        return x;
}
template <class F>
[[gnu::always_inline]] inline F load(const float* p) {
    F v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
template <class F>
[[gnu::always_inline]] inline void store(float* p, F v) {
    std::memcpy(p, &v, sizeof v);
}
// m ? a : b, lane by lane for vectors (m a comparison's mask).
template <class M, class F>
[[gnu::always_inline]] inline F select(M m, F a, F b) {
    return m ? a : b;
}

[[gnu::always_inline]] inline float floorLane(float x) { return std::floor(x); }
[[gnu::always_inline]] inline double floorLane(double x) { return std::floor(x); }
[[gnu::always_inline]] inline F8 floorLane(F8 x) { return simd::floor(x); }
[[gnu::always_inline]] inline float sqrtLane(float x) { return std::sqrt(x); }
[[gnu::always_inline]] inline F8 sqrtLane(F8 x) { return simd::sqrt(x); }
// A lattice coordinate (an integer-valued float within ±2^30) as 32 bits, wrapping arithmetic after.
[[gnu::always_inline]] inline uint32_t toLattice(float f) { return uint32_t(int32_t(f)); }
[[gnu::always_inline]] inline uint32_t toLattice(double f) { return uint32_t(int32_t(f)); }
[[gnu::always_inline]] inline U8 toLattice(F8 f) { return U8(__builtin_convertvector(f, I8)); }

// Runs body<F8>(i) for each whole group of eight of [0, n), then body<float>(i) for the rest.
template <class Body>
[[gnu::always_inline]] inline void forLanes(uint32_t n, Body&& body) {
    uint32_t i = 0;
    for (; i + kLanes <= n; i += kLanes) body.template operator()<F8>(i);
    for (; i < n; ++i) body.template operator()<float>(i);
}

// ---- Gradient noise ---------------------------------------------------------------------------------

// The lattice cell of p along one axis: the cell's integer corner (wrapped to 32 bits) and p's
// place in it, in [0, 1]. For |p| ≥ 2^24 (floats) every p is an integer and its place is 0.
template <class F>
[[gnu::always_inline]] inline F latticeCell(F p, typename Lane<F>::U& corner) {
    using E = typename Lane<F>::E;
    constexpr E kMax = E(1u << 30);
    F f = floorLane(p);
    F place = p - f;  // exact; 1 only just below a negative integer
    place = select((place >= E(0)) & (place <= E(1)), place, splat<F>(E(0)));  // inf − inf, NaN: 0
    f = select(f > kMax, splat<F>(kMax), f);
    f = select(f > -kMax, f, splat<F>(-kMax));  // NaN fails both tests and becomes −2^30
    corner = toLattice(f);
    return place;
}

// A 32-bit hash of a lattice point and a seed: a multiply-xor combination (Teschner et al. 2003)
// and the "lowbias32" finaliser (C. Wellons), all in unsigned (wrapping, defined) arithmetic.
template <class U>
[[gnu::always_inline]] inline U hashLattice(U x, U y, U z, uint32_t seed) {
    U h = (x * 0x8da6b343u) ^ (y * 0xd8163841u) ^ (z * 0xcb1ab31fu) ^ seed;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return h;
}

template <class F>
struct Vec3 {
    F x, y, z;
};

// One corner's gradient, Perlin's (2002) sixteen: the twelve edge midpoints of the cube, four of them
// twice, picked by the hash's top four bits (u along x for h < 8, else y; v along y for h < 4, x for
// 12 and 14, else z; their signs bits 0 and 1).
template <class F, class U>
[[gnu::always_inline]] inline Vec3<F> cornerGradient(U hash) {
    using E = typename Lane<F>::E;
    const U h = hash >> 28;
    const F one = splat<F>(E(1)), minus = splat<F>(E(-1)), zero = splat<F>(E(0));
    const F su = select((h & 1u) != 0u, minus, one), sv = select((h & 2u) != 0u, minus, one);
    const auto u_is_x = h < 8u;
    const auto v_is_y = h < 4u;
    const auto v_is_x = (h == 12u) | (h == 14u);
    return {select(u_is_x, su, zero) + select(v_is_x, sv, zero),
            select(u_is_x, zero, su) + select(v_is_y, sv, zero),
            select(v_is_y | v_is_x, zero, sv)};
}

// p's cell and its quintic fade weights u = 6f⁵ − 15f⁴ + 10f³ (C2: u' and u'' vanish at 0 and 1),
// their products, and their derivatives 30f²(f − 1)².
template <class F>
struct NoiseCell {
    typename Lane<F>::U ix, iy, iz;
    Vec3<F> f, u, du;
    F uxy, uyz, uzx, uxyz;
};

template <class F>
[[gnu::always_inline]] inline F fade(F f) {
    using E = typename Lane<F>::E;
    return f * f * f * (f * (f * E(6) - E(15)) + E(10));
}
template <class F>
[[gnu::always_inline]] inline F fadeDerivative(F f) {
    using E = typename Lane<F>::E;
    return E(30) * f * f * (f * (f - E(2)) + E(1));
}

template <class F>
[[gnu::always_inline]] inline NoiseCell<F> noiseCell(F px, F py, F pz) {
    NoiseCell<F> c;
    c.f = {latticeCell(px, c.ix), latticeCell(py, c.iy), latticeCell(pz, c.iz)};
    c.u = {fade(c.f.x), fade(c.f.y), fade(c.f.z)};
    c.du = {fadeDerivative(c.f.x), fadeDerivative(c.f.y), fadeDerivative(c.f.z)};
    c.uxy = c.u.x * c.u.y, c.uyz = c.u.y * c.u.z, c.uzx = c.u.z * c.u.x, c.uxyz = c.uxy * c.u.z;
    return c;
}

// The trilinear blend of eight corner values a..h (corners 000, 100, 010, 110, 001, 101, 011, 111)
// with the fade weights, as Quilez's polynomial in them ("gradient noise derivatives", 2017).
template <class F>
[[gnu::always_inline]] inline F blendCorners(const NoiseCell<F>& c, F a, F b, F cc, F d, F e, F f, F g, F h) {
    return a + c.u.x * (b - a) + c.u.y * (cc - a) + c.u.z * (e - a) + c.uxy * (a - b - cc + d) +
           c.uyz * (a - cc - e + g) + c.uzx * (a - b - e + f) + c.uxyz * (-a + b + cc - d + e - f - g + h);
}

template <class F>
struct NoiseLanes {
    F value;
    Vec3<F> gradient;
};

// The noise of the field whose lattice is offset by (ox, oy, oz), in cell c: value and gradient.
// Corner k contributes g_k·(f − k); the gradient is the blend of the g_k plus the fade weights'
// derivatives times the blend's differences.
template <class F>
[[gnu::always_inline]] inline NoiseLanes<F> noiseInCell(const NoiseCell<F>& c, uint32_t seed, uint32_t ox,
                                                        uint32_t oy, uint32_t oz) {
    using E = typename Lane<F>::E;
    using U = typename Lane<F>::U;
    const U x0 = c.ix + ox, y0 = c.iy + oy, z0 = c.iz + oz, x1 = x0 + 1u, y1 = y0 + 1u, z1 = z0 + 1u;
    auto grad = [seed](U x, U y, U z) { return cornerGradient<F>(hashLattice(x, y, z, seed)); };
    const Vec3<F> ga = grad(x0, y0, z0), gb = grad(x1, y0, z0), gc = grad(x0, y1, z0), gd = grad(x1, y1, z0);
    const Vec3<F> ge = grad(x0, y0, z1), gf = grad(x1, y0, z1), gg = grad(x0, y1, z1), gh = grad(x1, y1, z1);
    const F fx = c.f.x, fy = c.f.y, fz = c.f.z, hx = fx - E(1), hy = fy - E(1), hz = fz - E(1);
    auto dot = [](const Vec3<F>& g, F x, F y, F z) { return g.x * x + g.y * y + g.z * z; };
    const F va = dot(ga, fx, fy, fz), vb = dot(gb, hx, fy, fz), vc = dot(gc, fx, hy, fz);
    const F vd = dot(gd, hx, hy, fz), ve = dot(ge, fx, fy, hz), vf = dot(gf, hx, fy, hz);
    const F vg = dot(gg, fx, hy, hz), vh = dot(gh, hx, hy, hz);
    const F k1 = vb - va, k2 = vc - va, k3 = ve - va, k4 = va - vb - vc + vd, k5 = va - vc - ve + vg;
    const F k6 = va - vb - ve + vf, k7 = -va + vb + vc - vd + ve - vf - vg + vh;
    NoiseLanes<F> s;
    s.value = blendCorners(c, va, vb, vc, vd, ve, vf, vg, vh);
    s.gradient.x = blendCorners(c, ga.x, gb.x, gc.x, gd.x, ge.x, gf.x, gg.x, gh.x) +
                   c.du.x * (k1 + c.u.y * k4 + c.u.z * k6 + c.uyz * k7);
    s.gradient.y = blendCorners(c, ga.y, gb.y, gc.y, gd.y, ge.y, gf.y, gg.y, gh.y) +
                   c.du.y * (k2 + c.u.z * k5 + c.u.x * k4 + c.uzx * k7);
    s.gradient.z = blendCorners(c, ga.z, gb.z, gc.z, gd.z, ge.z, gf.z, gg.z, gh.z) +
                   c.du.z * (k3 + c.u.x * k6 + c.u.y * k5 + c.uxy * k7);
    return s;
}

// The lattice offsets of ψ's second and third components (arbitrary, far apart, not multiples of
// each other): N(p + o) for an integer o is a field independent of N(p) that shares p's cell.
constexpr uint32_t kOffset1[3] = {1013u, uint32_t(-307), 571u};
constexpr uint32_t kOffset2[3] = {uint32_t(-719), 911u, uint32_t(-1229)};
// 1 / the rms length of the raw curl over space: 1.726 over 10⁶ random points for each of three
// seeds (its largest length there was 5.16, so the normalized field peaks near 3). A test checks
// that the rms stays within a few per cent of 1.
constexpr double kCurlScale = 1.0 / 1.726;

template <class F>
[[gnu::always_inline]] inline Vec3<F> curlLanes(F px, F py, F pz, uint32_t seed) {
    using E = typename Lane<F>::E;
    const NoiseCell<F> c = noiseCell(px, py, pz);
    const Vec3<F> d1 = noiseInCell(c, seed, 0u, 0u, 0u).gradient;
    const Vec3<F> d2 = noiseInCell(c, seed, kOffset1[0], kOffset1[1], kOffset1[2]).gradient;
    const Vec3<F> d3 = noiseInCell(c, seed, kOffset2[0], kOffset2[1], kOffset2[2]).gradient;
    // curl ψ = (∂ψ3/∂y − ∂ψ2/∂z, ∂ψ1/∂z − ∂ψ3/∂x, ∂ψ2/∂x − ∂ψ1/∂y)
    const E scale = E(kCurlScale);
    return {(d3.y - d2.z) * scale, (d1.z - d3.x) * scale, (d2.x - d1.y) * scale};
}

}  // namespace

template <class T>
NoiseSample<T> gradientNoise(glm::vec<3, T> p, uint32_t seed) {
    const NoiseLanes<T> n = noiseInCell(noiseCell(p.x, p.y, p.z), seed, 0u, 0u, 0u);
    return {n.value, {n.gradient.x, n.gradient.y, n.gradient.z}};
}

template <class T>
glm::vec<3, T> curlNoise(glm::vec<3, T> p, uint32_t seed) {
    const Vec3<T> u = curlLanes(p.x, p.y, p.z, seed);
    return {u.x, u.y, u.z};
}

template NoiseSample<float> gradientNoise(glm::vec<3, float>, uint32_t);
template NoiseSample<double> gradientNoise(glm::vec<3, double>, uint32_t);
template glm::vec<3, float> curlNoise(glm::vec<3, float>, uint32_t);
template glm::vec<3, double> curlNoise(glm::vec<3, double>, uint32_t);

// ---- Curves -----------------------------------------------------------------------------------------

template <class T>
PiecewiseLinear<T>::PiecewiseLinear(std::vector<Key> keys) : keys_(std::move(keys)) {
    RASTER_REQUIRE(!keys_.empty(), InvalidArgument, "a curve needs at least one key");
    for (size_t i = 0; i < keys_.size(); ++i) {
        const std::string name = "curve keys[" + std::to_string(i) + "]";
        RASTER_REQUIRE(isFinite(keys_[i].t) && keys_[i].t >= 0.0f && keys_[i].t <= 1.0f, InvalidArgument,
                       name + ".t is " + formatValue(keys_[i].t) + ": must be in [0, 1] (normalized age)");
        RASTER_REQUIRE(isFinite(keys_[i].value), InvalidArgument, name + ".value must be finite");
        RASTER_REQUIRE(i == 0 || keys_[i].t > keys_[i - 1].t, InvalidArgument,
                       name + ".t is " + formatValue(keys_[i].t) + ": must be greater than the previous key's " +
                           formatValue(i ? keys_[i - 1].t : 0.0f));
    }
}

template <class T>
T PiecewiseLinear<T>::operator()(float t) const {
    if (!(t > keys_.front().t)) return keys_.front().value;  // NaN too
    if (t >= keys_.back().t) return keys_.back().value;
    // The first key after t; t lies in [previous key, that key).
    const auto next = std::upper_bound(keys_.begin() + 1, keys_.end(), t,
                                       [](float x, const Key& key) { return x < key.t; });
    const Key& a = next[-1];
    const Key& b = *next;
    const float s = (t - a.t) / (b.t - a.t);
    return a.value * (1.0f - s) + b.value * s;
}

template class PiecewiseLinear<float>;
template class PiecewiseLinear<glm::vec3>;

// ---- Emitters ---------------------------------------------------------------------------------------

Emitter Emitter::point(glm::vec3 position) {
    Emitter e;
    e.shape = EmitterShape::Point;
    e.centre = position;
    return e;
}

Emitter Emitter::line(glm::vec3 start, glm::vec3 end) {
    Emitter e;
    e.shape = EmitterShape::Line;
    e.centre = start;
    e.end = end;
    return e;
}

Emitter Emitter::disc(glm::vec3 centre, glm::vec3 normal, float radius) {
    Emitter e;
    e.shape = EmitterShape::Disc;
    e.centre = centre;
    e.normal = normal;
    e.radius = radius;
    return e;
}

Emitter Emitter::box(glm::vec3 centre, glm::vec3 halfExtents) {
    Emitter e;
    e.shape = EmitterShape::Box;
    e.centre = centre;
    e.halfExtents = halfExtents;
    return e;
}

Emitter Emitter::sphere(glm::vec3 centre, float radius) {
    Emitter e;
    e.shape = EmitterShape::Sphere;
    e.centre = centre;
    e.radius = radius;
    return e;
}

namespace {

void validateEmitter(const Emitter& e, const std::string& name) {
    RASTER_REQUIRE(uint8_t(e.shape) <= uint8_t(EmitterShape::Sphere), InvalidArgument,
                   name + ".shape is " + std::to_string(int(e.shape)) + ": not an EmitterShape");
    requireFinite(e.centre, name + ".centre", "world units");
    requireFinite(e.end, name + ".end", "world units");
    if (e.shape == EmitterShape::Disc) requireDirection(e.normal, name + ".normal");
    requireAtLeast(e.radius, 0.0f, name + ".radius", ">= 0", "world units");
    for (int k = 0; k < 3; ++k)
        requireAtLeast(e.halfExtents[k], 0.0f, name + ".halfExtents." + "xyz"[k], ">= 0", "world units");
    requireAtLeast(e.rate, 0.0f, name + ".rate", ">= 0", "particles per second");
    for (size_t i = 0; i < e.bursts.size(); ++i) {
        const std::string burst = name + ".bursts[" + std::to_string(i) + "]";
        requireAtLeast(e.bursts[i].time, 0.0f, burst + ".time", ">= 0", "seconds");
        requireAtLeast(e.bursts[i].interval, 0.0f, burst + ".interval", ">= 0", "seconds");
    }
    requireDirection(e.velocity.direction, name + ".velocity.direction");
    RASTER_REQUIRE(isFinite(e.velocity.halfAngle) && e.velocity.halfAngle >= 0.0f &&
                       e.velocity.halfAngle <= std::numbers::pi_v<float>,
                   InvalidArgument,
                   name + ".velocity.halfAngle is " + formatValue(e.velocity.halfAngle) +
                       ": must be in [0, pi] (radians)");
    requireAtLeast(e.velocity.speedMin, 0.0f, name + ".velocity.speedMin", ">= 0", "world units per second");
    requireAtLeast(e.velocity.speedMax, e.velocity.speedMin, name + ".velocity.speedMax", ">= speedMin",
                   "world units per second");
    requirePositive(e.lifespanMin, name + ".lifespanMin", "seconds");
    requireAtLeast(e.lifespanMax, e.lifespanMin, name + ".lifespanMax", ">= lifespanMin", "seconds");
    requireAtLeast(e.sizeMin, 0.0f, name + ".sizeMin", ">= 0", "world units");
    requireAtLeast(e.sizeMax, e.sizeMin, name + ".sizeMax", ">= sizeMin", "world units");
}

struct EffectorValidator {
    std::string name;
    void operator()(const Gravity& g) const {
        requireFinite(g.acceleration, name + "(Gravity).acceleration", "world units/s^2");
    }
    void operator()(const Wind& w) const {
        requireFinite(w.velocity, name + "(Wind).velocity", "world units/s");
        requireAtLeast(w.drag, 0.0f, name + "(Wind).drag", ">= 0", "1/s");
    }
    void operator()(const Buoyancy& b) const {
        requireDirection(b.up, name + "(Buoyancy).up");
        requireFinite(b.acceleration, name + "(Buoyancy).acceleration", "world units/s^2");
        requireFinite(b.endScale, name + "(Buoyancy).endScale", "a factor");
    }
    void operator()(const Drag& d) const {
        requireAtLeast(d.coefficient, 0.0f, name + "(Drag).coefficient", ">= 0", "1/s");
    }
    void operator()(const Attractor& a) const {
        requireFinite(a.position, name + "(Attractor).position", "world units");
        requireFinite(a.strength, name + "(Attractor).strength", "world units^3/s^2");
        requirePositive(a.softening, name + "(Attractor).softening", "world units");
    }
    void operator()(const Vortex& v) const {
        requireFinite(v.centre, name + "(Vortex).centre", "world units");
        requireDirection(v.axis, name + "(Vortex).axis");
        requireFinite(v.angularSpeed, name + "(Vortex).angularSpeed", "radians per second");
        requirePositive(v.radius, name + "(Vortex).radius", "world units");
        requireAtLeast(v.drag, 0.0f, name + "(Vortex).drag", ">= 0", "1/s");
    }
    void operator()(const Turbulence& t) const {
        requireFinite(t.amplitude, name + "(Turbulence).amplitude", "world units/s");
        requirePositive(t.frequency, name + "(Turbulence).frequency", "1/world units");
        requireFinite(t.drift, name + "(Turbulence).drift", "noise units/s");
        requireAtLeast(t.response, 0.0f, name + "(Turbulence).response", ">= 0", "1/s");
    }
};

void validateEffectors(const std::vector<Effector>& effectors) {
    for (size_t i = 0; i < effectors.size(); ++i)
        std::visit(EffectorValidator{"effectors[" + std::to_string(i) + "] "}, effectors[i]);
}

void validateDesc(const ParticleSystemDesc& d) {
    RASTER_REQUIRE(d.maxParticles > 0, InvalidArgument, "maxParticles is 0: must be > 0 (slots)");
    requirePositive(d.timeStep, "timeStep", "seconds");
    RASTER_REQUIRE(d.maxStepsPerAdvance > 0, InvalidArgument, "maxStepsPerAdvance is 0: must be > 0 (steps)");
    RASTER_REQUIRE(d.emitters.size() <= 0xFFFF, InvalidArgument,
                   "emitters has " + std::to_string(d.emitters.size()) + " entries: at most 65535");
    for (size_t i = 0; i < d.emitters.size(); ++i)
        validateEmitter(d.emitters[i], "emitters[" + std::to_string(i) + "]");
    validateEffectors(d.effectors);
}

// ---- Birth: where and how fast --------------------------------------------------------------------

glm::vec3 samplePosition(const Emitter& e, float u0, float u1, float u2) {
    constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
    switch (e.shape) {
        case EmitterShape::Point: return e.centre;
        case EmitterShape::Line: return e.centre + (e.end - e.centre) * u0;
        case EmitterShape::Disc: {
            glm::vec3 b1, b2;
            orthonormalBasis(unit(e.normal), b1, b2);
            const float r = e.radius * std::sqrt(u0), phi = kTwoPi * u1;  // sqrt: uniform over the area
            return e.centre + (b1 * std::cos(phi) + b2 * std::sin(phi)) * r;
        }
        case EmitterShape::Box:
            return e.centre + e.halfExtents * (glm::vec3(u0, u1, u2) * 2.0f - 1.0f);
        case EmitterShape::Sphere: {
            const float z = 1.0f - 2.0f * u0, s = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = kTwoPi * u1;
            const float r = e.radius * std::cbrt(u2);  // cube root: uniform over the volume
            return e.centre + glm::vec3(s * std::cos(phi), s * std::sin(phi), z) * r;
        }
    }
    return e.centre;
}

// Uniform over the cap's solid angle: cos θ uniform in [cos α, 1] (Archimedes' hat-box theorem).
glm::vec3 sampleVelocity(const VelocityCone& cone, float u_cone, float u_around, float u_speed) {
    const glm::vec3 axis = unit(cone.direction);
    glm::vec3 b1, b2;
    orthonormalBasis(axis, b1, b2);
    // 1 − cos α = 2 sin²(α/2), without cancellation for narrow cones.
    const double half_sin = std::sin(0.5 * double(cone.halfAngle));
    const float one_minus_cos = float(2.0 * half_sin * half_sin);
    const float cos_t = 1.0f - u_cone * one_minus_cos;
    const float sin_t = std::sqrt(std::max(0.0f, (1.0f - cos_t) * (1.0f + cos_t)));
    const float phi = 2.0f * std::numbers::pi_v<float> * u_around;
    const glm::vec3 dir = (b1 * std::cos(phi) + b2 * std::sin(phi)) * sin_t + axis * cos_t;
    return dir * lerp(cone.speedMin, cone.speedMax, u_speed);
}

}  // namespace

// ---- The system -------------------------------------------------------------------------------------

ParticleSystem::ParticleSystem(ParticleSystemDesc desc, ThreadPool* pool)
    : desc_(std::move(desc)), pool_(pool) {
    validateDesc(desc_);
    const uint64_t n = desc_.maxParticles;
    // The state, and room for a step's bookkeeping at its largest (every slot freed, every slot
    // born), so that step() never allocates.
    const uint64_t per_slot = 9 * sizeof(float) + sizeof(uint16_t) + 2 * sizeof(uint32_t) + sizeof(Birth);
    const uint64_t bytes = byteCount(n, per_slot);
    const std::string what = "a particle system of " + std::to_string(n) + " particles";
    requireMemory(bytes, what);
    allocateOrThrow(what, bytes, [&] {
        for (std::vector<float>* a : {&soa_.positionX, &soa_.positionY, &soa_.positionZ, &soa_.velocityX,
                                      &soa_.velocityY, &soa_.velocityZ, &soa_.age, &soa_.lifespan, &soa_.size})
            a->assign(n, 0.0f);
        soa_.emitter.assign(n, 0);
        const size_t blocks = (n + kParticleBlock - 1) / kParticleBlock;
        blockAlive_.assign(blocks, 0);
        blockDeaths_.resize(blocks);
        for (std::vector<uint32_t>& deaths : blockDeaths_) deaths.reserve(kParticleBlock);
        free_.reserve(n);
        births_.reserve(n);
    });
    emitterKey_.resize(desc_.emitters.size());
    for (size_t e = 0; e < emitterKey_.size(); ++e) emitterKey_[e] = mix64(desc_.seed + kGolden * (e + 1));
    emitted_.assign(desc_.emitters.size(), 0);
    phase_.assign(desc_.emitters.size(), 0.0);
}

void ParticleSystem::setEmitter(size_t index, Emitter emitter) {
    RASTER_REQUIRE(index < desc_.emitters.size(), OutOfRange,
                   "setEmitter: index " + std::to_string(index) + " but the system has " +
                       std::to_string(desc_.emitters.size()) + " emitters");
    validateEmitter(emitter, "emitters[" + std::to_string(index) + "]");
    desc_.emitters[index] = std::move(emitter);
}

void ParticleSystem::setEffectors(std::vector<Effector> effectors) {
    validateEffectors(effectors);
    desc_.effectors = std::move(effectors);
}

void ParticleSystem::parallel(uint32_t count, const std::function<void(uint32_t)>& fn) const {
    if (pool_ == nullptr || pool_->size() == 1 || count <= 1) {
        for (uint32_t i = 0; i < count; ++i) fn(i);
        return;
    }
    pool_->parallelFor(count, [&](uint32_t item, unsigned) { fn(item); });
}

void ParticleSystem::step() {
    const double dt = double(desc_.timeStep);
    const double t0 = double(steps_) * dt, t1 = double(steps_ + 1) * dt;
    integrate(desc_.timeStep, float(t0));
    collectDeaths();
    planBirths(t0, t1);
    initBirths();
    ++steps_;
}

uint32_t ParticleSystem::advance(double frameSeconds) {
    RASTER_REQUIRE(std::isfinite(frameSeconds) && frameSeconds >= 0.0, InvalidArgument,
                   "advance: frameSeconds is " + formatValue(frameSeconds) + ": must be finite and >= 0 (seconds)");
    const double dt = double(desc_.timeStep), threshold = dt * (1.0 - 1e-4);
    pending_ += frameSeconds;
    uint32_t steps = 0;
    while (pending_ >= threshold && steps < desc_.maxStepsPerAdvance) {
        step();
        pending_ -= dt;
        ++steps;
    }
    if (pending_ >= threshold) pending_ = std::fmod(pending_, dt);  // behind: drop the backlog
    return steps;
}

// ---- Effectors over one block -----------------------------------------------------------------------

namespace {

// One block of slots while a step runs: the state arrays at the block, the velocities at the step's
// start (v₀), and the advection velocity of turbulence without response.
struct Block {
    uint32_t n = 0;
    float *px, *py, *pz, *vx, *vy, *vz, *age, *life;
    float v0x[kParticleBlock], v0y[kParticleBlock], v0z[kParticleBlock];
    float ax[kParticleBlock], ay[kParticleBlock], az[kParticleBlock];
    bool advected = false;
};

struct StepInfo {
    float dt, time;
    uint64_t seed;
};

// v = target + (v − target)·k: relaxation toward a velocity, k = exp(−rate·dt).
template <class F, class T>
[[gnu::always_inline]] inline F relax(F v, T target, float k) {
    return target + (v - target) * k;
}

float decay(float rate, float dt) { return float(std::exp(-double(rate) * double(dt))); }

constexpr float kMaxFloat = std::numeric_limits<float>::max();

struct EffectorApplier {
    Block& b;
    const StepInfo& s;

    void operator()(const Gravity& g) const {
        const glm::vec3 dv = g.acceleration * s.dt;
        forLanes(b.n, [&]<class F>(uint32_t i) {
            store(b.vx + i, load<F>(b.vx + i) + dv.x);
            store(b.vy + i, load<F>(b.vy + i) + dv.y);
            store(b.vz + i, load<F>(b.vz + i) + dv.z);
        });
    }
    void operator()(const Wind& w) const {
        const float k = decay(w.drag, s.dt);
        forLanes(b.n, [&]<class F>(uint32_t i) {
            store(b.vx + i, relax(load<F>(b.vx + i), w.velocity.x, k));
            store(b.vy + i, relax(load<F>(b.vy + i), w.velocity.y, k));
            store(b.vz + i, relax(load<F>(b.vz + i), w.velocity.z, k));
        });
    }
    void operator()(const Buoyancy& y) const {
        const glm::vec3 dv = unit(y.up) * (y.acceleration * s.dt);
        const float fade = y.endScale - 1.0f;
        forLanes(b.n, [&]<class F>(uint32_t i) {
            const F life = load<F>(b.life + i);
            // Normalized age; dead slots (lifespan 0) get some finite t, never 0/0.
            const F t = load<F>(b.age + i) / select(life > 0.0f, life, splat<F>(1.0f));
            const F scale = 1.0f + fade * t;
            store(b.vx + i, load<F>(b.vx + i) + dv.x * scale);
            store(b.vy + i, load<F>(b.vy + i) + dv.y * scale);
            store(b.vz + i, load<F>(b.vz + i) + dv.z * scale);
        });
    }
    void operator()(const Drag& d) const {
        const float k = decay(d.coefficient, s.dt);
        forLanes(b.n, [&]<class F>(uint32_t i) {
            store(b.vx + i, load<F>(b.vx + i) * k);
            store(b.vy + i, load<F>(b.vy + i) * k);
            store(b.vz + i, load<F>(b.vz + i) * k);
        });
    }
    void operator()(const Attractor& a) const {
        const float soft2 = a.softening * a.softening, gain = a.strength * s.dt;
        forLanes(b.n, [&]<class F>(uint32_t i) {
            const F dx = a.position.x - load<F>(b.px + i), dy = a.position.y - load<F>(b.py + i);
            const F dz = a.position.z - load<F>(b.pz + i);
            const F r2 = dx * dx + dy * dy + dz * dz + soft2;
            // Capped: a softening so small that r2^1.5 underflows would give inf, and 0·inf = NaN.
            const F f = splat<F>(gain) / (r2 * sqrtLane(r2));
            const F f_capped = select(f < kMaxFloat, f, splat<F>(kMaxFloat));
            store(b.vx + i, load<F>(b.vx + i) + dx * f_capped);
            store(b.vy + i, load<F>(b.vy + i) + dy * f_capped);
            store(b.vz + i, load<F>(b.vz + i) + dz * f_capped);
        });
    }
    void operator()(const Vortex& v) const;
    void operator()(const Turbulence& t) const;
};

void EffectorApplier::operator()(const Vortex& v) const {
    const glm::vec3 a = unit(v.axis);
    // 1/radius², in double and capped, so that a tiny radius gives no inf (and no 0·inf on the axis).
    const float k = decay(v.drag, s.dt);
    const float inv_r2 = float(std::min(1.0 / (double(v.radius) * double(v.radius)), double(kMaxFloat)));
    forLanes(b.n, [&]<class F>(uint32_t i) {
        const F rx = load<F>(b.px + i) - v.centre.x, ry = load<F>(b.py + i) - v.centre.y;
        const F rz = load<F>(b.pz + i) - v.centre.z;
        const F along = rx * a.x + ry * a.y + rz * a.z;
        const F qx = rx - a.x * along, qy = ry - a.y * along, qz = rz - a.z * along;  // r⊥
        const F w = splat<F>(v.angularSpeed) / (1.0f + (qx * qx + qy * qy + qz * qz) * inv_r2);
        // u = w · (a × r⊥)
        store(b.vx + i, relax(load<F>(b.vx + i), w * (a.y * qz - a.z * qy), k));
        store(b.vy + i, relax(load<F>(b.vy + i), w * (a.z * qx - a.x * qz), k));
        store(b.vz + i, relax(load<F>(b.vz + i), w * (a.x * qy - a.y * qx), k));
    });
}

void EffectorApplier::operator()(const Turbulence& t) const {
    const uint32_t seed = uint32_t(mix64(s.seed ^ (kGolden * (uint64_t(t.seed) + 1))) >> 32);
    const glm::vec3 shift = t.drift * s.time;
    const float f = t.frequency, amp = t.amplitude, k = decay(t.response, s.dt);
    const bool advect = t.response == 0.0f;
    if (advect && !b.advected) {
        std::fill_n(b.ax, b.n, 0.0f), std::fill_n(b.ay, b.n, 0.0f), std::fill_n(b.az, b.n, 0.0f);
        b.advected = true;
    }
    forLanes(b.n, [&]<class F>(uint32_t i) {
        const Vec3<F> c = curlLanes<F>(load<F>(b.px + i) * f + shift.x, load<F>(b.py + i) * f + shift.y,
                                       load<F>(b.pz + i) * f + shift.z, seed);
        const F ux = c.x * amp, uy = c.y * amp, uz = c.z * amp;
        if (advect) {
            store(b.ax + i, load<F>(b.ax + i) + ux);
            store(b.ay + i, load<F>(b.ay + i) + uy);
            store(b.az + i, load<F>(b.az + i) + uz);
        } else {
            store(b.vx + i, relax(load<F>(b.vx + i), ux, k));
            store(b.vy + i, relax(load<F>(b.vy + i), uy, k));
            store(b.vz + i, relax(load<F>(b.vz + i), uz, k));
        }
    });
}

// Whether any lane of a mask is set.
[[gnu::always_inline]] inline bool anyLane(bool m) { return m; }
[[gnu::always_inline]] inline bool anyLane(I8 m) { return simd::maskBits(m) != 0; }

// The step's end for the block's living slots: position += ½(v₀ + v₁)·dt (+ advection·dt), age += dt.
// Dead slots keep everything (their velocity v₀ = 0), whatever the effectors computed for them.
// Those whose age reaches their lifespan die: `deaths` gets their slots (begin + index), ascending,
// and they get lifespan 0 and velocity 0.
void finishBlock(Block& b, float dt, uint32_t begin, std::vector<uint32_t>& deaths) {
    const float half_dt = 0.5f * dt;
    const bool advected = b.advected;
    deaths.clear();
    forLanes(b.n, [&]<class F>(uint32_t i) {
        const F age = load<F>(b.age + i), life = load<F>(b.life + i);
        const auto alive = age < life;
        const F v0x = load<F>(b.v0x + i), v0y = load<F>(b.v0y + i), v0z = load<F>(b.v0z + i);
        const F vx = load<F>(b.vx + i), vy = load<F>(b.vy + i), vz = load<F>(b.vz + i);
        const F px = load<F>(b.px + i), py = load<F>(b.py + i), pz = load<F>(b.pz + i);
        F nx = px + (v0x + vx) * half_dt, ny = py + (v0y + vy) * half_dt, nz = pz + (v0z + vz) * half_dt;
        if (advected) {
            nx = nx + load<F>(b.ax + i) * dt;
            ny = ny + load<F>(b.ay + i) * dt;
            nz = nz + load<F>(b.az + i) * dt;
        }
        const F new_age = age + dt;
        store(b.px + i, select(alive, nx, px)), store(b.py + i, select(alive, ny, py));
        store(b.pz + i, select(alive, nz, pz));
        store(b.vx + i, select(alive, vx, v0x)), store(b.vy + i, select(alive, vy, v0y));
        store(b.vz + i, select(alive, vz, v0z));
        store(b.age + i, select(alive, new_age, age));
        if (!anyLane(alive & (new_age >= life))) return;
        for (uint32_t j = i; j < i + sizeof(F) / sizeof(float); ++j) {
            if (b.life[j] > 0.0f && b.age[j] >= b.life[j]) {
                deaths.push_back(begin + j);
                b.life[j] = 0.0f;
                b.vx[j] = b.vy[j] = b.vz[j] = 0.0f;
            }
        }
    });
}

}  // namespace

void ParticleSystem::integrate(float dt, float time) {
    const uint32_t blocks = (highWater_ + kParticleBlock - 1) / kParticleBlock;
    parallel(blocks, [&](uint32_t block) { integrateBlock(block, dt, time); });
}

void ParticleSystem::integrateBlock(uint32_t block, float dt, float time) {
    const uint32_t begin = block * kParticleBlock;
    Block block_state;  // 48 KiB of the thread's stack
    Block* const b = &block_state;
    b->n = std::min(kParticleBlock, highWater_ - begin);
    b->px = soa_.positionX.data() + begin, b->py = soa_.positionY.data() + begin;
    b->pz = soa_.positionZ.data() + begin;
    b->vx = soa_.velocityX.data() + begin, b->vy = soa_.velocityY.data() + begin;
    b->vz = soa_.velocityZ.data() + begin;
    b->age = soa_.age.data() + begin, b->life = soa_.lifespan.data() + begin;
    std::memcpy(b->v0x, b->vx, b->n * sizeof(float));
    std::memcpy(b->v0y, b->vy, b->n * sizeof(float));
    std::memcpy(b->v0z, b->vz, b->n * sizeof(float));
    const StepInfo info{dt, time, desc_.seed};
    for (const Effector& e : desc_.effectors) std::visit(EffectorApplier{*b, info}, e);
    finishBlock(*b, dt, begin, blockDeaths_[block]);
}

void ParticleSystem::collectDeaths() {
    const uint32_t blocks = (highWater_ + kParticleBlock - 1) / kParticleBlock;
    for (uint32_t block = 0; block < blocks; ++block) {
        const std::vector<uint32_t>& deaths = blockDeaths_[block];
        free_.insert(free_.end(), deaths.begin(), deaths.end());
        blockAlive_[block] -= uint32_t(deaths.size());
        alive_ -= uint32_t(deaths.size());
        died_ += deaths.size();
    }
}

// This step's births, in a fixed order: emitter by emitter; for each, its bursts in list order, then
// its continuous stream. Slots are given out here, on one thread; initBirths fills them in parallel.
void ParticleSystem::planBirths(double t0, double t1) {
    births_.clear();
    for (size_t e = 0; e < desc_.emitters.size(); ++e) {
        const Emitter& emitter = desc_.emitters[e];
        for (const Burst& burst : emitter.bursts) {
            const double start = burst.time, interval = burst.interval;
            // Firing m happens at start + m·interval, in the one step whose [t0, t1) holds it; the
            // first m scanned is one below the estimate, so rounding cannot skip a firing.
            double m = 0.0;
            if (interval > 0.0 && t0 > start) m = std::max(0.0, std::floor((t0 - start) / interval) - 1.0);
            for (;; m += 1.0) {
                const double when = start + m * interval;
                if (when >= t1) break;
                if (when >= t0) {
                    uint32_t k = 0;
                    for (; k < burst.count && !full(); ++k) planBirth(uint16_t(e), when, t1);
                    if (k < burst.count) dropAll(uint16_t(e), burst.count - k);
                }
                if (interval == 0.0) break;
            }
        }
        if (emitter.rate > 0.0f) {
            // Particle n of the stream is born when the phase rate·time passes n.
            const double rate = emitter.rate, before = phase_[e], after = before + rate * (t1 - t0);
            double n = std::ceil(before);
            for (; n < after && !full(); n += 1.0) planBirth(uint16_t(e), t0 + (n - before) / rate, t1);
            if (n < after) dropAll(uint16_t(e), uint64_t(std::ceil(after) - n));
            phase_[e] = after;
        }
    }
}

// With every slot taken, the rest of a burst or stream is dropped without a loop over it: a burst
// of 4·10⁹ costs nothing once the slots are full. Only the emission count moves on.
void ParticleSystem::dropAll(uint16_t emitter, uint64_t count) {
    emitted_[emitter] += count;
    dropped_ += count;
}

void ParticleSystem::planBirth(uint16_t emitter, double birth_time, double t1) {
    const uint64_t index = emitted_[emitter]++;
    const Emitter& e = desc_.emitters[emitter];
    const uint64_t key = emitterKey_[emitter];
    const float lifespan = lerp(e.lifespanMin, e.lifespanMax, uniform01(key, index, kRandLifespan));
    const float age = float(t1 - birth_time);
    ++born_;
    if (age >= lifespan) {  // born and dead within this step
        ++died_;
        return;
    }
    uint32_t slot;
    if (free_.empty()) {
        slot = highWater_++;
    } else {
        slot = free_.back();
        free_.pop_back();
    }
    births_.push_back({slot, emitter, index, age, lifespan});
    ++blockAlive_[slot / kParticleBlock];
    ++alive_;
}

void ParticleSystem::initBirths() {
    constexpr uint32_t kChunk = 1024;
    const uint32_t chunks = uint32_t((births_.size() + kChunk - 1) / kChunk);
    parallel(chunks, [&](uint32_t chunk) {
        const size_t end = std::min(births_.size(), size_t(chunk + 1) * kChunk);
        for (size_t i = size_t(chunk) * kChunk; i < end; ++i) initBirth(births_[i]);
    });
}

void ParticleSystem::initBirth(const Birth& birth) {
    const Emitter& e = desc_.emitters[birth.emitter];
    const uint64_t key = emitterKey_[birth.emitter];
    auto u = [&](uint32_t dim) { return uniform01(key, birth.index, dim); };
    const glm::vec3 v = sampleVelocity(e.velocity, u(kRandCone), u(kRandAround), u(kRandSpeed));
    // Born `age` seconds before the step's end: it has moved that long along its first velocity.
    const glm::vec3 p = samplePosition(e, u(kRandPos0), u(kRandPos1), u(kRandPos2)) + v * birth.age;
    const uint32_t s = birth.slot;
    soa_.positionX[s] = p.x, soa_.positionY[s] = p.y, soa_.positionZ[s] = p.z;
    soa_.velocityX[s] = v.x, soa_.velocityY[s] = v.y, soa_.velocityZ[s] = v.z;
    soa_.age[s] = birth.age;
    soa_.lifespan[s] = birth.lifespan;
    soa_.size[s] = lerp(e.sizeMin, e.sizeMax, u(kRandSize));
    soa_.emitter[s] = birth.emitter;
}

// ---- Upload -----------------------------------------------------------------------------------------

size_t ParticleSystem::writeVertices(void* dst, size_t capacityBytes) const {
    RASTER_REQUIRE(capacityBytes / sizeof(Particle) >= alive_, OutOfRange,
                   "writeVertices: " + std::to_string(alive_) + " particles alive (" +
                       std::to_string(uint64_t(alive_) * sizeof(Particle)) + " bytes), room for " +
                       std::to_string(capacityBytes) + " bytes");
    const uint32_t blocks = (highWater_ + kParticleBlock - 1) / kParticleBlock;
    std::vector<uint32_t> first(blocks + 1, 0);  // each block's first vertex
    for (uint32_t block = 0; block < blocks; ++block) first[block + 1] = first[block] + blockAlive_[block];
    std::byte* const out = static_cast<std::byte*>(dst);
    parallel(blocks, [&](uint32_t block) {
        const uint32_t begin = block * kParticleBlock, end = std::min(begin + kParticleBlock, highWater_);
        size_t vertex = first[block];
        for (uint32_t s = begin; s < end; ++s) {
            if (!(soa_.age[s] < soa_.lifespan[s])) continue;
            const Emitter& e = desc_.emitters[soa_.emitter[s]];
            Particle p;
            p.position = {soa_.positionX[s], soa_.positionY[s], soa_.positionZ[s]};
            p.velocity = {soa_.velocityX[s], soa_.velocityY[s], soa_.velocityZ[s]};
            p.age = soa_.age[s];
            p.lifespan = soa_.lifespan[s];
            const float t = p.age / p.lifespan;
            p.size = soa_.size[s] * e.sizeOverLife(t);
            p.colour = glm::vec4(e.colourOverLife(t), e.opacityOverLife(t));
            std::memcpy(out + vertex * sizeof(Particle), &p, sizeof(Particle));
            ++vertex;
        }
        RASTER_CHECK(vertex == first[block + 1]);
    });
    return alive_;
}

size_t ParticleSystem::writeVertices(std::span<Particle> dst) const {
    return writeVertices(dst.data(), dst.size_bytes());
}

std::vector<Particle> ParticleSystem::vertices() const {
    std::vector<Particle> out(alive_);
    writeVertices(out);
    return out;
}

}  // namespace raster
