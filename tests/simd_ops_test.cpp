// The SIMD layer's named operations (raster/simd/ops.hpp) against scalar references written from
// their documented rules, lane by lane and bit for bit, on edge values (NaN, ±0, ±∞, saturation
// limits, rounding ties) and random ones; and the portable versions (simd/portable.hpp) against the
// ones this build chose, so that a build for a target without the instruction set gets the same
// bits. Small on purpose: it includes the layer and the output merger only, so that it also
// compiles alone, e.g. for plain x86-64:
//     g++ -std=c++20 -O2 -march=x86-64 -ffp-contract=off -Iraster/pipeline/include tests/simd_ops_test.cpp -lgtest -lgtest_main
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "raster/format.hpp"
#include "raster/simd/ops.hpp"
#include "raster/stages/9_output_merger.hpp"
#include "test_paths.hpp"

namespace raster {
namespace {

using simd::F32x8;
using simd::I32x8;

uint32_t bitsOf(float f) { return __builtin_bit_cast(uint32_t, f); }

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// Values where the rules have an edge: NaN of both signs, ±0, ±∞, the limits of saturate and of
// int32, ties of round-to-nearest-even and of the unorm8 rounding (n + 0.5)/255, denormals.
std::vector<float> edgeValues() {
    std::vector<float> v = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 1.5f, 2.5f, -2.5f, 3.5f, kNaN, -kNaN, kInf, -kInf,
                            2147483648.0f, -2147483648.0f, 2147483520.0f, 3e9f, -3e9f, 1e-45f, -1e-45f, 1e-38f,
                            std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), 0.99999994f,
                            1.00000012f, 255.5f, 16777216.0f, -16777217.0f, 8388608.5f};
    for (int n : {0, 1, 127, 128, 254, 255}) v.push_back((float(n) + 0.5f) / 255.0f);
    return v;
}

// Eight lanes drawn from the edge values and from a uniform range, mixed.
struct LaneSource {
    std::mt19937 rng;
    std::vector<float> edges = edgeValues();
    float lo, hi;
    LaneSource(unsigned seed, float lo_, float hi_) : rng(seed), lo(lo_), hi(hi_) {}
    float next() {
        if (rng() % 3 == 0) return edges[rng() % edges.size()];
        return std::uniform_real_distribution<float>(lo, hi)(rng);
    }
    F32x8 lanes() {
        F32x8 v;
        for (int i = 0; i < 8; ++i) v[i] = next();
        return v;
    }
};

void expectSameBits(F32x8 got, F32x8 want, const char* what, F32x8 in) {
    for (int i = 0; i < 8; ++i)
        ASSERT_EQ(bitsOf(got[i]), bitsOf(want[i])) << what << " lane " << i << " of " << in[i];
}
// The same, but any NaN for a NaN: which of several NaN operands a fused multiply-add returns
// differs between FMA's three instruction forms (the compiler picks one) and the C library's fmaf.
void expectSameValues(F32x8 got, F32x8 want, const char* what, F32x8 in) {
    for (int i = 0; i < 8; ++i) {
        if (std::isnan(want[i]))
            ASSERT_TRUE(std::isnan(got[i])) << what << " lane " << i << " of " << in[i];
        else
            ASSERT_EQ(bitsOf(got[i]), bitsOf(want[i])) << what << " lane " << i << " of " << in[i];
    }
}

