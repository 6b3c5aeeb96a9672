#include "raster/texture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "raster/check.hpp"
#include "raster/format.hpp"
#include "raster/sampler.hpp"
#include "raster/shader_context.hpp"
#include "test_paths.hpp"

namespace raster {
namespace {

// 4×2 float texture whose texel (x, y) is (x, y, 1 + x + 4y, x²): a sample names the texels it mixed,
// and the x² channel is not reproduced by bilinear interpolation, so a wrong weight shows.
glm::vec4 indexTexel(int x, int y) {
    return {float(x), float(y), float(1 + x + 4 * y), float(x * x)};
}

Texture2D indexTexture4x2() {
    std::vector<float> rgba;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            const glm::vec4 t = indexTexel(x, y);
            rgba.insert(rgba.end(), {t.x, t.y, t.z, t.w});
        }
    return Texture2D::fromRgba32f(4, 2, rgba);
}

const glm::vec4 kBorder{-1, -2, -3, -4};

SamplerState withBorder(SamplerState s) {
    s.borderColor = kBorder;
    return s;
}

// 4×4 float texture, r = x and g = y, with mips: level 1 is r = 2X + 0.5 (0.5, 2.5), level 2 r = 1.5.
// At uv (1/8, 1/8), the centre of level 0's texel (0, 0), linear filtering reads r = 0, 0.5, 1.5 at
// levels 0, 1, 2 (clamp).
Texture2D rampTexture4x4() {
    std::vector<float> rgba;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) rgba.insert(rgba.end(), {float(x), float(y), 0.0f, 1.0f});
    return Texture2D::fromRgba32f(4, 4, rgba, true);
}
const glm::vec2 kRampUv{0.125f, 0.125f};

// Bytes with no pattern a filter could hide behind.
std::vector<uint8_t> scrambledBytes(size_t count) {
    std::vector<uint8_t> bytes(count);
    for (size_t k = 0; k < count; ++k) bytes[k] = uint8_t((k * 97 + 13) % 251);
    return bytes;
}

// A texel of an UNORM texture as its stored bytes.
glm::ivec4 loadBytes(const Texture2D& t, int x, int y, int level) {
    const glm::vec4 c = t.load(x, y, level);
    return {floatToUnorm8(c.x), floatToUnorm8(c.y), floatToUnorm8(c.z), floatToUnorm8(c.w)};
}

struct ReferenceModeScope {
    ReferenceModeScope() { detail::tReferenceMode = true; }
    ~ReferenceModeScope() { detail::tReferenceMode = false; }
};

template <class F>
ErrorCode errorCodeOf(F&& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    ADD_FAILURE() << "no raster::Error thrown";
    return ErrorCode::ShaderError;
}

}  // namespace

// ---- Point sampling and address modes -------------------------------------------------------------

TEST(TextureSample, PointPicksFloorOfUTimesWidth) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::point();
    EXPECT_EQ(t.SampleLevel(s, {0.1f, 0.25f}, 0), indexTexel(0, 0));
    EXPECT_EQ(t.SampleLevel(s, {0.25f, 0.25f}, 0), indexTexel(1, 0));  // on the edge: the texel to the right
    EXPECT_EQ(t.SampleLevel(s, {0.2499f, 0.25f}, 0), indexTexel(0, 0));
    EXPECT_EQ(t.SampleLevel(s, {0.625f, 0.5f}, 0), indexTexel(2, 1));  // texel centre / row edge
    EXPECT_EQ(t.SampleLevel(s, {0.99f, 0.99f}, 0), indexTexel(3, 1));
}

TEST(TextureSample, PointClamp) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::point(AddressMode::Clamp);
    EXPECT_EQ(t.SampleLevel(s, {1.0f, 0.25f}, 0), indexTexel(3, 0));
    EXPECT_EQ(t.SampleLevel(s, {-0.3f, 0.25f}, 0), indexTexel(0, 0));
    EXPECT_EQ(t.SampleLevel(s, {1.7f, -4.0f}, 0), indexTexel(3, 0));
    EXPECT_EQ(t.SampleLevel(s, {0.3f, 9.0f}, 0), indexTexel(1, 1));
}

TEST(TextureSample, PointWrap) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::point(AddressMode::Wrap);
    EXPECT_EQ(t.SampleLevel(s, {1.0f, 0.25f}, 0), indexTexel(0, 0));  // index 4 → 0
    EXPECT_EQ(t.SampleLevel(s, {1.1f, 0.25f}, 0), indexTexel(0, 0));
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, 0.25f}, 0), indexTexel(3, 0));  // index −1 → 3
    EXPECT_EQ(t.SampleLevel(s, {2.6f, 0.25f}, 0), indexTexel(2, 0));   // index 10 → 2
    EXPECT_EQ(t.SampleLevel(s, {0.1f, -0.2f}, 0), indexTexel(0, 1));   // row −1 → 1
}

TEST(TextureSample, PointMirror) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::point(AddressMode::Mirror);
    EXPECT_EQ(t.SampleLevel(s, {1.1f, 0.25f}, 0), indexTexel(3, 0));   // 4 → 3
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, 0.25f}, 0), indexTexel(0, 0));  // −1 → 0
    EXPECT_EQ(t.SampleLevel(s, {1.6f, 0.25f}, 0), indexTexel(1, 0));   // 6 → 1
    EXPECT_EQ(t.SampleLevel(s, {2.1f, 0.25f}, 0), indexTexel(0, 0));   // 8 → 0: period 8
    EXPECT_EQ(t.SampleLevel(s, {0.1f, -0.2f}, 0), indexTexel(0, 0));   // row −1 → 0
}

TEST(TextureSample, PointMirrorOnce) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::point(AddressMode::MirrorOnce);
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, 0.25f}, 0), indexTexel(0, 0));  // −1 → 0
    EXPECT_EQ(t.SampleLevel(s, {-0.6f, 0.25f}, 0), indexTexel(2, 0));  // −3 → 2
    EXPECT_EQ(t.SampleLevel(s, {-1.5f, 0.25f}, 0), indexTexel(3, 0));  // −6 → 5 → clamped 3
    EXPECT_EQ(t.SampleLevel(s, {1.6f, 0.25f}, 0), indexTexel(3, 0));   // 6 → clamped 3 (Mirror: 1)
}

TEST(TextureSample, PointBorder) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = withBorder(SamplerState::point(AddressMode::Border));
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, 0.25f}, 0), kBorder);
    EXPECT_EQ(t.SampleLevel(s, {1.0f, 0.25f}, 0), kBorder);
    EXPECT_EQ(t.SampleLevel(s, {0.5f, 1.0f}, 0), kBorder);
    EXPECT_EQ(t.SampleLevel(s, {0.99f, 0.75f}, 0), indexTexel(3, 1));
    EXPECT_EQ(t.SampleLevel(s, {0.0f, 0.0f}, 0), indexTexel(0, 0));
}