TEST(SimdOps, LaneOperationsFollowTheirScalarRules) {
    LaneSource source(1, -300.0f, 300.0f);
    for (int round = 0; round < 4000; ++round) {
        const F32x8 a = source.lanes(), b = source.lanes(), c = source.lanes();
        F32x8 min_ref, max_ref, floor_ref, sqrt_ref, fma_ref;
        I32x8 round_ref, less;
        for (int i = 0; i < 8; ++i) {
            min_ref[i] = a[i] < b[i] ? a[i] : b[i];
            max_ref[i] = a[i] > b[i] ? a[i] : b[i];
            floor_ref[i] = std::floor(a[i]);
            sqrt_ref[i] = std::sqrt(a[i]);
            fma_ref[i] = std::fma(a[i], b[i], c[i]);
            // Ties to even; NaN and what lies outside int32 give INT32_MIN.
            const float r = std::nearbyint(a[i]);
            round_ref[i] = r >= -2147483648.0f && r < 2147483648.0f ? int32_t(r) : INT32_MIN;
            less[i] = a[i] < b[i] ? -1 : 0;
        }
        expectSameBits(simd::min(a, b), min_ref, "min", a);
        expectSameBits(simd::max(a, b), max_ref, "max", a);
        expectSameBits(simd::floor(a), floor_ref, "floor", a);
        expectSameBits(simd::sqrt(a), sqrt_ref, "sqrt", a);
        expectSameValues(simd::fma(a, b, c), fma_ref, "fma", a);
        for (int i = 0; i < 8; ++i) ASSERT_EQ(simd::roundToInt(a)[i], round_ref[i]) << a[i];
        uint32_t bits = 0;
        for (int i = 0; i < 8; ++i) bits |= uint32_t(less[i] != 0) << i;
        ASSERT_EQ(simd::maskBits(less), bits);
        const simd::I64x4 wide = {less[0], less[3], less[5], less[6]};
        ASSERT_EQ(simd::maskBits(wide), (bits & 1) | (bits >> 2 & 2) | (bits >> 3 & 4) | (bits >> 3 & 8));
        // The portable versions give the same bits as the ones chosen here.
        expectSameBits(simd::portable::min(a, b), min_ref, "portable min", a);
        expectSameBits(simd::portable::max(a, b), max_ref, "portable max", a);
        expectSameBits(simd::portable::floor(a), floor_ref, "portable floor", a);
        expectSameBits(simd::portable::sqrt(a), sqrt_ref, "portable sqrt", a);
        expectSameValues(simd::portable::fma(a, b, c), fma_ref, "portable fma", a);
        for (int i = 0; i < 8; ++i) ASSERT_EQ(simd::portable::roundToInt(a)[i], round_ref[i]) << a[i];
        ASSERT_EQ(simd::portable::maskBits(less), bits);
        ASSERT_EQ(simd::portable::maskBits(wide), simd::maskBits(wide));
    }
}

TEST(SimdOps, DoublesToFloatsGathersAndRowLoads) {
    const simd::F64x4 lo = {0.1, -0.0, 1e300, 1.0000000596046448};  // the last a tie: rounds to even 1
    const simd::F64x4 hi = {std::nan(""), -1e-300, -3.4028235677973366e38, 16777217.0};
    const F32x8 f = simd::toFloat8(lo, hi), p = simd::portable::toFloat8(lo, hi);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(bitsOf(f[i]), bitsOf(float(lo[i]))) << i;
        EXPECT_EQ(bitsOf(f[4 + i]), bitsOf(float(hi[i]))) << i;
        EXPECT_EQ(bitsOf(p[i]), bitsOf(f[i])) << i;
        EXPECT_EQ(bitsOf(p[4 + i]), bitsOf(f[4 + i])) << i;
    }
    std::vector<int32_t> table(64);
    std::vector<float> floats(64);
    for (int k = 0; k < 64; ++k) table[k] = k * 7919 - 100000, floats[k] = float(k) * -0.25f;
    const I32x8 index = {63, 0, 5, 5, 17, 32, 1, 62};
    const I32x8 g = simd::gather(table.data(), index), gp = simd::portable::gather(table.data(), index);
    const F32x8 gf = simd::gather(floats.data(), index);
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(g[i], table[index[i]]);
        EXPECT_EQ(gp[i], table[index[i]]);
        EXPECT_EQ(bitsOf(gf[i]), bitsOf(floats[index[i]]));
    }
    const F32x8 rows = simd::loadRows(floats.data() + 3, floats.data() + 40);
    const F32x8 rows_p = simd::portable::loadRows(floats.data() + 3, floats.data() + 40);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(bitsOf(rows[i]), bitsOf(floats[3 + i]));
        EXPECT_EQ(bitsOf(rows[4 + i]), bitsOf(floats[40 + i]));
    }
    expectSameBits(rows_p, rows, "portable loadRows", rows);
}

// ---- The footprint filter ------------------------------------------------------------------------

// A w × h grid of random footprints (bytes − 128 of four texels per channel, as Texture2D builds
// them; any bytes do for the formula), and its channel planes for the AVX-512 pair.
struct Footprints {
    int w, h;
    simd::FootprintGrid grid;
    std::vector<uint8_t> bytes;
    std::vector<int32_t> planes;
    Footprints(int w_, int h_, unsigned seed) : w(w_), h(h_) {
        grid = {float(w), float(h), float(w - 1), float(h - 1), float(w + 1), float(w + 2), w - 1, h - 1, w + 1, 0};
        const size_t count = size_t(w + 1) * size_t(h + 1), plane = count + simd::kFootprintPlaneWindow - 1;
        std::mt19937 rng(seed);
        bytes.resize(16 * count);
        for (auto& b : bytes) b = uint8_t(rng());
        for (size_t k = 0; k < 4 && k < count; ++k) std::memset(&bytes[16 * k], k % 2 ? 0x00 : 0xFF, 16);  // extremes
        planes.assign(4 * plane, 0);
        for (size_t c = 0; c < 4; ++c)
            for (size_t k = 0; k < count; ++k) std::memcpy(&planes[c * plane + k], &bytes[16 * k + 4 * c], 4);
        grid.planeStride = int32_t(plane);
    }
    // The formula of simd/base.hpp for one sample at (u, v), written out in scalar code.
    glm::vec4 reference(float u, float v) const {
        auto clampCoord = [](float x, float last) {
            x = x > -1.0f ? x : -1.0f;  // NaN -> −1
            return x < last ? x : last;
        };
        const float a = clampCoord(u * grid.width - 0.5f, grid.lastI);
        const float b = clampCoord(v * grid.height - 0.5f, grid.lastJ);
        const float i = std::floor(a), j = std::floor(b);
        const int wa = std::min(int(std::nearbyint((a - i) * 256.0f)), 255);
        const int wb = int(std::nearbyint((b - j) * 16384.0f));
        const size_t index = size_t(int32_t(j * grid.rowStride + i + grid.originIndex));
        const int8_t* t = reinterpret_cast<const int8_t*>(bytes.data()) + 16 * index;
        glm::vec4 out;
        for (int c = 0; c < 4; ++c, t += 4) {
            const int top = (256 - wa) * t[0] + wa * t[1], bottom = (256 - wa) * t[2] + wa * t[3];
            const int sum = (16384 - wb) * top + wb * bottom;
            out[c] = (float(sum) + 536870912.0f) * ((1.0f / 255.0f) / 4194304.0f);
        }
        return out;
    }
};

// Texture coordinates for a block pair, lanes 0–3 the top row and 4–7 the bottom one of each block:
// a billboard's (u growing along x, one v per row) or random ones, with edge values mixed in, and
// α, β ties (α·256 and β·2^14 halfway between integers: the sizes are powers of two, so exact).
void blockPairCoordinates(std::mt19937& rng, const Footprints& f, F32x8 (&u)[2], F32x8 (&v)[2]) {
    std::uniform_real_distribution<float> d(-0.3f, 1.3f);
    const int kind = int(rng() % 4);
    const float u0 = d(rng), du = std::uniform_real_distribution<float>(0.0f, 3.0f / f.grid.width)(rng);
    for (int k = 0; k < 2; ++k)
        for (int l = 0; l < 8; ++l) {
            const float column = float(4 * k + l % 4);
            if (kind == 0) {  // a billboard's row pair
                u[k][l] = u0 + du * column, v[k][l] = float(l / 4) * 0.01f + 0.4f;
            } else if (kind == 1) {  // ties
                const float ti = float(int(rng() % uint32_t(f.w))), tj = float(int(rng() % uint32_t(f.h)));
                u[k][l] = (ti + 0.5f + float(2 * int(rng() % 256) + 1) / 512.0f) / f.grid.width;
                v[k][l] = (tj + 0.5f + float(2 * int(rng() % 16384) + 1) / 32768.0f) / f.grid.height;
            } else {
                LaneSource edges(unsigned(rng()), -0.3f, 1.3f);
                u[k][l] = kind == 2 ? edges.next() : d(rng), v[k][l] = kind == 2 ? edges.next() : d(rng);
            }
        }
}