TEST(TextureSample, AddressModesAreIndependentPerAxis) {
    const Texture2D t = indexTexture4x2();
    SamplerState s = SamplerState::point();
    s.addressU = AddressMode::Wrap;
    s.addressV = AddressMode::Clamp;
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, -0.2f}, 0), indexTexel(3, 0));
    s.addressU = AddressMode::Clamp;
    s.addressV = AddressMode::Wrap;
    EXPECT_EQ(t.SampleLevel(s, {-0.1f, -0.2f}, 0), indexTexel(0, 1));
}

// ---- Bilinear sampling ------------------------------------------------------------------------------

TEST(TextureSample, BilinearInteriorMixesFourTexels) {
    const Texture2D t = indexTexture4x2();
    // a = 5/16·4 − 0.5 = 0.75, b = 3/8·2 − 0.5 = 0.25: texels (0..1, 0..1), α = 0.75, β = 0.25.
    // top = (0.75, 0, 1.75, 0.75), bottom = (0.75, 1, 5.75, 0.75); x² reads 0.75, not 0.5625.
    EXPECT_EQ(t.SampleLevel(SamplerState::linear(), {5 / 16.0f, 3 / 8.0f}, 0),
              glm::vec4(0.75f, 0.25f, 2.75f, 0.75f));
    // On a texel edge in u, a row centre in v: the two texels' mean.
    EXPECT_EQ(t.SampleLevel(SamplerState::linear(), {0.25f, 0.25f}, 0), glm::vec4(0.5f, 0, 1.5f, 0.5f));
    // On a row edge in v: the two rows' mean.
    EXPECT_EQ(t.SampleLevel(SamplerState::linear(), {0.125f, 0.5f}, 0), glm::vec4(0, 0.5f, 3.0f, 0));
}

TEST(TextureSample, BilinearClamp) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::bilinear(AddressMode::Clamp);
    EXPECT_EQ(t.SampleLevel(s, {0.0f, 0.25f}, 0), indexTexel(0, 0));  // −1 and 0 both clamp to 0
    EXPECT_EQ(t.SampleLevel(s, {15 / 16.0f, 0.25f}, 0), indexTexel(3, 0));
    EXPECT_EQ(t.SampleLevel(s, {-5.0f, 0.25f}, 0), indexTexel(0, 0));
    EXPECT_EQ(t.SampleLevel(s, {7.0f, 3.0f}, 0), indexTexel(3, 1));
    EXPECT_EQ(t.SampleLevel(s, {0.125f, 0.0f}, 0), indexTexel(0, 0));
}

TEST(TextureSample, BilinearWrapBlendsLastWithFirst) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::bilinear(AddressMode::Wrap);
    // u = 0: a = −0.5, texels 3 and 0, α = 0.5: (3 + 0)/2, (4 + 1)/2, (9 + 0)/2.
    EXPECT_EQ(t.SampleLevel(s, {0.0f, 0.25f}, 0), glm::vec4(1.5f, 0, 2.5f, 4.5f));
    // u = 17/16: a = 3.75, texels 3 and 0, α = 0.75: 3 − 3·0.75, 4 − 3·0.75, 9 − 9·0.75.
    EXPECT_EQ(t.SampleLevel(s, {17 / 16.0f, 0.25f}, 0), glm::vec4(0.75f, 0, 1.75f, 2.25f));
    // v = 0: b = −0.5, rows 1 and 0, β = 0.5.
    EXPECT_EQ(t.SampleLevel(s, {0.125f, 0.0f}, 0), glm::vec4(0, 0.5f, 3.0f, 0));
}

TEST(TextureSample, BilinearMirror) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::bilinear(AddressMode::Mirror);
    // u = −3/16: a = −1.25, texels −2 → 1 and −1 → 0, α = 0.75.
    EXPECT_EQ(t.SampleLevel(s, {-3 / 16.0f, 0.25f}, 0), glm::vec4(0.25f, 0, 1.25f, 0.25f));
    // u = 19/16: a = 4.25, texels 4 → 3 and 5 → 2, α = 0.25.
    EXPECT_EQ(t.SampleLevel(s, {19 / 16.0f, 0.25f}, 0), glm::vec4(2.75f, 0, 3.75f, 7.75f));
    // u = −21/16: a = −5.75, texels −6 → 2 and −5 → 3, α = 0.25.
    EXPECT_EQ(t.SampleLevel(s, {-21 / 16.0f, 0.25f}, 0), glm::vec4(2.25f, 0, 3.25f, 5.25f));
    EXPECT_EQ(t.SampleLevel(s, {0.125f, 0.0f}, 0), indexTexel(0, 0));  // rows −1 → 0 and 0
}

TEST(TextureSample, BilinearMirrorOnce) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = SamplerState::bilinear(AddressMode::MirrorOnce);
    EXPECT_EQ(t.SampleLevel(s, {-3 / 16.0f, 0.25f}, 0), glm::vec4(0.25f, 0, 1.25f, 0.25f));  // as Mirror
    // u = −21/16: texels −6 → 5 and −5 → 4, both clamped to 3 (Mirror would read 2 and 3).
    EXPECT_EQ(t.SampleLevel(s, {-21 / 16.0f, 0.25f}, 0), indexTexel(3, 0));
    EXPECT_EQ(t.SampleLevel(s, {19 / 16.0f, 0.25f}, 0), indexTexel(3, 0));
}

TEST(TextureSample, BilinearBorderMixesBorderColourPerTexel) {
    const Texture2D t = indexTexture4x2();
    const SamplerState s = withBorder(SamplerState::bilinear(AddressMode::Border));
    // u = 0, v = 1/4: texel −1 is border, texel 0 is (0, 0, 1, 0), α = 0.5, β = 0.
    EXPECT_EQ(t.SampleLevel(s, {0.0f, 0.25f}, 0), glm::vec4(-0.5f, -1.0f, -1.0f, -2.0f));
    // The corner (0, 0): three border texels and texel (0, 0), each weighted 1/4.
    EXPECT_EQ(t.SampleLevel(s, {0.0f, 0.0f}, 0), glm::vec4(-0.75f, -1.5f, -2.0f, -3.0f));
    // Row −1 is border, column 0 in range: (border + texel (0, 0)) / 2.
    EXPECT_EQ(t.SampleLevel(s, {0.125f, 0.0f}, 0), glm::vec4(-0.5f, -1.0f, -1.0f, -2.0f));
    EXPECT_EQ(t.SampleLevel(s, {3.0f, 0.25f}, 0), kBorder);
    EXPECT_EQ(t.SampleLevel(s, {5 / 16.0f, 3 / 8.0f}, 0), glm::vec4(0.75f, 0.25f, 2.75f, 0.75f));
}