TEST(SimdOps, FootprintFilterFollowsTheFormulaInEveryLane) {
    for (const auto& [w, h] : {std::pair{16, 8}, std::pair{1, 1}, std::pair{37, 5}}) {
        const Footprints f(w, h, unsigned(w * 31 + h));
        std::mt19937 rng(unsigned(w + h));
        for (int round = 0; round < 3000; ++round) {
            F32x8 u[2], v[2];
            blockPairCoordinates(rng, f, u, v);
            F32x8 one[1][4], pair[2][4], portable[2][4];
            simd::footprintFilter<1>(f.grid, f.bytes.data(), f.planes.data(), {u[0]}, {v[0]}, one);
            simd::footprintFilter<2>(f.grid, f.bytes.data(), f.planes.data(), u, v, pair);
            simd::portable::footprintFilter8<2>(f.grid, f.bytes.data(), u, v, portable);
            for (int k = 0; k < 2; ++k)
                for (int l = 0; l < 8; ++l) {
                    const glm::vec4 want = f.reference(u[k][l], v[k][l]);
                    for (int c = 0; c < 4; ++c) {
                        ASSERT_EQ(bitsOf(pair[k][c][l]), bitsOf(want[c]))
                            << w << "x" << h << " block " << k << " lane " << l << " (" << u[k][l] << ", " << v[k][l] << ")";
                        ASSERT_EQ(bitsOf(portable[k][c][l]), bitsOf(want[c])) << "portable";
                        if (k == 0) {
                            ASSERT_EQ(bitsOf(one[0][c][l]), bitsOf(want[c])) << "one block";
                        }
                    }
                }
        }
    }
}

TEST(SimdOps, OneFootprintFollowsTheFormulaForEveryWeight) {
    const Footprints f(3, 2, 9);
    for (size_t k = 0; k < f.bytes.size() / 16; ++k) {
        const int8_t* t = reinterpret_cast<const int8_t*>(f.bytes.data()) + 16 * k;
        for (int a = 0; a <= 255; a += (a < 3 || a > 252) ? 1 : 17)
            for (int b = 0; b <= 16384; b += (b < 2 || b > 16382) ? 1 : 1021) {
                const glm::vec4 got = simd::footprintFilter1(t, a, b);
                const simd::F32x4 portable = simd::portable::footprintFilter1(t, a, b);
                for (int c = 0; c < 4; ++c) {
                    const int8_t* q = t + 4 * c;
                    const int sum = (16384 - b) * ((256 - a) * q[0] + a * q[1]) + b * ((256 - a) * q[2] + a * q[3]);
                    const float want = (float(sum) + 536870912.0f) * ((1.0f / 255.0f) / 4194304.0f);
                    ASSERT_EQ(bitsOf(got[c]), bitsOf(want)) << a << " " << b;
                    ASSERT_EQ(bitsOf(portable[c]), bitsOf(want)) << a << " " << b;
                }
            }
    }
    // At α = β = 0 the texel comes back exactly: unorm8ToFloat of the stored byte.
    const int8_t texel[16] = {-128, 0, 0, 0, 127, 0, 0, 0, 0, 0, 0, 0, -1, 5, 5, 5};
    const glm::vec4 at_centre = simd::footprintFilter1(texel, 0, 0);
    EXPECT_EQ(at_centre.x, unorm8ToFloat(0));
    EXPECT_EQ(at_centre.y, unorm8ToFloat(255));
    EXPECT_EQ(at_centre.z, unorm8ToFloat(128));
    EXPECT_EQ(at_centre.w, unorm8ToFloat(127));
}