TEST(TextureSample, LinearAtTexelCentreReturnsTheTexelExactly) {
    const std::vector<uint8_t> bytes = scrambledBytes(8 * 4 * 4);
    const Texture2D t = Texture2D::fromRgba8(8, 4, bytes);
    for (AddressMode mode : {AddressMode::Wrap, AddressMode::Mirror, AddressMode::Clamp, AddressMode::Border,
                             AddressMode::MirrorOnce})
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 8; ++i) {
                const glm::vec2 uv{(i + 0.5f) / 8, (j + 0.5f) / 4};
                const size_t k = 4 * size_t(j * 8 + i);
                const glm::vec4 expected(unorm8ToFloat(bytes[k]), unorm8ToFloat(bytes[k + 1]),
                                         unorm8ToFloat(bytes[k + 2]), unorm8ToFloat(bytes[k + 3]));
                EXPECT_EQ(t.SampleLevel(SamplerState::linear(mode), uv, 0), expected) << i << "," << j;
                EXPECT_EQ(t.Sample(SamplerState::bilinear(mode), uv), expected) << i << "," << j;
                EXPECT_EQ(t.load(i, j), expected);
            }
}

// ---- The fixed-point filter of one-level RGBA8 textures under Clamp (texture.hpp, "Precision") ------

// Random texel bytes, so that neighbours differ by up to 255.
std::vector<uint8_t> randomBytes(size_t n, std::mt19937& rng) {
    std::vector<uint8_t> bytes(n);
    for (auto& b : bytes) b = uint8_t(rng());
    return bytes;
}

// The float formula's texel indices for coordinate x on an axis of n texels, clamped.
std::pair<int, int> clampedPair(float x, int n) {
    const int i = int(std::floor(std::clamp(x * float(n) - 0.5f, -16777216.0f, 16777216.0f)));
    return {std::clamp(i, 0, n - 1), std::clamp(i + 1, 0, n - 1)};
}

TEST(TextureFootprint, WithinItsDocumentedBoundOfTheExactFilter) {
    // Random bytes, so that neighbours differ by up to 255: the bound is tested where it is widest.
    constexpr int kW = 16, kH = 8;
    std::mt19937 rng(11);
    const std::vector<uint8_t> bytes = randomBytes(kW * kH * 4, rng);
    const Texture2D t = Texture2D::fromRgba8(kW, kH, bytes);
    const SamplerState s = SamplerState::bilinear(AddressMode::Clamp);
    std::uniform_real_distribution<float> d(-0.2f, 1.2f);
    double worst_ratio = 0, worst = 0;
    for (int k = 0; k < 20000; ++k) {
        const glm::vec2 uv{d(rng), d(rng)};
        const glm::vec4 fixed = t.Sample(s, uv);
        glm::vec4 exact;
        {
            ReferenceModeScope scope;
            exact = t.Sample(s, uv);
        }
        const auto [x0, x1] = clampedPair(uv.x, kW);
        const auto [y0, y1] = clampedPair(uv.y, kH);
        for (int c = 0; c < 4; ++c) {
            const auto at = [&](int x, int y) { return int(bytes[size_t(4 * (y * kW + x) + c)]); };
            const int du = std::max(std::abs(at(x1, y0) - at(x0, y0)), std::abs(at(x1, y1) - at(x0, y1)));
            const int dv = std::max({std::abs(at(x0, y1) - at(x0, y0)), std::abs(at(x1, y1) - at(x1, y0))});
            const double bound = (du / 256.0 + dv / 32768.0) / 255.0 + std::ldexp(1.0, -22);
            const double error = std::abs(double(fixed[c]) - double(exact[c]));
            ASSERT_LE(error, bound) << "uv " << uv.x << "," << uv.y << " channel " << c;
            worst = std::max(worst, error);
            worst_ratio = std::max(worst_ratio, error / bound);
        }
    }
    // Not a looser filter than documented either: α really is rounded to 1/256, so the error
    // reaches well over a third of an 8-bit step somewhere.
    EXPECT_GT(worst * 255, 0.35);
    EXPECT_GT(worst_ratio, 0.5);
}

TEST(TextureFootprint, WeightsAreStepsOf1Over256AndTheSumIsExact) {
    // Along u at the row centre (β = 0): a = α·256 exactly for u = (i + 0.5 + k/256)/W, and the
    // result is ((256 − k)·t0 + k·t1)/256 bytes, rounded once to float.
    const std::vector<uint8_t> bytes = {0, 10, 200, 255, 255, 30, 0, 1};  // 2×1: texel 0, texel 1
    const Texture2D t = Texture2D::fromRgba8(2, 1, bytes);
    const SamplerState s = SamplerState::bilinear(AddressMode::Clamp);
    for (int k = 0; k < 256; ++k) {
        const glm::vec2 uv{(0.5f + float(k) / 256.0f) / 2.0f, 0.5f};
        const glm::vec4 c = t.Sample(s, uv);
        for (int ch = 0; ch < 4; ++ch) {
            const double expected = ((256 - k) * bytes[size_t(ch)] + k * bytes[size_t(4 + ch)]) / 256.0 / 255.0;
            EXPECT_NEAR(c[ch], expected, 1e-7) << k << " " << ch;
        }
    }
    // α above 255.5/256 rounds to 255/256, not to the right texel.
    const glm::vec4 near_one = t.Sample(s, {(0.5f + 0.999f) / 2.0f, 0.5f});
    EXPECT_NEAR(near_one.x, 255.0 * 255 / 256 / 255, 1e-7);
    // Outside the texture both texels of a pair clamp to the edge one: exact.
    EXPECT_EQ(t.Sample(s, {-3.0f, 0.5f}), t.load(0, 0));
    EXPECT_EQ(t.Sample(s, {7.0f, -2.0f}), t.load(1, 0));
}

// Two 4×2 blocks side by side in one call (Float8x2, the billboards' pair) against each lane's
// scalar sample, on coordinates laid out as a screen-aligned rectangle's: u grows with the pixel's
// column and v with its row. With AVX-512 the pair reads each row's footprints from one 16-wide
// window when its eight pixels span fewer than 16 footprints and lane by lane otherwise, so the
// scales below cover both (0.25 to 1.9 texels a pixel fit, 2.5 and more do not; a mirrored u
// never fits), at every offset including windows that begin at the last footprints of the texture,
// and clamped or NaN coordinates.
TEST(TextureFootprint, PairOfBlocksOnARectangleIsEveryLanesScalarSample) {
    constexpr int kW = 64, kH = 32;
    std::mt19937 rng(29);
    const Texture2D t = Texture2D::fromRgba8(kW, kH, randomBytes(kW * kH * 4, rng));
    const SamplerState s = SamplerState::bilinear(AddressMode::Clamp);
    std::uniform_real_distribution<float> origin(-0.3f, 1.3f);
    int checked = 0, mismatches = 0;
    for (const float texels_per_pixel : {0.25f, 1.0f, 1.7f, 1.9f, 2.5f, 6.0f, -1.0f}) {
        for (int round = 0; round < 400; ++round) {
            const float du = texels_per_pixel / kW, dv = std::abs(texels_per_pixel) / kH;
            float u0 = origin(rng), v0 = origin(rng);
            if (round % 50 == 0) u0 = 1.0f - 8 * du, v0 = 1.0f;  // the last footprints of the last row
            if (round % 50 == 1) u0 = std::numeric_limits<float>::quiet_NaN();
            glm::vec<2, Float8x2> uv;
            for (int lane = 0; lane < 16; ++lane) {
                const int px = (lane & 3) + 4 * (lane >> 3), py = (lane >> 2) & 1;
                uv.x.h[lane >> 3].set(lane & 7, u0 + (float(px) + 0.5f) * du);
                uv.y.h[lane >> 3].set(lane & 7, v0 + (float(py) + 0.5f) * dv);
            }
            const glm::vec<4, Float8x2> pair = t.Sample(s, uv);
            for (int lane = 0; lane < 16; ++lane) {
                const glm::vec4 expected = t.Sample(s, glm::vec2(uv.x[lane], uv.y[lane]));
                for (int c = 0; c < 4; ++c) {
                    ++checked;
                    if (std::bit_cast<uint32_t>(pair[c][lane]) != std::bit_cast<uint32_t>(expected[c]) &&
                        ++mismatches <= 5)
                        ADD_FAILURE() << "scale " << texels_per_pixel << " lane " << lane << " uv "
                                      << uv.x[lane] << "," << uv.y[lane] << " channel " << c;
                }
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(checked, 7 * 400 * 16 * 4);
}

TEST(TextureFootprint, OnlyOneLevelRgba8ClampLinearIsFixedPoint) {
    // The same bytes as floats, with mips, or under Wrap keep the float formula, bit for bit.
    std::mt19937 rng(5);
    std::vector<uint8_t> bytes(8 * 4 * 4);
    for (auto& b : bytes) b = uint8_t(rng());
    std::vector<float> floats(bytes.size());
    for (size_t k = 0; k < bytes.size(); ++k) floats[k] = unorm8ToFloat(bytes[k]);
    const Texture2D unorm = Texture2D::fromRgba8(8, 4, bytes), real = Texture2D::fromRgba32f(8, 4, floats);
    const Texture2D mipped = Texture2D::fromRgba8(8, 4, bytes, true);
    const SamplerState clamp = SamplerState::bilinear(AddressMode::Clamp);
    const SamplerState wrap = SamplerState::bilinear(AddressMode::Wrap);
    int differ = 0;
    for (int k = 0; k < 200; ++k) {
        const glm::vec2 uv{0.013f + 0.0049f * k, 0.97f - 0.0047f * k};
        differ += unorm.Sample(clamp, uv) != real.Sample(clamp, uv);
        EXPECT_EQ(unorm.Sample(wrap, uv), real.Sample(wrap, uv)) << k;
        EXPECT_EQ(mipped.SampleLevel(clamp, uv, 0), real.Sample(clamp, uv)) << k;
    }
    EXPECT_GT(differ, 100) << "the one-level RGBA8 clamp case should take the fixed-point filter";
}

TEST(TextureSample, NanAndHugeCoordinatesStayInBounds) {
    const Texture2D t = Texture2D::fromRgba8(4, 2, scrambledBytes(32), true);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (AddressMode mode : {AddressMode::Wrap, AddressMode::Mirror, AddressMode::Clamp, AddressMode::Border,
                             AddressMode::MirrorOnce})
        for (const SamplerState& s : {SamplerState::point(mode), SamplerState::linear(mode)})
            for (glm::vec2 uv : {glm::vec2(nan, 0.5f), glm::vec2(0.5f, nan), glm::vec2(inf, -inf),
                                 glm::vec2(1e30f, -1e30f), glm::vec2(-3e9f, 7e8f)}) {
                const glm::vec4 c = t.Sample(s, uv);
                const glm::vec4 d = t.SampleLevel(s, uv, nan);
                const glm::vec4 e = t.SampleGrad(s, uv, {nan, 0}, {inf, nan});
                for (int k = 0; k < 4; ++k) {
                    EXPECT_TRUE(std::isfinite(c[k]) && std::isfinite(d[k]) && std::isfinite(e[k]));
                }
            }
}

// ---- Mip chain ----------------------------------------------------------------------------------------

// The union of two rows' spans, as the sparse table and its queries take it: the least first and
// the greatest last, so that a row of alpha 0 only (first > last, as {width, −1}) adds nothing.
TEST(TextureAlphaSpans, UniteTakesTheLeastFirstAndTheGreatestLast) {
    using Span = Texture2D::AlphaSpan;
    EXPECT_EQ((Span{3, 9}.unite(Span{5, 12})), (Span{3, 12}));
    EXPECT_EQ((Span{5, 12}.unite(Span{3, 9})), (Span{3, 12}));
    EXPECT_EQ((Span{4, 6}.unite(Span{0, 63})), (Span{0, 63}));
    const Span clear{64, -1};
    EXPECT_EQ(clear.unite(Span{7, 8}), (Span{7, 8}));
    EXPECT_EQ((Span{7, 8}.unite(clear)), (Span{7, 8}));
    const Span both_clear = clear.unite(clear);
    EXPECT_GT(both_clear.first, both_clear.last);
}

// Per texel row, the first and last column of non-zero alpha (NaN counts as non-zero), and the
// union of any run of rows r0..r1 from alphaSpanOfRows, all against a brute-force scan: sizes with
// and without a power of two of rows, rows transparent throughout, one-texel textures.
TEST(TextureAlphaSpans, RowsAndEveryRunOfRowsMatchAScan) {
    std::mt19937 rng(11);
    for (const auto& size : {std::pair{1u, 1u}, {1u, 9u}, {9u, 1u}, {7u, 13u}, {16u, 16u}, {5u, 33u}, {64u, 64u}}) {
        // Not a structured binding: the lambda below captures w, which clang 14 cannot (P1091).
        const uint32_t w = size.first, h = size.second;
        std::vector<float> rgba(size_t(w) * h * 4, 1.0f);
        for (uint32_t y = 0; y < h; ++y) {
            const bool clear_row = rng() % 4 == 0;
            for (uint32_t x = 0; x < w; ++x) {
                float& a = rgba[(size_t(y) * w + x) * 4 + 3];
                const uint32_t pick = rng() % 8;
                a = clear_row || pick < 5 ? 0.0f : pick == 5 ? std::nanf("") : 0.5f;
            }
        }
        const Texture2D t = Texture2D::fromRgba32f(w, h, rgba, false);
        ASSERT_EQ(t.alphaSpans().size(), size_t(h));
        auto scan = [&](uint32_t r0, uint32_t r1) {
            Texture2D::AlphaSpan s{int32_t(w), -1};
            for (uint32_t y = r0; y <= r1; ++y)
                for (uint32_t x = 0; x < w; ++x)
                    if (!(rgba[(size_t(y) * w + x) * 4 + 3] == 0.0f))
                        s.first = std::min(s.first, int32_t(x)), s.last = std::max(s.last, int32_t(x));
            return s;
        };
        for (uint32_t y = 0; y < h; ++y) EXPECT_EQ(t.alphaSpans()[y], scan(y, y)) << w << "x" << h << " row " << y;
        for (uint32_t r0 = 0; r0 < h; ++r0)
            for (uint32_t r1 = r0; r1 < h; ++r1) {
                const Texture2D::AlphaSpan got = t.alphaSpanOfRows(int32_t(r0), int32_t(r1)), want = scan(r0, r1);
                ASSERT_EQ(got, want) << w << "x" << h << " rows " << r0 << ".." << r1 << ": " << got.first << ","
                                     << got.last << " for " << want.first << "," << want.last;
            }
    }
    // With mipmaps there are no spans.
    const std::vector<uint8_t> texels(8 * 8 * 4, 255);
    EXPECT_TRUE(Texture2D::fromRgba8(8, 8, texels, true).alphaSpans().empty());
    EXPECT_EQ(Texture2D::fromRgba8(8, 8, texels, false).alphaSpanOfRows(0, 7), (Texture2D::AlphaSpan{0, 7}));
}

TEST(TextureMips, ChainSizesHalveDownToOneByOne) {
    const Texture2D a = Texture2D::fromRgba8(8, 4, scrambledBytes(8 * 4 * 4), true);
    ASSERT_EQ(a.mipLevels(), 4u);
    const uint32_t aw[] = {8, 4, 2, 1}, ah[] = {4, 2, 1, 1};
    for (uint32_t l = 0; l < 4; ++l) {
        EXPECT_EQ(a.width(l), aw[l]) << l;
        EXPECT_EQ(a.height(l), ah[l]) << l;
    }
    const Texture2D b = Texture2D::fromRgba8(5, 3, scrambledBytes(5 * 3 * 4), true);
    ASSERT_EQ(b.mipLevels(), 3u);
    const uint32_t bw[] = {5, 2, 1}, bh[] = {3, 1, 1};
    for (uint32_t l = 0; l < 3; ++l) {
        EXPECT_EQ(b.width(l), bw[l]) << l;
        EXPECT_EQ(b.height(l), bh[l]) << l;
    }
    EXPECT_EQ(Texture2D::fromRgba8(16, 2, scrambledBytes(16 * 2 * 4), true).mipLevels(), 5u);
    EXPECT_EQ(Texture2D::fromRgba8(1, 1, scrambledBytes(4), true).mipLevels(), 1u);
    EXPECT_EQ(Texture2D::fromRgba8(8, 4, scrambledBytes(8 * 4 * 4), false).mipLevels(), 1u);
    EXPECT_EQ(errorCodeOf([&] { (void)a.width(4); }), ErrorCode::InvalidArgument);
}

TEST(TextureMips, PowerOfTwoLevelsAreTwoByTwoBoxAverages) {
    // r = 10x + 40y, g = 4x², b = 200 on odd x + y, a = 255: every 2×2 mean is a whole number.
    std::vector<uint8_t> bytes;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x)
            bytes.insert(bytes.end(),
                         {uint8_t(10 * x + 40 * y), uint8_t(4 * x * x), uint8_t((x + y) % 2 * 200), 255});
    const Texture2D t = Texture2D::fromRgba8(8, 4, bytes, true);
    // Level 1 texel (X, Y) averages x ∈ {2X, 2X+1}, y ∈ {2Y, 2Y+1}: r = 20X + 80Y + 25, g = 16X² + 8X + 2.
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            EXPECT_EQ(loadBytes(t, x, y, 1),
                      glm::ivec4(20 * x + 80 * y + 25, 16 * x * x + 8 * x + 2, 100, 255))
                << x << "," << y;
        }
    // Level 2 (2×1): r = 40X + 75, g = 64X² + 48X + 14.
    EXPECT_EQ(loadBytes(t, 0, 0, 2), glm::ivec4(75, 14, 100, 255));
    EXPECT_EQ(loadBytes(t, 1, 0, 2), glm::ivec4(115, 126, 100, 255));
    // Level 3 (1×1) is the mean of level 0.
    glm::dvec4 mean(0.0);
    for (size_t k = 0; k < bytes.size(); k += 4)
        mean += glm::dvec4(bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]) / 32.0;
    EXPECT_EQ(mean, glm::dvec4(95, 70, 100, 255));
    EXPECT_EQ(loadBytes(t, 0, 0, 3), glm::ivec4(mean));
}