// ---- The RGBA8 blenders ----------------------------------------------------------------------------

TEST(SimdOps, Unorm8StoreAndAdditiveBlendFollowTheScalarRules) {
    LaneSource source(4, -0.5f, 1.5f);
    std::mt19937 rng(6);
    for (int round = 0; round < 20000; ++round) {
        const glm::vec4 c(source.next(), source.next(), source.next(), source.next());
        uint8_t stored[4], stored_p[4];
        simd::storeUnorm8x4(stored, c);
        simd::portable::storeUnorm8x4(stored_p, simd::F32x4{c.x, c.y, c.z, c.w});
        uint8_t dest[4];
        for (auto& d : dest) d = rng() % 4 == 0 ? 255 : uint8_t(rng());
        uint8_t added[4], added_p[4];
        std::memcpy(added, dest, 4), std::memcpy(added_p, dest, 4);
        simd::additiveBlendUnorm8x4(added, c);
        simd::portable::additiveBlendUnorm8x4(added_p, simd::F32x4{c.x, c.y, c.z, c.w});
        const glm::vec4 s = detail::saturate(c);
        for (int k = 0; k < 4; ++k) {
            ASSERT_EQ(stored[k], floatToUnorm8(c[k])) << c[k];
            ASSERT_EQ(stored_p[k], stored[k]) << c[k];
            ASSERT_EQ(added[k], detail::addUnits255(dest[k], s[k], s.w)) << c[k] << " alpha " << c.w;
            ASSERT_EQ(added_p[k], added[k]) << c[k];
        }
    }
}

TEST(SimdOps, EightPixelAdditiveBlendIsTheOnePixelBlendInEveryLane) {
    LaneSource source(8, -0.5f, 1.5f);
    std::mt19937 rng(10);
    for (int round = 0; round < 5000; ++round) {
        F32x8 rgba[4];
        for (auto& channel : rgba) channel = source.lanes();
        I32x8 dest;
        for (int l = 0; l < 8; ++l) dest[l] = rng() % 4 == 0 ? -1 : int32_t(rng());
        const I32x8 got = simd::additiveBlendRgba8(dest, rgba[0], rgba[1], rgba[2], rgba[3]);
        const I32x8 portable = simd::portable::additiveBlendRgba8(dest, rgba[0], rgba[1], rgba[2], rgba[3]);
        for (int l = 0; l < 8; ++l) {
            uint8_t pixel[4];
            const int32_t old = dest[l];  // a copy: clang takes no vector element's address
            std::memcpy(pixel, &old, 4);
            simd::additiveBlendUnorm8x4(pixel, glm::vec4(rgba[0][l], rgba[1][l], rgba[2][l], rgba[3][l]));
            int32_t want;
            std::memcpy(&want, pixel, 4);
            ASSERT_EQ(got[l], want) << "lane " << l << ": " << rgba[0][l] << " alpha " << rgba[3][l];
            ASSERT_EQ(portable[l], want) << "portable, lane " << l;
        }
    }
}

// ---- The pair of blocks (AVX-512) ------------------------------------------------------------------

// What a test that needs AVX-512 prints when it skips, naming what did not run.
[[maybe_unused]] constexpr const char* kNoAvx512 =
    "no AVX-512 in this build (F, BW, DQ and VL): simd/avx512.hpp's kernels were not run here; "
    "SimdOps.PortablePairKernelsReproduceTheAvx512Recording checked their recorded outputs instead";