TEST(TextureMips, OddSizesUseExactAreaWeights) {
    // 5×3 float, texel (x, y) = (x, y, x², 1). 5 → 2 weights columns 0.4 0.4 0.2 | 0.2 0.4 0.4; 3 → 1 weights
    // rows 1/3 each.
    std::vector<float> rgba;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) rgba.insert(rgba.end(), {float(x), float(y), float(x * x), 1.0f});
    const Texture2D t = Texture2D::fromRgba32f(5, 3, rgba, true);
    const glm::vec4 l10 = t.load(0, 0, 1), l11 = t.load(1, 0, 1), l2 = t.load(0, 0, 2);
    EXPECT_NEAR(l10.x, 0.4f * 1 + 0.2f * 2, 1e-6f);
    EXPECT_NEAR(l11.x, 0.2f * 2 + 0.4f * 3 + 0.4f * 4, 1e-6f);
    EXPECT_NEAR(l10.y, 1.0f, 1e-6f);
    EXPECT_NEAR(l10.z, 0.4f * 1 + 0.2f * 4, 1e-6f);
    EXPECT_NEAR(l11.z, 0.2f * 4 + 0.4f * 9 + 0.4f * 16, 1e-5f);
    EXPECT_NEAR(l10.w, 1.0f, 1e-6f);
    // The mean survives odd sizes: mean x = 2, mean x² = 6, mean y = 1.
    EXPECT_NEAR(l2.x, 2.0f, 1e-6f);
    EXPECT_NEAR(l2.y, 1.0f, 1e-6f);
    EXPECT_NEAR(l2.z, 6.0f, 1e-5f);
    EXPECT_EQ(t.load(2, 0, 1), glm::vec4(0));  // out of range at level 1
}

TEST(TextureMips, OddUnormLevelRoundsTheWeightedMean) {
    // 3×1 → 1×1: a third each. (0 + 30 + 90)/3 = 40; (1 + 2 + 2)/3 = 1.67 → 2; (255·3)/3 = 255.
    const std::vector<uint8_t> bytes = {0, 1, 255, 255, 30, 2, 255, 255, 90, 2, 255, 255};
    const Texture2D t = Texture2D::fromRgba8(3, 1, bytes, true);
    ASSERT_EQ(t.mipLevels(), 2u);
    EXPECT_EQ(loadBytes(t, 0, 0, 1), glm::ivec4(40, 2, 255, 255));
    EXPECT_EQ(t.load(0, 0, 1).x, unorm8ToFloat(40));
}

// ---- Level of detail -----------------------------------------------------------------------------------

TEST(TextureLod, SampleLevelAtIntegerLevels) {
    const Texture2D t = rampTexture4x4();
    ASSERT_EQ(t.mipLevels(), 3u);
    const SamplerState s = SamplerState::linear();
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0), glm::vec4(0, 0, 0, 1));
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1), glm::vec4(0.5f, 0.5f, 0, 1));
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 2), glm::vec4(1.5f, 1.5f, 0, 1));
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 7), glm::vec4(1.5f, 1.5f, 0, 1));  // clamped to the last level
    EXPECT_EQ(t.SampleLevel(s, kRampUv, -3), glm::vec4(0, 0, 0, 1));       // magnification: level 0
}

TEST(TextureLod, TrilinearBlendsTwoLevelsByFraction) {
    const Texture2D t = rampTexture4x4();
    const SamplerState s = SamplerState::linear();
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0.25f).x, 0.125f);  // 0 + (0.5 − 0)·0.25
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1.5f).x, 1.0f);     // 0.5 + (1.5 − 0.5)·0.5
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1.75f).y, 1.25f);
}

TEST(TextureLod, PointMipFilterRoundsToNearestTiesUp) {
    const Texture2D t = rampTexture4x4();
    const SamplerState s = SamplerState::bilinear();
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0.49f).x, 0.0f);
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0.5f).x, 0.5f);  // the tie goes to the coarser level
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1.49f).x, 0.5f);
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1.5f).x, 1.5f);
    // Point filtering within the level too: level 1's texel 0 (r = 0.5), level 2's only texel (1.5).
    EXPECT_EQ(t.SampleLevel(SamplerState::point(), {0.4f, 0.4f}, 1.2f).x, 0.5f);
    EXPECT_EQ(t.SampleLevel(SamplerState::point(), {0.4f, 0.4f}, 1.6f).x, 1.5f);
}

TEST(TextureLod, SampleGradPicksLevelFromLongestGradient) {
    const Texture2D t = rampTexture4x4();
    const SamplerState s = SamplerState::linear();
    // ddx = (2/W, 0): two texels a pixel, λ = 1.
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.5f, 0}, {0, 0}).x, 0.5f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0, 0}, {0, 0.5f}).x, 0.5f);
    // The longer of the two decides: |ddy·size| = 4 → λ = 2.
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.5f, 0}, {0, 1.0f}).x, 1.5f);
    // A diagonal gradient by its length: (1.2, 1.6) texels, length 2 → λ = 1.
    EXPECT_NEAR(t.SampleGrad(s, kRampUv, {0.3f, 0.4f}, {0, 0}).x, 0.5f, 1e-5f);
    // √2 texels: λ = 0.5, halfway between levels 0 and 1.
    EXPECT_NEAR(t.SampleGrad(s, kRampUv, {std::sqrt(2.0f) / 4, 0}, {0, 0}).x, 0.25f, 1e-5f);
    // One texel a pixel or less: magnification, level 0.
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.25f, 0}, {0, 0.25f}).x, 0.0f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.01f, 0}, {0, 0.01f}).x, 0.0f);
}

TEST(TextureLod, ZeroOrNanGradientsGiveMinLod) {
    const Texture2D t = rampTexture4x4();
    SamplerState s = SamplerState::linear();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0, 0}, {0, 0}).x, 0.0f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {nan, nan}, {nan, 0}).x, 0.0f);
    s.minLod = 1.0f;
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0, 0}, {0, 0}).x, 0.5f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {nan, 0}, {0, nan}).x, 0.5f);
    s.mipLodBias = 1.0f;  // −∞ + bias is still −∞: the clamp, not the bias, decides
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0, 0}, {0, 0}).x, 0.5f);
}

TEST(TextureLod, BiasAndClampsApply) {
    const Texture2D t = rampTexture4x4();
    SamplerState s = SamplerState::linear();
    s.mipLodBias = 1.0f;
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0).x, 0.5f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.5f, 0}, {0, 0}).x, 1.5f);  // λ = 1 + 1
    s.mipLodBias = -1.0f;
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1.25f).x, 0.125f);  // λ = 0.25
    s = SamplerState::linear();
    s.maxLod = 1.0f;
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 2).x, 0.5f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {4.0f, 0}, {0, 0}).x, 0.5f);
    s.maxLod = std::numeric_limits<float>::max();  // D3D11_FLOAT32_MAX
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 1e30f).x, 1.5f);
    s = SamplerState::linear();
    s.minLod = 1.5f;
    EXPECT_EQ(t.SampleLevel(s, kRampUv, 0).x, 1.0f);
    EXPECT_EQ(t.SampleGrad(s, kRampUv, {0.25f, 0}, {0, 0}).x, 1.0f);
}

TEST(TextureLod, MagFilterWhenLambdaAtMostZeroElseMinFilter) {
    const Texture2D t = rampTexture4x4();
    SamplerState s = SamplerState::linear();
    s.minFilter = Filter::Point;  // mag stays Linear
    // At u = 1/4 on level 0 (a = 0.5): linear reads (0 + 1)/2, point reads texel floor(1.0) = 1.
    const glm::vec2 uv{0.25f, 0.125f};
    EXPECT_EQ(t.SampleLevel(s, uv, 0).x, 0.5f);
    EXPECT_EQ(t.SampleLevel(s, uv, -1).x, 0.5f);
    // λ = 0.25 minifies: point on levels 0 (r = 1) and 1 (texel 0, r = 0.5), blended by 0.25.
    EXPECT_EQ(t.SampleLevel(s, uv, 0.25f).x, 0.875f);
    // One level: λ > 0 is still minification, at level 0.
    const Texture2D one =
        Texture2D::fromRgba32f(4, 1, std::vector<float>{0, 0, 0, 1, 1, 0, 0, 1, 2, 0, 0, 1, 3, 0, 0, 1});
    EXPECT_EQ(one.SampleLevel(s, uv, 3).x, 1.0f);
    EXPECT_EQ(one.SampleLevel(s, uv, 0).x, 0.5f);
    // minLod > 0 forces minification even with zero derivatives.
    s.minLod = 0.5f;
    EXPECT_EQ(one.SampleGrad(s, uv, {0, 0}, {0, 0}).x, 1.0f);
}

// ---- Sample and the quad context ----------------------------------------------------------------------

TEST(TextureSample, WithoutQuadContextUsesLodZero) {
    ASSERT_EQ(detail::tCurrentQuad, nullptr);
    const Texture2D t = rampTexture4x4();
    EXPECT_EQ(t.Sample(SamplerState::linear(), kRampUv), t.SampleLevel(SamplerState::linear(), kRampUv, 0));
    EXPECT_EQ(t.Sample(SamplerState::linear(), kRampUv).x, 0.0f);
    SamplerState s = SamplerState::linear();
    s.minFilter = Filter::Point;
    EXPECT_EQ(t.Sample(s, {0.25f, 0.125f}).x, 0.5f);  // mag (linear), not min (point, 1)
}