// `blend` (a pair kernel: two side-by-side 4×2 blocks, block 0 in lanes 0–7 at columns 0–3, block 1
// in lanes 8–15 at columns 4–7) against the one-pixel blend lane by lane, under random masks.
template <class PairBlend>
void expectPairBlendIsOnePixelBlend(PairBlend blend) {
    LaneSource source(8, -0.5f, 1.5f);
    std::mt19937 rng(10);
    for (int round = 0; round < 5000; ++round) {
        F32x8 rgba[4];
        for (auto& channel : rgba) channel = source.lanes();
        uint8_t rows[2][32], want_rows[2][32];
        for (auto& row : rows)
            for (auto& b : row) b = uint8_t(rng());
        std::memcpy(want_rows, rows, sizeof rows);
        const uint32_t mask = rng() & 0xFFFF;
        const F32x8 pair[4][2] = {{rgba[0], rgba[1]}, {rgba[1], rgba[2]}, {rgba[2], rgba[3]}, {rgba[3], rgba[0]}};
        uint32_t want_no_ops = 0;
        for (int lane = 0; lane < 16; ++lane) {
            const int k = lane / 8, l = lane % 8;
            const glm::vec4 c(pair[0][k][l], pair[1][k][l], pair[2][k][l], pair[3][k][l]);
            want_no_ops |= uint32_t(detail::saturate(c.w) == 0.0f) << lane;
            if (mask >> lane & 1) simd::additiveBlendUnorm8x4(&want_rows[l / 4][16 * k + 4 * (l % 4)], c);
        }
        ASSERT_EQ(blend(rows[0], rows[1], pair, mask), want_no_ops) << "round " << round;  // bits 16–31 too
        ASSERT_EQ(std::memcmp(rows, want_rows, sizeof rows), 0) << "round " << round;
    }
}

TEST(SimdOps, PortablePairAdditiveBlendIsTheOnePixelBlendInEveryLane) {
    expectPairBlendIsOnePixelBlend(simd::portable::additiveBlendRgba8Pair);
}

TEST(SimdOps, Avx512PairAdditiveBlendIsTheOnePixelBlendInEveryLane) {
#if RASTER_AVX512
    expectPairBlendIsOnePixelBlend(simd::avx512::additiveBlendRgba8Pair);
#else
    GTEST_SKIP() << kNoAvx512;
#endif
}

// ---- The AVX-512 kernels' recorded outputs -----------------------------------------------------------
// Debian packages no emulator that runs AVX-512 code (QEMU's TCG and valgrind stop at AVX2; Intel's SDE
// is not packaged), and a build without AVX-512 does not compile simd/avx512.hpp at all. So the pair
// kernels' outputs on fixed inputs are recorded where they run, as digests in
// tests/data/simd/avx512_kernels.txt together with a digest of avx512.hpp's text. Everywhere, the
// portable reference must reproduce the recorded outputs, and the recording must be of today's
// avx512.hpp: an edit to it fails here until it is recorded again on a machine with AVX-512:
//     RASTER_RECORD_AVX512=1 build/bin/simd_ops_test --gtest_filter='*Avx512*Recording*'

// FNV-1a, 64 bits: a digest of bytes (not for security: it notices any change of an output).
struct Digest {
    uint64_t h = 0xcbf29ce484222325ull;
    void add(const void* data, size_t n) {
        for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(data)[i]) * 0x100000001b3ull;
    }
    std::string hex() const {
        char text[17];
        std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
        return text;
    }
};

std::string readFile(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return "";
    std::string text;
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) text.append(buffer, n);
    std::fclose(f);
    return text;
}

const std::string kRecordingPath = test::testDataDir() + "/simd/avx512_kernels.txt";
const std::string kAvx512Header = test::sourceDir() + "/raster/pipeline/include/raster/simd/avx512.hpp";

// A float in [lo, hi) from 24 random bits, the same on every standard library (the <random>
// distributions are not).
float uniformFloat(std::mt19937& rng, float lo, float hi) { return lo + (hi - lo) * float(rng() >> 8) * 0x1p-24f; }

// The pair kernels on seeded inputs: footprint filters of several grids (a billboard's row pair, ties
// of both weights, edge values, random coordinates) and additive blends under random masks, digested.
struct PairKernels {
    void (*filter)(const simd::FootprintGrid&, const uint8_t*, const int32_t*, const F32x8 (&)[2],
                   const F32x8 (&)[2], F32x8 (&)[2][4]);
    uint32_t (*blend)(uint8_t*, uint8_t*, const F32x8 (&)[4][2], uint32_t);
};
std::pair<std::string, std::string> pairKernelDigests(const PairKernels& kernels) {
    Digest filter, blend;
    const std::vector<float> edges = edgeValues();
    for (const auto& [w, h] : {std::pair{16, 8}, std::pair{1, 1}, std::pair{37, 5}, std::pair{64, 64}}) {
        const Footprints f(w, h, unsigned(w * 131 + h));
        std::mt19937 rng(unsigned(w * 7 + h));
        for (int round = 0; round < 2000; ++round) {
            F32x8 u[2], v[2], out[2][4];
            const int kind = int(rng() % 4);
            const float u0 = uniformFloat(rng, -0.3f, 1.3f), du = uniformFloat(rng, 0.0f, 3.0f / float(w));
            for (int k = 0; k < 2; ++k)
                for (int l = 0; l < 8; ++l) {
                    const float column = float(4 * k + l % 4);
                    if (kind == 0) {  // a billboard's row pair
                        u[k][l] = u0 + du * column, v[k][l] = float(l / 4) * 0.01f + 0.4f;
                    } else if (kind == 1) {  // α·256 and β·2^14 halfway between integers
                        u[k][l] = (float(rng() % uint32_t(w)) + 0.5f + float(2 * (rng() % 256) + 1) / 512.0f) / float(w);
                        v[k][l] = (float(rng() % uint32_t(h)) + 0.5f + float(2 * (rng() % 16384) + 1) / 32768.0f) / float(h);
                    } else if (kind == 2) {
                        u[k][l] = edges[rng() % edges.size()], v[k][l] = edges[rng() % edges.size()];
                    } else {
                        u[k][l] = uniformFloat(rng, -0.3f, 1.3f), v[k][l] = uniformFloat(rng, -0.3f, 1.3f);
                    }
                }
            kernels.filter(f.grid, f.bytes.data(), f.planes.data(), u, v, out);
            filter.add(out, sizeof out);
        }
    }
    std::mt19937 rng(20261204);
    for (int round = 0; round < 20000; ++round) {
        F32x8 rgba[4][2];
        for (auto& channel : rgba)
            for (auto& block : channel)
                for (int l = 0; l < 8; ++l)
                    block[l] = rng() % 3 == 0 ? edges[rng() % edges.size()] : uniformFloat(rng, -0.5f, 1.5f);
        uint8_t rows[2][32];
        for (auto& row : rows)
            for (auto& b : row) b = uint8_t(rng());
        const uint32_t no_ops = kernels.blend(rows[0], rows[1], rgba, rng() & 0xFFFF);
        blend.add(rows, sizeof rows), blend.add(&no_ops, sizeof no_ops);
    }
    return {filter.hex(), blend.hex()};
}

// The recording's "key value" lines (lines starting with '#' are comments).
std::map<std::string, std::string> readRecording() {
    std::map<std::string, std::string> values;
    std::istringstream in(readFile(kRecordingPath));
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        const size_t space = line.find(' ');
        if (space != std::string::npos) values[line.substr(0, space)] = line.substr(space + 1);
    }
    return values;
}

void portableFootprintFilterPair(const simd::FootprintGrid& grid, const uint8_t* footprints, const int32_t*,
                                const F32x8 (&u)[2], const F32x8 (&v)[2], F32x8 (&out)[2][4]) {
    simd::portable::footprintFilter8<2>(grid, footprints, u, v, out);
}
const PairKernels kPortablePair = {portableFootprintFilterPair, simd::portable::additiveBlendRgba8Pair};