TEST(TextureSample, InsideQuadTakesLodFromDerivatives) {
    const Texture2D t = rampTexture4x4();
    detail::QuadContext quad;
    quad.pass = 1;
    quad.lane = 0;
    // Lane 1 is half a texture to the right: ddx(uv) = (0.5, 0), two texels a pixel, λ = 1.
    quad.previous[0][0] = quad.previous[2][0] = glm::vec4(kRampUv, 0, 0);
    quad.previous[1][0] = quad.previous[3][0] = glm::vec4(kRampUv + glm::vec2(0.5f, 0), 0, 0);
    detail::tCurrentQuad = &quad;
    const glm::vec4 c = t.Sample(SamplerState::linear(), kRampUv);
    const int calls = quad.call;
    detail::tCurrentQuad = nullptr;
    EXPECT_EQ(c.x, 0.5f);
    EXPECT_EQ(calls, 1);
}

TEST(TextureSample, OneLevelOneFilterMakesNoDerivativeCall) {
    const Texture2D t = indexTexture4x2();
    detail::QuadContext quad;
    quad.pass = 1;
    detail::tCurrentQuad = &quad;
    const glm::vec4 c = t.Sample(SamplerState::bilinear(), {5 / 16.0f, 3 / 8.0f});
    const bool used = quad.used;
    SamplerState minPoint = SamplerState::bilinear();
    minPoint.minFilter = Filter::Point;
    (void)t.Sample(minPoint, {0.5f, 0.5f});  // min ≠ mag: the LOD matters, so a derivative is taken
    const bool usedAfter = quad.used;
    detail::tCurrentQuad = nullptr;
    EXPECT_EQ(c, glm::vec4(0.75f, 0.25f, 2.75f, 0.75f));
    EXPECT_FALSE(used);
    EXPECT_TRUE(usedAfter);
}

// ---- Load and basic properties ---------------------------------------------------------------------

TEST(TextureLoad, OutOfRangeReadsZero) {
    const Texture2D t = indexTexture4x2();
    EXPECT_EQ(t.load(3, 1), indexTexel(3, 1));
    EXPECT_EQ(t.load(-1, 0), glm::vec4(0));
    EXPECT_EQ(t.load(4, 0), glm::vec4(0));
    EXPECT_EQ(t.load(0, 2), glm::vec4(0));
    EXPECT_EQ(t.load(0, 0, 1), glm::vec4(0));
    EXPECT_EQ(t.load(0, 0, -1), glm::vec4(0));
}

TEST(Texture2D, FormatsSizesAndCopies) {
    const Texture2D a = Texture2D::fromRgba8(4, 2, scrambledBytes(32));
    EXPECT_EQ(a.format(), Format::R8G8B8A8_UNORM);
    EXPECT_EQ(a.width(), 4u);
    EXPECT_EQ(a.height(), 2u);
    EXPECT_EQ(indexTexture4x2().format(), Format::R32G32B32A32_FLOAT);
    const Texture2D b = a;
    EXPECT_EQ(a, b);
    EXPECT_EQ(b.load(1, 1), a.load(1, 1));
    const Texture2D empty;
    EXPECT_TRUE(empty.empty());
    EXPECT_EQ(empty.width(), 0u);
    EXPECT_EQ(empty.Sample(SamplerState::linear(), {0.5f, 0.5f}), glm::vec4(0));
    EXPECT_EQ(empty.SampleLevel(SamplerState::linear(), {0.5f, 0.5f}, 1), glm::vec4(0));
    EXPECT_EQ(empty.load(0, 0), glm::vec4(0));
}

// ---- Files ---------------------------------------------------------------------------------------------

TEST(TextureFile, FirePngMatchesScenesFormula) {
    const Texture2D t = Texture2D::fromPng(test::sharedDir() + "/bench/fire.png");
    ASSERT_EQ(t.width(), 64u);
    ASSERT_EQ(t.height(), 64u);
    ASSERT_EQ(t.mipLevels(), 1u);
    int mismatches = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const double u = (i + 0.5) / 64, v = (j + 0.5) / 64;
            const double r = 2 * std::hypot(u - 0.5, v - 0.5);
            const double s = std::pow(std::clamp(1 - r, 0.0, 1.0), 2);
            const double expected[4] = {1, 0.25 + 0.55 * s, 0.05 + 0.15 * s, 0.25 * s};
            const glm::vec4 texel = t.load(i, j);
            for (int c = 0; c < 4; ++c) {
                const long want = std::lround(255 * expected[c]);
                const long got = floatToUnorm8(texel[c]);
                if (std::abs(got - want) > 1 && ++mismatches < 10)
                    ADD_FAILURE() << "texel " << i << "," << j << " channel " << c << ": " << got << " vs "
                                  << want;
            }
        }
    EXPECT_EQ(mismatches, 0);
    const Texture2D f = Texture2D::fromPng(test::sharedDir() + "/bench/fire.png", Format::R32G32B32A32_FLOAT);
    EXPECT_EQ(f.format(), Format::R32G32B32A32_FLOAT);
    EXPECT_EQ(f.load(17, 40), t.load(17, 40));
}

TEST(TextureFile, MissingFileIsBadFileNamingPath) {
    const std::string path = "/nonexistent/raster/no_such_texture.png";
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { Texture2D::fromPng(path); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find(path), std::string::npos) << message;
}

TEST(TextureFile, CorruptFileIsBadFileNamingPath) {
    const std::string path =
        (std::filesystem::temp_directory_path() / "raster_texture_test_corrupt.png").string();
    {
        std::ofstream out(path, std::ios::binary);
        out << "\x89PNG\r\n\x1a\n this is not a PNG stream at all \x01\x02\x03";
    }
    std::string message;
    EXPECT_EQ(errorCodeOf([&] { Texture2D::fromPng(path); }, &message), ErrorCode::BadFile);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    std::filesystem::remove(path);
}

// ---- Bad input -------------------------------------------------------------------------------------------

TEST(TextureErrors, BadSizesAndFormatsAreInvalidArgument) {
    std::string message;
    EXPECT_EQ(errorCodeOf([] { Texture2D::fromRgba8(0, 4, {}); }, &message), ErrorCode::InvalidArgument);
    EXPECT_NE(message.find("0x4"), std::string::npos) << message;
    EXPECT_EQ(errorCodeOf([] { Texture2D::fromRgba32f(3, 0, {}); }), ErrorCode::InvalidArgument);
    const std::vector<uint8_t> bytes(15);
    EXPECT_EQ(errorCodeOf([&] { Texture2D::fromRgba8(2, 2, bytes); }, &message), ErrorCode::InvalidArgument);
    EXPECT_NE(message.find("15"), std::string::npos) << message;
    EXPECT_NE(message.find("2x2"), std::string::npos) << message;
    const std::vector<float> floats(4 * 6 + 1);
    EXPECT_EQ(errorCodeOf([&] { Texture2D::fromRgba32f(3, 2, floats); }), ErrorCode::InvalidArgument);
    EXPECT_EQ(errorCodeOf([] { Texture2D::fromRgba8(Texture2D::kMaxSize + 1, 1, {}); }),
              ErrorCode::InvalidArgument);
    EXPECT_EQ(errorCodeOf([] { Texture2D::fromPng(test::sharedDir() + "/bench/fire.png", Format::D32_FLOAT); }),
              ErrorCode::InvalidArgument);
}