TEST(SimdOps, PortablePairKernelsReproduceTheAvx512Recording) {
    const std::map<std::string, std::string> recorded = readRecording();
    ASSERT_FALSE(recorded.empty()) << "no recording at " << kRecordingPath;
    const auto [filter, blend] = pairKernelDigests(kPortablePair);
    EXPECT_EQ(filter, recorded.at("footprintFilterPair")) << "the portable footprint filter of a pair";
    EXPECT_EQ(blend, recorded.at("additiveBlendRgba8Pair")) << "the portable additive blend of a pair";
}

TEST(SimdOps, Avx512RecordingIsOfTodaysAvx512Header) {
    const std::string header = readFile(kAvx512Header);
    ASSERT_FALSE(header.empty()) << "cannot read " << kAvx512Header;
    Digest source;
    source.add(header.data(), header.size());
    std::map<std::string, std::string> recorded = readRecording();
    if (simd::kAvx512 && std::getenv("RASTER_RECORD_AVX512")) {
#if RASTER_AVX512
        const auto [filter, blend] = pairKernelDigests({simd::avx512::footprintFilterPair, simd::avx512::additiveBlendRgba8Pair});
        std::string machine = "unknown";
        std::istringstream cpuinfo(readFile("/proc/cpuinfo"));
        for (std::string line; std::getline(cpuinfo, line);)
            if (line.rfind("model name", 0) == 0) {
                machine = line.substr(line.find(':') + 2);
                break;
            }
        std::FILE* f = std::fopen(kRecordingPath.c_str(), "wb");
        ASSERT_NE(f, nullptr) << "cannot write " << kRecordingPath;
        std::fprintf(f,
                     "# The outputs of raster/pipeline/include/raster/simd/avx512.hpp's pair kernels on the seeded inputs of\n"
                     "# tests/simd_ops_test.cpp (pairKernelDigests), as FNV-1a 64 digests, and the digest of the header\n"
                     "# they were recorded from. Written by RASTER_RECORD_AVX512=1 simd_ops_test on a machine with AVX-512.\n"
                     "machine %s\nsource %s\nfootprintFilterPair %s\nadditiveBlendRgba8Pair %s\n",
                     machine.c_str(), source.hex().c_str(), filter.c_str(), blend.c_str());
        std::fclose(f);
        std::printf("recorded %s on %s\n", kRecordingPath.c_str(), machine.c_str());
        return;
#endif
    }
    ASSERT_FALSE(recorded.empty()) << "no recording at " << kRecordingPath;
    EXPECT_EQ(source.hex(), recorded.at("source"))
        << "raster/pipeline/include/raster/simd/avx512.hpp changed since its kernels' outputs were recorded (on "
        << recorded["machine"] << "): record them again on a machine with AVX-512 (RASTER_RECORD_AVX512=1 "
        << "build/bin/simd_ops_test --gtest_filter='*Avx512*'), where the tests also run the kernels themselves";
}

TEST(SimdOps, Avx512PairKernelsReproduceTheirRecording) {
#if RASTER_AVX512
    const std::map<std::string, std::string> recorded = readRecording();
    ASSERT_FALSE(recorded.empty()) << "no recording at " << kRecordingPath;
    const auto [filter, blend] = pairKernelDigests({simd::avx512::footprintFilterPair, simd::avx512::additiveBlendRgba8Pair});
    EXPECT_EQ(filter, recorded.at("footprintFilterPair")) << "avx512::footprintFilterPair";
    EXPECT_EQ(blend, recorded.at("additiveBlendRgba8Pair")) << "avx512::additiveBlendRgba8Pair";
#else
    GTEST_SKIP() << kNoAvx512;
#endif
}

}  // namespace
}  // namespace raster