TEST(SamplerValidate, RefusesWhatD3D11Refuses) {
    EXPECT_NO_THROW(validate(SamplerState{}));
    EXPECT_NO_THROW(validate(SamplerState::point(AddressMode::Border)));
    SamplerState s;
    s.maxLod = std::numeric_limits<float>::max();
    s.minLod = -5.0f;
    EXPECT_NO_THROW(validate(s));

    std::string message;
    s = SamplerState{};
    s.minLod = 3.0f;
    s.maxLod = 1.0f;
    EXPECT_EQ(errorCodeOf([&] { validate(s); }, &message), ErrorCode::InvalidState);
    EXPECT_NE(message.find("minLod"), std::string::npos) << message;
    s = SamplerState{};
    s.mipLodBias = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(errorCodeOf([&] { validate(s); }, &message), ErrorCode::InvalidState);
    EXPECT_NE(message.find("mipLodBias"), std::string::npos) << message;
    s = SamplerState{};
    s.maxLod = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(errorCodeOf([&] { validate(s); }), ErrorCode::InvalidState);
    s = SamplerState{};
    s.magFilter = Filter(7);
    EXPECT_EQ(errorCodeOf([&] { validate(s); }, &message), ErrorCode::InvalidState);
    EXPECT_NE(message.find("magFilter"), std::string::npos) << message;
    s = SamplerState{};
    s.addressV = AddressMode(9);
    EXPECT_EQ(errorCodeOf([&] { validate(s); }), ErrorCode::InvalidState);
}

TEST(Sampler, FactoriesSetD3D11Filters) {
    const SamplerState p = SamplerState::point(AddressMode::Wrap);
    EXPECT_EQ(p.minFilter, Filter::Point);
    EXPECT_EQ(p.magFilter, Filter::Point);
    EXPECT_EQ(p.mipFilter, Filter::Point);
    EXPECT_EQ(p.addressU, AddressMode::Wrap);
    EXPECT_EQ(p.addressV, AddressMode::Wrap);
    const SamplerState b = SamplerState::bilinear();
    EXPECT_EQ(b.minFilter, Filter::Linear);
    EXPECT_EQ(b.magFilter, Filter::Linear);
    EXPECT_EQ(b.mipFilter, Filter::Point);
    EXPECT_EQ(b.addressU, AddressMode::Clamp);
    EXPECT_EQ(SamplerState::linear().mipFilter, Filter::Linear);
}

// ---- Reference (double) precision ---------------------------------------------------------------------

TEST(TextureReference, AgreesWithFloatPathOnUnorm) {
    const Texture2D t = Texture2D::fromRgba8(8, 4, scrambledBytes(8 * 4 * 4), true);
    for (AddressMode mode : {AddressMode::Wrap, AddressMode::Mirror, AddressMode::Clamp, AddressMode::Border,
                             AddressMode::MirrorOnce})
        for (const SamplerState& base :
             {SamplerState::point(mode), SamplerState::bilinear(mode), SamplerState::linear(mode)}) {
            const SamplerState s = withBorder(base);
            for (int k = 0; k < 40; ++k) {
                const glm::vec2 uv{-1.3f + 0.087f * k, 2.1f - 0.073f * k};
                const float lod = -0.5f + 0.11f * k;
                const glm::vec4 fast = t.SampleLevel(s, uv, lod);
                const glm::vec4 sampled = t.Sample(s, uv);
                const glm::vec4 graded = t.SampleGrad(s, uv, {0.01f * k, 0}, {0, 0.02f});
                glm::vec4 ref, refSampled, refGraded;
                {
                    ReferenceModeScope scope;
                    ref = t.SampleLevel(s, uv, lod);
                    refSampled = t.Sample(s, uv);
                    refGraded = t.SampleGrad(s, uv, {0.01f * k, 0}, {0, 0.02f});
                }
                for (int c = 0; c < 4; ++c) {
                    EXPECT_NEAR(fast[c], ref[c], 1e-6f) << k;
                    EXPECT_NEAR(sampled[c], refSampled[c], 1e-6f) << k;
                    EXPECT_NEAR(graded[c], refGraded[c], 1e-6f) << k;
                }
            }
        }
    EXPECT_FALSE(inReferenceMode());
}

TEST(TextureReference, BilinearIsExactAgainstDoubleByHand) {
    const std::vector<uint8_t> bytes = scrambledBytes(4 * 2 * 4);
    const Texture2D t = Texture2D::fromRgba8(4, 2, bytes);
    const glm::vec2 uv{0.3f, 0.7f};
    glm::vec4 ref, single;
    {
        ReferenceModeScope scope;
        ref = t.SampleLevel(SamplerState::bilinear(), uv, 0);
        single = t.Sample(SamplerState::bilinear(), uv);
    }
    // a = 0.3·4 − 0.5 = 0.7000000477 (0.3f is not 0.3), texels 0 and 1; b = 0.7·2 − 0.5, rows 0 and 1.
    const double a = double(uv.x) * 4 - 0.5, b = double(uv.y) * 2 - 0.5;
    const auto at = [&](int x, int y, int c) { return bytes[size_t(4 * (y * 4 + x) + c)] / 255.0; };
    for (int c = 0; c < 4; ++c) {
        const double top = at(0, 0, c) + (at(1, 0, c) - at(0, 0, c)) * a;
        const double bottom = at(0, 1, c) + (at(1, 1, c) - at(0, 1, c)) * a;
        const double expected = top + (bottom - top) * b;
        EXPECT_EQ(ref[c], float(expected)) << c;
        EXPECT_EQ(single[c], float(expected)) << c;
    }
}

TEST(TextureReference, TrilinearIsExactAgainstDoubleByHand) {
    // 2×2 → 1×1; at uv (1/4, 1/4), level 0's texel (0, 0) centre, λ = 0.3.
    const std::vector<uint8_t> bytes = {10, 200, 3, 255, 20, 100, 7, 255, 40, 50, 11, 255, 80, 25, 13, 255};
    const Texture2D t = Texture2D::fromRgba8(2, 2, bytes, true);
    glm::vec4 ref;
    {
        ReferenceModeScope scope;
        ref = t.SampleLevel(SamplerState::linear(), {0.25f, 0.25f}, 0.3f);
    }
    const double lambda = double(0.3f);
    // Level 1 texel, rounded to bytes: (37.5 → 38, 93.75 → 94, 8.5 → 9, 255).
    const double level1[4] = {38, 94, 9, 255};
    for (int c = 0; c < 4; ++c) {
        const double c0 = bytes[size_t(c)] / 255.0, c1 = level1[c] / 255.0;
        EXPECT_EQ(ref[c], float(c0 + (c1 - c0) * lambda)) << c;
    }
}

}  // namespace raster
