#include "raster/fastpath/blend_rgba8.hpp"
#include "raster/fastpath/merge_policy.hpp"
#include "raster/stages/9_output_merger.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "raster/check.hpp"
#include "raster/render_target.hpp"
#include "raster/states.hpp"

namespace raster {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// The fixed operands of the factor and operation tables.
const glm::vec4 kSrc(0.2f, 0.4f, 0.6f, 0.8f);
const glm::vec4 kSrc1(0.9f, 0.1f, 0.3f, 0.5f);
const glm::vec4 kDst(0.5f, 0.25f, 0.75f, 0.4f);
const glm::vec4 kFactor(0.1f, 0.2f, 0.3f, 0.4f);

RenderTargetBlendDesc blendDesc(Blend src, Blend dest, BlendOp op, Blend srcAlpha, Blend destAlpha,
                                BlendOp opAlpha) {
    RenderTargetBlendDesc d;
    d.blendEnable = true;
    d.srcBlend = src;
    d.destBlend = dest;
    d.blendOp = op;
    d.srcBlendAlpha = srcAlpha;
    d.destBlendAlpha = destAlpha;
    d.blendOpAlpha = opAlpha;
    return d;
}

RenderTargetBlendDesc blendDesc(Blend src, Blend dest, BlendOp op = BlendOp::Add) {
    return blendDesc(src, dest, op, src, dest, op);
}

void expectNear4(const glm::vec4& actual, const glm::vec4& expected, const std::string& what) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(actual[c], expected[c], 1e-6f) << what << ", channel " << c;
}

struct FactorRow {
    Blend blend;
    glm::vec4 timesSrc;  // kSrc * factor, by hand
    glm::vec4 timesDst;  // kDst * factor, by hand
};

// Factors (by hand from the operands above):
//   SrcColor (.2 .4 .6 .8), InvSrcColor (.8 .6 .4 .2), SrcAlpha .8, InvSrcAlpha .2, DestAlpha .4,
//   InvDestAlpha .6, DestColor (.5 .25 .75 .4), InvDestColor (.5 .75 .25 .6),
//   SrcAlphaSat (.6 .6 .6 1) since min(.8, 1 - .4) = .6, BlendFactor (.1 .2 .3 .4),
//   InvBlendFactor (.9 .8 .7 .6), Src1Color (.9 .1 .3 .5), InvSrc1Color (.1 .9 .7 .5), Src1Alpha .5,
//   InvSrc1Alpha .5.
const FactorRow kFactorTable[] = {
    {Blend::Zero, {0, 0, 0, 0}, {0, 0, 0, 0}},
    {Blend::One, {0.2f, 0.4f, 0.6f, 0.8f}, {0.5f, 0.25f, 0.75f, 0.4f}},
    {Blend::SrcColor, {0.04f, 0.16f, 0.36f, 0.64f}, {0.1f, 0.1f, 0.45f, 0.32f}},
    {Blend::InvSrcColor, {0.16f, 0.24f, 0.24f, 0.16f}, {0.4f, 0.15f, 0.3f, 0.08f}},
    {Blend::SrcAlpha, {0.16f, 0.32f, 0.48f, 0.64f}, {0.4f, 0.2f, 0.6f, 0.32f}},
    {Blend::InvSrcAlpha, {0.04f, 0.08f, 0.12f, 0.16f}, {0.1f, 0.05f, 0.15f, 0.08f}},
    {Blend::DestAlpha, {0.08f, 0.16f, 0.24f, 0.32f}, {0.2f, 0.1f, 0.3f, 0.16f}},
    {Blend::InvDestAlpha, {0.12f, 0.24f, 0.36f, 0.48f}, {0.3f, 0.15f, 0.45f, 0.24f}},
    {Blend::DestColor, {0.1f, 0.1f, 0.45f, 0.32f}, {0.25f, 0.0625f, 0.5625f, 0.16f}},
    {Blend::InvDestColor, {0.1f, 0.3f, 0.15f, 0.48f}, {0.25f, 0.1875f, 0.1875f, 0.24f}},
    {Blend::SrcAlphaSat, {0.12f, 0.24f, 0.36f, 0.8f}, {0.3f, 0.15f, 0.45f, 0.4f}},
    {Blend::BlendFactor, {0.02f, 0.08f, 0.18f, 0.32f}, {0.05f, 0.05f, 0.225f, 0.16f}},
    {Blend::InvBlendFactor, {0.18f, 0.32f, 0.42f, 0.48f}, {0.45f, 0.2f, 0.525f, 0.24f}},
    {Blend::Src1Color, {0.18f, 0.04f, 0.18f, 0.4f}, {0.45f, 0.025f, 0.225f, 0.2f}},
    {Blend::InvSrc1Color, {0.02f, 0.36f, 0.42f, 0.4f}, {0.05f, 0.225f, 0.525f, 0.2f}},
    {Blend::Src1Alpha, {0.1f, 0.2f, 0.3f, 0.4f}, {0.25f, 0.125f, 0.375f, 0.2f}},
    {Blend::InvSrc1Alpha, {0.1f, 0.2f, 0.3f, 0.4f}, {0.25f, 0.125f, 0.375f, 0.2f}},
};

TEST(BlendColor, EveryFactorMatchesHandTable) {
    static_assert(std::size(kFactorTable) == 17);
    for (const FactorRow& row : kFactorTable) {
        const std::string what(name(row.blend));
        // As the source factor (dest Zero) and as the destination factor (source Zero). The alpha channel
        // shows the factor's own alpha, as D3D defines it even for colour factors.
        expectNear4(blendColor(blendDesc(row.blend, Blend::Zero), kSrc, kSrc1, kDst, kFactor), row.timesSrc,
                    what + " as srcBlend");
        expectNear4(blendColor(blendDesc(Blend::Zero, row.blend), kSrc, kSrc1, kDst, kFactor), row.timesDst,
                    what + " as destBlend");
        expectNear4(glm::vec4(blendColor(blendDesc(row.blend, Blend::Zero), glm::dvec4(kSrc),
                                         glm::dvec4(kSrc1), glm::dvec4(kDst), glm::dvec4(kFactor))),
                    row.timesSrc, what + " as srcBlend, double");
    }
}

TEST(BlendColor, Src1AlphaIsNotItsInverse) {
    // The table's src1.a = 0.5 cannot tell these two apart.
    const glm::vec4 src1(0.9f, 0.1f, 0.3f, 0.25f);
    expectNear4(blendColor(blendDesc(Blend::Src1Alpha, Blend::Zero), kSrc, src1, kDst, kFactor),
                {0.05f, 0.1f, 0.15f, 0.2f}, "Src1Alpha");
    expectNear4(blendColor(blendDesc(Blend::InvSrc1Alpha, Blend::Zero), kSrc, src1, kDst, kFactor),
                {0.15f, 0.3f, 0.45f, 0.6f}, "InvSrc1Alpha");
}

TEST(BlendColor, EveryOpMatchesHandTable) {
    // Colour: src * SrcAlpha (.8) = (.16 .32 .48), dst * InvSrcAlpha (.2) = (.1 .05 .15).
    // Alpha:  src.a * InvDestAlpha (.6) = .48,   dst.a * BlendFactor.a (.4) = .16.
    struct Row {
        BlendOp op;
        glm::vec4 expected;
    };
    const Row rows[] = {
        {BlendOp::Add, {0.26f, 0.37f, 0.63f, 0.64f}},
        {BlendOp::Subtract, {0.06f, 0.27f, 0.33f, 0.32f}},
        {BlendOp::RevSubtract, {-0.06f, -0.27f, -0.33f, -0.32f}},
        {BlendOp::Min, {0.2f, 0.25f, 0.6f, 0.4f}},  // factors ignored: min(src, dst)
        {BlendOp::Max, {0.5f, 0.4f, 0.75f, 0.8f}},  // factors ignored: max(src, dst)
    };
    for (const Row& row : rows) {
        const auto d = blendDesc(Blend::SrcAlpha, Blend::InvSrcAlpha, row.op, Blend::InvDestAlpha,
                                 Blend::BlendFactor, row.op);
        expectNear4(blendColor(d, kSrc, kSrc1, kDst, kFactor), row.expected, std::string(name(row.op)));
    }
}

TEST(BlendColor, AlphaUsesItsOwnFactorsAndOp) {
    auto d = blendDesc(Blend::SrcAlpha, Blend::InvSrcAlpha, BlendOp::Add, Blend::InvDestAlpha,
                       Blend::BlendFactor, BlendOp::RevSubtract);
    expectNear4(blendColor(d, kSrc, kSrc1, kDst, kFactor), {0.26f, 0.37f, 0.63f, -0.32f},
                "Add / RevSubtract");
    d.blendOp = BlendOp::Min;
    d.blendOpAlpha = BlendOp::Add;
    expectNear4(blendColor(d, kSrc, kSrc1, kDst, kFactor), {0.2f, 0.25f, 0.6f, 0.64f}, "Min / Add");
    // One for colour, Zero for alpha and the reverse.
    expectNear4(
        blendColor(blendDesc(Blend::One, Blend::Zero, BlendOp::Add, Blend::Zero, Blend::One, BlendOp::Add),
                   kSrc, kSrc1, kDst, kFactor),
        {0.2f, 0.4f, 0.6f, 0.4f}, "colour from src, alpha from dst");
}

TEST(BlendColor, ClampsNothing) {
    const glm::vec4 src(2.0f, -1.0f, 0.5f, 3.0f), dst(1.5f, 0.5f, -2.0f, 0.5f);
    // One + One: plain sums, beyond [0, 1] both ways.
    expectNear4(blendColor(blendDesc(Blend::One, Blend::One), src, kSrc1, dst, kFactor),
                {3.5f, -0.5f, -1.5f, 3.5f}, "One + One");
    // SrcAlpha with alpha 3 is 3, not 1.
    expectNear4(blendColor(blendDesc(Blend::SrcAlpha, Blend::Zero), src, kSrc1, dst, kFactor),
                {6, -3, 1.5f, 9}, "SrcAlpha 3");
}

// ---- Depth ----------------------------------------------------------------------------------------

bool passesT(ComparisonFunc f, float fragment, float stored) {
    switch (f) {
        case ComparisonFunc::Never: return depthPassesT<ComparisonFunc::Never>(fragment, stored);
        case ComparisonFunc::Less: return depthPassesT<ComparisonFunc::Less>(fragment, stored);
        case ComparisonFunc::Equal: return depthPassesT<ComparisonFunc::Equal>(fragment, stored);
        case ComparisonFunc::LessEqual: return depthPassesT<ComparisonFunc::LessEqual>(fragment, stored);
        case ComparisonFunc::Greater: return depthPassesT<ComparisonFunc::Greater>(fragment, stored);
        case ComparisonFunc::NotEqual: return depthPassesT<ComparisonFunc::NotEqual>(fragment, stored);
        case ComparisonFunc::GreaterEqual:
            return depthPassesT<ComparisonFunc::GreaterEqual>(fragment, stored);
        case ComparisonFunc::Always: return depthPassesT<ComparisonFunc::Always>(fragment, stored);
    }
    ADD_FAILURE() << "bad ComparisonFunc";
    return false;
}

TEST(DepthTest, EveryFunctionMatchesHandTable) {
    const float pairs[][2] = {{0.25f, 0.5f}, {0.5f, 0.5f}, {0.75f, 0.5f}, {-0.0f, 0.0f},
                              {kNaN, 0.5f},  {0.5f, kNaN}, {kNaN, kNaN}};
    struct Row {
        ComparisonFunc f;
        bool expected[7];  // per pair: less, equal, greater, -0 vs +0, NaN fragment, NaN stored, both NaN
    };
    const Row rows[] = {
        {ComparisonFunc::Never, {false, false, false, false, false, false, false}},
        {ComparisonFunc::Less, {true, false, false, false, false, false, false}},
        {ComparisonFunc::Equal, {false, true, false, true, false, false, false}},
        {ComparisonFunc::LessEqual, {true, true, false, true, false, false, false}},
        {ComparisonFunc::Greater, {false, false, true, false, false, false, false}},
        {ComparisonFunc::NotEqual, {true, false, true, false, true, true, true}},
        {ComparisonFunc::GreaterEqual, {false, true, true, true, false, false, false}},
        {ComparisonFunc::Always, {true, true, true, true, true, true, true}},
    };
    for (const Row& row : rows) {
        for (int i = 0; i < 7; ++i) {
            EXPECT_EQ(depthPasses(row.f, pairs[i][0], pairs[i][1]), row.expected[i])
                << name(row.f) << " pair " << i;
            EXPECT_EQ(passesT(row.f, pairs[i][0], pairs[i][1]), row.expected[i])
                << name(row.f) << " pair " << i;
        }
    }
}

TEST(DepthTest, OutOfRangeFunctionFails) {
    EXPECT_FALSE(depthPasses(ComparisonFunc(99), 0.0f, 1.0f));
}

// ---- mergeFragment --------------------------------------------------------------------------------

std::vector<uint8_t> pixelBytes(const RenderTarget& rt, uint32_t x, uint32_t y) {
    const uint8_t* p = rt.rgba8() + 4 * (size_t(y) * rt.width() + x);
    return {p[0], p[1], p[2], p[3]};
}

template <class Real>
std::vector<uint8_t> mergeUnorm(const RenderTargetBlendDesc& d, const std::vector<uint8_t>& dst,
                                const glm::vec4& src, const glm::vec4& src1 = kSrc1,
                                const glm::vec4& factor = kFactor) {
    RenderTarget rt(2, 2);
    uint8_t* p = rt.rgba8() + 4 * 3;  // pixel (1, 1)
    for (int c = 0; c < 4; ++c) p[c] = dst[c];
    mergeFragment<Real>(rt, 1, 1, d, src, src1, factor);
    EXPECT_EQ(pixelBytes(rt, 0, 0), std::vector<uint8_t>(4, 0)) << "a neighbour changed";
    return pixelBytes(rt, 1, 1);
}

using Bytes = std::vector<uint8_t>;

TEST(MergeFragment, UnormStoreClampsAndRoundsHalfUp) {
    const RenderTargetBlendDesc off;
    const glm::vec4 src(0.5f, 1.2f, -0.1f, kNaN);
    EXPECT_EQ(mergeUnorm<float>(off, {9, 9, 9, 9}, src), (Bytes{128, 255, 0, 0}));
    EXPECT_EQ(mergeUnorm<double>(off, {9, 9, 9, 9}, src), (Bytes{128, 255, 0, 0}));
    EXPECT_EQ(mergeUnorm<float>(off, {9, 9, 9, 9}, {kInf, -kInf, 1.0f, 0.0f}), (Bytes{255, 0, 255, 0}));
    EXPECT_EQ(mergeUnorm<double>(off, {9, 9, 9, 9}, {kInf, -kInf, 1.0f, 0.0f}), (Bytes{255, 0, 255, 0}));
    // 0.25 * 255 = 63.75 -> 64; 0.75 * 255 = 191.25 -> 191.
    EXPECT_EQ(mergeUnorm<float>(off, {9, 9, 9, 9}, {0.25f, 0.75f, 0, 1}), (Bytes{64, 191, 0, 255}));
    EXPECT_EQ(mergeUnorm<double>(off, {9, 9, 9, 9}, {0.25f, 0.75f, 0, 1}), (Bytes{64, 191, 0, 255}));
}

TEST(MergeFragment, UnormReadsDestinationAsNOver255) {
    // One + One: 51/255 = 0.2, plus 0.2 is 0.4 = 102/255; plus 0 keeps 51.
    const auto add = blendDesc(Blend::One, Blend::One);
    for (auto merge : {mergeUnorm<float>, mergeUnorm<double>}) {
        EXPECT_EQ(merge(add, {51, 51, 51, 51}, {0.2f, 0.0f, 0.2f, 0.0f}, kSrc1, kFactor),
                  (Bytes{102, 51, 102, 51}));
        // Result clamped: 200/255 + 0.5 > 1 -> 255. Subtract: 0 - 100/255 < 0 -> 0.
        EXPECT_EQ(merge(add, {200, 200, 0, 0}, {0.5f, 0.5f, 0, 0}, kSrc1, kFactor), (Bytes{255, 255, 0, 0}));
        EXPECT_EQ(merge(blendDesc(Blend::One, Blend::One, BlendOp::Subtract), {100, 100, 100, 100},
                        {0.0f, 0.0f, 0.0f, 0.0f}, kSrc1, kFactor),
                  (Bytes{0, 0, 0, 0}));
    }
}

TEST(MergeFragment, UnormClampsSourceAndFactorBeforeBlending) {
    // Alpha blend of src (0.5, ., ., 2) over 51/255 = 0.2: alpha clamped to 1 gives 0.5 -> 128; unclamped
    // it would be 0.5 * 2 + 0.2 * (1 - 2) = 0.8 -> 204.
    const auto alpha = BlendState::alphaBlend().renderTarget[0];
    for (auto merge : {mergeUnorm<float>, mergeUnorm<double>}) {
        EXPECT_EQ(merge(alpha, {51, 51, 51, 51}, {0.5f, 0.5f, 0.5f, 2.0f}, kSrc1, kFactor)[0], 128);
        // BlendFactor 2 clamped to 1: 0.25 * 1 = 63.75 -> 64 (unclamped: 0.5 -> 128).
        EXPECT_EQ(merge(blendDesc(Blend::BlendFactor, Blend::Zero), {0, 0, 0, 0},
                        {0.25f, 0.25f, 0.25f, 0.25f}, kSrc1, {2.0f, 2.0f, 2.0f, 2.0f})[0],
                  64);
        // src1 clamped: (-1, 3) weigh as (0, 1), so 1 * 0 + 51 stays 51 and 1 * 1 + 51/255 saturates.
        EXPECT_EQ(merge(blendDesc(Blend::Src1Color, Blend::One), {51, 51, 51, 51}, {1, 1, 1, 1},
                        {-1.0f, 3.0f, 0.0f, 0.0f}, kFactor),
                  (Bytes{51, 255, 51, 51}));
    }
}

TEST(MergeFragment, WriteMaskKeepsChannels) {
    RenderTargetBlendDesc d;
    d.renderTargetWriteMask = 0x5;  // R and B
    EXPECT_EQ(mergeUnorm<float>(d, {1, 2, 3, 4}, {1, 1, 1, 1}), (Bytes{255, 2, 255, 4}));
    EXPECT_EQ(mergeUnorm<double>(d, {1, 2, 3, 4}, {1, 1, 1, 1}), (Bytes{255, 2, 255, 4}));
    d = blendDesc(Blend::One, Blend::One);
    d.renderTargetWriteMask = 0x8;  // A only
    EXPECT_EQ(mergeUnorm<float>(d, {1, 2, 3, 4}, {1, 1, 1, 1}), (Bytes{1, 2, 3, 255}));
    d.renderTargetWriteMask = 0;
    EXPECT_EQ(mergeUnorm<double>(d, {1, 2, 3, 4}, {1, 1, 1, 1}), (Bytes{1, 2, 3, 4}));

    RenderTarget fp(1, 1, Format::R32G32B32A32_FLOAT);
    fp.clear({5, 6, 7, 8});
    d = RenderTargetBlendDesc{};
    d.renderTargetWriteMask = 0xA;  // G and A
    mergeFragment<float>(fp, 0, 0, d, {1.5f, -2.5f, 3.5f, -4.5f}, kSrc1, kFactor);
    EXPECT_EQ(fp.load(0, 0), glm::vec4(5, -2.5f, 7, -4.5f));
}

TEST(MergeFragment, FloatTargetKeepsValuesOutsideZeroOne) {
    for (bool reference : {false, true}) {
        RenderTarget fp(1, 1, Format::R32G32B32A32_FLOAT);
        auto merge = [&](const RenderTargetBlendDesc& d, const glm::vec4& src) {
            if (reference)
                mergeFragment<double>(fp, 0, 0, d, src, kSrc1, kFactor);
            else
                mergeFragment<float>(fp, 0, 0, d, src, kSrc1, kFactor);
        };
        merge(RenderTargetBlendDesc{}, {1.5f, -0.25f, 3.0f, -1.0f});
        EXPECT_EQ(fp.load(0, 0), glm::vec4(1.5f, -0.25f, 3.0f, -1.0f));
        // One + One on top: sums not clamped.
        merge(blendDesc(Blend::One, Blend::One), {1.0f, -1.0f, 0.5f, 4.0f});
        EXPECT_EQ(fp.load(0, 0), glm::vec4(2.5f, -1.25f, 3.5f, 3.0f));
        // SrcAlpha with alpha 2 is not clamped either: 0.5 * 2 + 2.5 * (1 - 2) = -1.5.
        merge(BlendState::alphaBlend().renderTarget[0], {0.5f, 0.5f, 0.5f, 2.0f});
        EXPECT_EQ(fp.load(0, 0).x, -1.5f);
    }
}

// ---- Precision: the double path rounds once ----------------------------------------------------------

TEST(MergeFragment, DoublePathRoundsOnceWhereFloatPathRoundsTwice) {
    const RenderTargetBlendDesc off;
    // x = 0x1.0101p-9 = 65793 / 2^25; x * 255 = 16777215 / 2^25 = 0.5 - 2^-25 exactly, so the correctly
    // rounded byte is 0. In float x * 255 rounds to 0.5 and + 0.5 makes 1.
    const float x = 0x1.0101p-9f;
    EXPECT_EQ(mergeUnorm<double>(off, {9, 9, 9, 9}, {x, x, x, x})[0], 0);
    EXPECT_EQ(mergeUnorm<float>(off, {9, 9, 9, 9}, {x, x, x, x})[0], 1);

    // Alpha blend, s = 29/256, a = 53/256, d = 239/255: in bytes
    //   255 * s * a + 239 * (1 - a) = (255 * 29 * 53 + 239 * 203 * 256) / 65536 = 12812287 / 65536
    //                               = 195 + 32767/65536, just below 195.5 -> 195.
    const auto alpha = BlendState::alphaBlend().renderTarget[0];
    const glm::vec4 src(29.0f / 256, 0, 0, 53.0f / 256);
    EXPECT_EQ(mergeUnorm<double>(alpha, {239, 0, 0, 0}, src)[0], 195);
    EXPECT_EQ(mergeUnorm<float>(alpha, {239, 0, 0, 0}, src)[0], 196);

    // 12.5 % black over 28: 28 * (1 - 0.125) = 24.5 exactly, a tie, which rounds up. Evaluating in
    // [0, 1] units (28/255 is inexact) and converting with x * 255 + 0.5 lands at 24.
    EXPECT_EQ(mergeUnorm<double>(alpha, {28, 0, 0, 0}, {0, 0, 0, 0.125f})[0], 25);
}

// The exact result of a blend in bytes, as a fraction num / den, rounded to nearest with ties up.
int roundFraction(long num, long den) {
    if (num <= 0) return 0;
    const long q = num / den, r = num % den;
    return std::min<long>(255, q + (2 * r >= den ? 1 : 0));
}

TEST(MergeFragment, DoublePathIsCorrectlyRoundedOnAGrid) {
    // Sources i/64, alpha j/64, every destination byte; the exact results by integer arithmetic.
    const auto alpha = BlendState::alphaBlend().renderTarget[0];
    const auto modulate = blendDesc(Blend::DestColor, Blend::Zero);
    const auto sat = blendDesc(Blend::SrcAlphaSat, Blend::One);
    int mismatches = 0;
    for (int i = 0; i <= 64; ++i) {
        for (int j = 0; j <= 64; ++j) {
            const glm::vec4 src(i / 64.0f, i / 64.0f, i / 64.0f, j / 64.0f);
            for (int n = 0; n < 256; ++n) {
                const Bytes dst{uint8_t(n), uint8_t(n), uint8_t(n), uint8_t(n)};
                // alpha blend: 255 * s * a + n * (1 - a) = (255 i j + 64 n (64 - j)) / 4096.
                const int expectedAlpha = roundFraction(255L * i * j + 64L * n * (64 - j), 4096);
                // modulate: s * n = i n / 64.
                const int expectedModulate = roundFraction(long(i) * n, 64);
                // SrcAlphaSat + One: s * min(a, 1 - n/255) * 255 + n = i * min(255 j, 64 (255 - n)) / 4096 +
                // n.
                const int expectedSat =
                    roundFraction(long(i) * std::min(255L * j, 64L * (255 - n)) + 4096L * n, 4096);
                const int gotAlpha = mergeUnorm<double>(alpha, dst, src)[0];
                const int gotModulate = mergeUnorm<double>(modulate, dst, src)[0];
                const int gotSat = mergeUnorm<double>(sat, dst, src)[0];
                if (gotAlpha == expectedAlpha && gotModulate == expectedModulate && gotSat == expectedSat)
                    continue;
                if (++mismatches <= 5)
                    ADD_FAILURE() << "i=" << i << " j=" << j << " n=" << n << ": alpha " << gotAlpha << " vs "
                                  << expectedAlpha << ", modulate " << gotModulate << " vs "
                                  << expectedModulate << ", sat " << gotSat << " vs " << expectedSat;
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
}

// ---- Fast blenders --------------------------------------------------------------------------------

std::vector<float> sourceGrid() {
    std::vector<float> grid;
    for (int k = -4; k <= 36; ++k) grid.push_back(k / 32.0f);
    for (float v : {kNaN, kInf, -kInf, -0.0f, 1e-7f, 0.5f / 255, 1.5f / 255, 0x1.0101p-9f, 0.49999997f,
                    std::nextafter(1.0f, 0.0f), 0.3f, 0.7f})
        grid.push_back(v);
    return grid;
}

template <class Blender>
void expectSameAsMergeFragment(const RenderTargetBlendDesc& desc) {
    const std::vector<float> grid = sourceGrid();
    const size_t g = grid.size();
    RenderTarget rt(1, 1);
    int mismatches = 0;
    for (size_t i = 0; i < g; ++i) {
        for (size_t j = 0; j < g; ++j) {
            const glm::vec4 src(grid[i], grid[(i + 7) % g], grid[(i * 5 + j) % g], grid[j]);
            for (int n = 0; n < 256; ++n) {
                const uint8_t dst[4] = {uint8_t(n), uint8_t(255 - n), uint8_t(n * 37), uint8_t(n ^ 0xA5)};
                std::copy(dst, dst + 4, rt.rgba8());
                mergeFragment<float>(rt, 0, 0, desc, src, kSrc1, kFactor);
                uint8_t fast[4];
                std::copy(dst, dst + 4, fast);
                Blender::apply(fast, src);
                if (!std::equal(fast, fast + 4, rt.rgba8()) && ++mismatches <= 5)
                    ADD_FAILURE() << "src (" << src.x << ", " << src.y << ", " << src.z << ", " << src.w
                                  << ") dst " << n << ": fast " << int(fast[0]) << " " << int(fast[1]) << " "
                                  << int(fast[2]) << " " << int(fast[3]) << ", generic " << int(rt.rgba8()[0])
                                  << " " << int(rt.rgba8()[1]) << " " << int(rt.rgba8()[2]) << " "
                                  << int(rt.rgba8()[3]);
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
}

TEST(FastBlender, ReplaceIsBitIdenticalToMergeFragment) {
    expectSameAsMergeFragment<BlendReplaceRgba8>(BlendState::opaque().renderTarget[0]);
    EXPECT_FALSE(BlendReplaceRgba8::isNoOp({0, 0, 0, 0}));
}

TEST(FastBlender, AdditiveIsBitIdenticalToMergeFragment) {
    expectSameAsMergeFragment<BlendAdditiveRgba8>(BlendState::additive().renderTarget[0]);
}

// The eight-wide merge the fast pipeline's block loops store through (ColorFast::writeWide, a 4×2
// block) against the scalar blender, lane by lane: the same sources as above, including NaN, ±∞,
// negatives and values above 1, under full, partial and empty lane masks.
template <class Blender>
void expectWideSameAsScalar() {
    const std::vector<float> grid = sourceGrid();
    const size_t g = grid.size();
    std::vector<uint8_t> wide(32), scalar(32);
    const ColorFast<Blender> color{wide.data(), 4};
    int mismatches = 0, lanes_checked = 0;
    for (size_t i = 0; i < g; ++i) {
        for (size_t j = 0; j < g; ++j) {
            float lanes[4][8];
            for (size_t l = 0; l < 8; ++l) {
                lanes[0][l] = grid[(i + l) % g], lanes[1][l] = grid[(3 * i + l + 7) % g];
                lanes[2][l] = grid[(j + 2 * l) % g], lanes[3][l] = grid[(j + 5 * l) % g];
            }
            auto channel = [&](int k) {
                simd::F32x8 v;
                std::memcpy(&v, lanes[k], sizeof v);
                return Float8(v);
            };
            const glm::vec<4, Float8> c(channel(0), channel(1), channel(2), channel(3));
            for (const uint32_t mask : {0xFFu, 0x00u, 0x5Au, uint32_t(i * 31 + j * 7) & 0xFFu}) {
                for (size_t b = 0; b < 32; ++b) wide[b] = scalar[b] = uint8_t(i * 11 + j * 3 + b * 29);
                color.writeWide(0, 0, c, mask);
                for (int l = 0; l < 8; ++l) {
                    if (mask >> l & 1u) {
                        Blender::apply(&scalar[size_t(4 * l)], glm::vec4(c.x[l], c.y[l], c.z[l], c.w[l]));
                        ++lanes_checked;
                    }
                }
                if (wide != scalar && ++mismatches <= 5) ADD_FAILURE() << "sources " << i << ", " << j << " mask " << mask;
            }
        }
    }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(lanes_checked, int(g * g * 8));
}

TEST(FastBlender, EightWideAdditiveIsTheScalarBlenderLaneByLane) { expectWideSameAsScalar<BlendAdditiveRgba8>(); }
TEST(FastBlender, EightWideReplaceIsTheScalarBlenderLaneByLane) { expectWideSameAsScalar<BlendReplaceRgba8>(); }

// The pair of blocks the billboards' loop blends at once (ColorFast::writeWidePair, two 4×2 blocks side
// by side in a target eight pixels wide) against writeWide on each block: the same sources (NaN, ±∞,
// negatives, above 1), independent masks per block, and the no-op lanes it returns against noOpWide's.
TEST(FastBlender, PairOfBlocksIsWriteWideOnEachBlock) {
    using Color = ColorFast<BlendAdditiveRgba8>;
    if constexpr (!Color::kWidePair) {
        GTEST_SKIP() << "no AVX-512 in this build: ColorFast::writeWidePair (avx512::additiveBlendRgba8Pair) was not run "
                        "here; the pipeline blends a pair as two writeWide calls";
    } else {
        const std::vector<float> grid = sourceGrid();
        const size_t g = grid.size();
        std::vector<uint8_t> pair(64), single(64);
        const Color pair_target{pair.data(), 8}, single_target{single.data(), 8};
        int mismatches = 0, blends = 0;
        for (size_t i = 0; i < g; ++i) {
            for (size_t j = 0; j < g; ++j) {
                glm::vec<4, Float8x2> c;
                for (int l = 0; l < 16; ++l) {
                    c.x.h[l >> 3].set(l & 7, grid[(i + size_t(l)) % g]);
                    c.y.h[l >> 3].set(l & 7, grid[(3 * i + size_t(l) + 7) % g]);
                    c.z.h[l >> 3].set(l & 7, grid[(j + 2 * size_t(l)) % g]);
                    c.w.h[l >> 3].set(l & 7, grid[(j + 5 * size_t(l)) % g]);
                }
                const uint32_t varied = uint32_t(i * 131 + j * 29) & 0xFFFFu;
                for (const uint32_t mask : {0xFFFFu, 0x0000u, 0x00FFu, 0xA55Au, varied}) {
                    for (size_t b = 0; b < 64; ++b) pair[b] = single[b] = uint8_t(i * 7 + j * 13 + b * 37);
                    const uint32_t no_ops = pair_target.writeWidePair(0, 0, c, mask);
                    uint32_t expected_no_ops = 0;
                    for (int h = 0; h < 2; ++h) {
                        const glm::vec<4, Float8> block(c.x.h[h], c.y.h[h], c.z.h[h], c.w.h[h]);
                        single_target.writeWide(4 * h, 0, block, mask >> (8 * h) & 0xFFu);
                        expected_no_ops |= single_target.noOpWide(block) << (8 * h);
                    }
                    ++blends;
                    if ((pair != single || no_ops != expected_no_ops) && ++mismatches <= 5)
                        ADD_FAILURE() << "sources " << i << ", " << j << " mask " << mask;
                }
            }
        }
        EXPECT_EQ(mismatches, 0);
        EXPECT_EQ(blends, int(g * g * 5));
    }
}

// Additive blending on a UNORM target adds the same bytes to every destination: the source term is
// rounded alone (in units of 1/255) and the destination byte added exactly, then clamped at 255. The
// older n / 255 + s·a in float made the increment depend on n near ties. Away from ties, that is the
// reference's exactly rounded sum.
TEST(FastBlender, AdditiveIncrementDoesNotDependOnTheDestination) {
    const std::vector<float> grid = sourceGrid();
    const auto additive = BlendState::additive().renderTarget[0];
    RenderTarget rt(1, 1), ref(1, 1);
    int checked_against_reference = 0;
    for (size_t i = 0; i < grid.size(); ++i) {
        for (size_t j = 0; j < grid.size(); ++j) {
            const glm::vec4 src(grid[i], grid[(i + 3) % grid.size()], grid[(i + j) % grid.size()], grid[j]);
            uint8_t increment[4];
            rt.rgba8()[0] = rt.rgba8()[1] = rt.rgba8()[2] = rt.rgba8()[3] = 0;
            mergeFragment<float>(rt, 0, 0, additive, src, kSrc1, kFactor);
            std::copy(rt.rgba8(), rt.rgba8() + 4, increment);
            const glm::dvec4 s = glm::clamp(glm::dvec4(glm::isnan(src.x) ? 0.0f : src.x, glm::isnan(src.y) ? 0.0f : src.y,
                                                       glm::isnan(src.z) ? 0.0f : src.z, glm::isnan(src.w) ? 0.0f : src.w),
                                            0.0, 1.0);
            for (int n = 0; n < 256; ++n) {
                for (int c = 0; c < 4; ++c) rt.rgba8()[c] = ref.rgba8()[c] = uint8_t(n);
                mergeFragment<float>(rt, 0, 0, additive, src, kSrc1, kFactor);
                mergeFragment<double>(ref, 0, 0, additive, src, kSrc1, kFactor);
                for (int c = 0; c < 4; ++c) {
                    ASSERT_EQ(int(rt.rgba8()[c]), std::min(255, n + increment[c]))
                        << "channel " << c << " src (" << src.x << ", " << src.y << ", " << src.z << ", " << src.w
                        << ") dst " << n;
                    const double units = s[c] * s.w * 255.0;
                    if (std::abs(units - std::floor(units) - 0.5) > 1e-4) {
                        ASSERT_EQ(rt.rgba8()[c], ref.rgba8()[c]) << "channel " << c << " units " << units << " dst " << n;
                        ++checked_against_reference;
                    }
                }
            }
        }
    }
    EXPECT_GT(checked_against_reference, 1000000);
    // Terms just below a tie (s·a·255 = 16.49999, 12.49997, 0.49999), where n / 255 + s·a in float
    // rounded up to n + 17, n + 13, n + 1 (found by a random search): the reference's n + 16 etc.
    struct Case {
        float s, a;
        int n, expected;
    };
    for (const Case k : {Case{0x1.0434ccp-3f, 0x1.04c036p-1f, 96, 112}, Case{0x1.d86fep-2f, 0x1.b33222p-4f, 193, 205},
                         Case{0x1.33c0c2p-3f, 0x1.ab8fa6p-7f, 96, 96}}) {
        for (int c = 0; c < 4; ++c) rt.rgba8()[c] = ref.rgba8()[c] = uint8_t(k.n);
        mergeFragment<float>(rt, 0, 0, additive, {k.s, k.s, k.s, k.a}, kSrc1, kFactor);
        mergeFragment<double>(ref, 0, 0, additive, {k.s, k.s, k.s, k.a}, kSrc1, kFactor);
        EXPECT_EQ(int(rt.rgba8()[0]), k.expected) << k.s;
        EXPECT_EQ(int(ref.rgba8()[0]), k.expected) << k.s;
        uint8_t fast[4] = {uint8_t(k.n), uint8_t(k.n), uint8_t(k.n), uint8_t(k.n)};
        BlendAdditiveRgba8::apply(fast, {k.s, k.s, k.s, k.a});
        EXPECT_EQ(int(fast[0]), k.expected) << k.s;
    }
}

TEST(FastBlender, AdditiveNoOpLeavesEveryDestinationUnchanged) {
    const std::vector<float> grid = sourceGrid();
    const auto additive = BlendState::additive().renderTarget[0];
    RenderTarget rt(1, 1);
    for (float a : {0.0f, -0.0f, -0.5f, -kInf, kNaN}) {
        for (float v : grid) {
            const glm::vec4 src(v, v, v, a);
            ASSERT_TRUE(BlendAdditiveRgba8::isNoOp(src)) << "alpha " << a;
            for (int n = 0; n < 256; ++n) {
                const uint8_t dst[4] = {uint8_t(n), uint8_t(n), uint8_t(n), uint8_t(n)};
                std::copy(dst, dst + 4, rt.rgba8());
                mergeFragment<float>(rt, 0, 0, additive, src, kSrc1, kFactor);
                ASSERT_TRUE(std::equal(dst, dst + 4, rt.rgba8()))
                    << "src " << v << " alpha " << a << " dst " << n;
            }
        }
    }
    // Any positive alpha is not claimed to be a no-op, and alpha 1 visibly adds.
    EXPECT_FALSE(BlendAdditiveRgba8::isNoOp({0, 0, 0, 1e-30f}));
    EXPECT_FALSE(BlendAdditiveRgba8::isNoOp({0, 0, 0, 1}));
    uint8_t pixel[4] = {10, 10, 10, 10};
    BlendAdditiveRgba8::apply(pixel, {0.2f, 0.0f, 1.0f, 1.0f});
    EXPECT_EQ((Bytes{pixel[0], pixel[1], pixel[2], pixel[3]}), (Bytes{61, 10, 255, 255}));
}

// The additive blend's ceiling: a pixel with every byte at 255 is one no source can change (NaN, ±∞,
// negatives and values above 1 included), and atCeiling finds exactly the blocks made of such pixels:
// one byte of one pixel below 255 anywhere in the block is enough to say no, and pixels outside the
// block do not count.
TEST(FastBlender, AdditiveCeilingIsEveryByte255AndNoSourceLeavesIt) {
    static_assert(ColorFast<BlendAdditiveRgba8>::kCeiling && !ColorFast<BlendReplaceRgba8>::kCeiling);
    const std::vector<float> grid = sourceGrid();
    const size_t g = grid.size();
    std::vector<uint8_t> pixels(12 * 2 * 4, 255);  // three 4×2 blocks side by side
    const ColorFast<BlendAdditiveRgba8> color{pixels.data(), 12};
    for (size_t i = 0; i < g; ++i) {
        for (size_t j = 0; j < g; ++j) {
            const glm::vec4 src(grid[i], grid[(i + 5) % g], grid[(j + 2) % g], grid[j]);
            uint8_t one[4] = {255, 255, 255, 255};
            BlendAdditiveRgba8::apply(one, src);
            ASSERT_EQ((Bytes{one[0], one[1], one[2], one[3]}), (Bytes{255, 255, 255, 255})) << i << ", " << j;
            color.writeWide(4, 0,
                            glm::vec<4, Float8>(Float8(src.x), Float8(src.y), Float8(src.z), Float8(src.w)),
                            uint32_t(i * 7 + j) & 0xFFu);
            ASSERT_TRUE(std::all_of(pixels.begin(), pixels.end(), [](uint8_t b) { return b == 255; }))
                << i << ", " << j;
        }
    }
    EXPECT_TRUE(color.atCeiling<1>(0, 0) && color.atCeiling<1>(4, 0) && color.atCeiling<1>(8, 0));
    EXPECT_TRUE(color.atCeiling<2>(0, 0) && color.atCeiling<2>(4, 0));
    int refused_one = 0, refused_two = 0;
    for (size_t b = 0; b < pixels.size(); ++b) {
        const int x = int(b / 4 % 12);
        pixels[b] = 254;
        // The block (one or two wide) at x0 holds this byte exactly when x0 <= x < x0 + its width.
        for (const int x0 : {0, 4, 8}) {
            const bool inside = x >= x0 && x < x0 + 4;
            EXPECT_EQ(color.atCeiling<1>(x0, 0), !inside) << "byte " << b << " block " << x0;
            refused_one += inside;
        }
        for (const int x0 : {0, 4}) {
            const bool inside = x >= x0 && x < x0 + 8;
            EXPECT_EQ(color.atCeiling<2>(x0, 0), !inside) << "byte " << b << " pair " << x0;
            refused_two += inside;
        }
        pixels[b] = 255;
    }
    EXPECT_EQ(refused_one, 96);   // every byte is in one block
    EXPECT_EQ(refused_two, 128);  // the middle block's 32 bytes are in both pairs
}

// ---- States: presets, names, validation --------------------------------------------------------------

TEST(States, DefaultsAndPresetsAreD3D11s) {
    const RenderTargetBlendDesc d;
    EXPECT_FALSE(d.blendEnable);
    EXPECT_EQ(d.srcBlend, Blend::One);
    EXPECT_EQ(d.destBlend, Blend::Zero);
    EXPECT_EQ(d.renderTargetWriteMask, 0xF);
    const DepthStencilState ds;
    EXPECT_TRUE(ds.depthEnable && ds.depthWriteMask);
    EXPECT_EQ(ds.depthFunc, ComparisonFunc::Less);
    const RasterizerState rs;
    EXPECT_EQ(rs.cullMode, CullMode::Back);
    EXPECT_FALSE(rs.frontCounterClockwise);
    EXPECT_TRUE(rs.depthClipEnable);

    const BlendState add = BlendState::additive();
    EXPECT_TRUE(add.target(3).blendEnable);
    EXPECT_EQ(add.target(0).srcBlend, Blend::SrcAlpha);
    EXPECT_EQ(add.target(0).destBlend, Blend::One);
    EXPECT_EQ(add.target(0).srcBlendAlpha, Blend::SrcAlpha);
    EXPECT_EQ(add.target(0).destBlendAlpha, Blend::One);
    const BlendState alpha = BlendState::alphaBlend();
    EXPECT_EQ(alpha.target(0).destBlend, Blend::InvSrcAlpha);
    EXPECT_FALSE(BlendState::opaque().target(0).blendEnable);
    EXPECT_FALSE(DepthStencilState::disabled().depthEnable);
    EXPECT_FALSE(DepthStencilState::readOnly(ComparisonFunc::Equal).depthWriteMask);
    EXPECT_EQ(DepthStencilState::readOnly(ComparisonFunc::Equal).depthFunc, ComparisonFunc::Equal);

    for (const BlendState& s : {BlendState{}, BlendState::opaque(), add, alpha}) EXPECT_NO_THROW(validate(s));
    EXPECT_NO_THROW(validate(DepthStencilState{}));
    EXPECT_NO_THROW(validate(RasterizerState{}));
    EXPECT_NO_THROW(validate(Viewport{0, 0, 640, 480, 0, 1}));
}

TEST(States, TargetFollowsIndependentBlendEnable) {
    BlendState s;
    s.renderTarget[2].blendEnable = true;
    EXPECT_FALSE(s.target(2).blendEnable);
    s.independentBlendEnable = true;
    EXPECT_TRUE(s.target(2).blendEnable);
}

TEST(States, NamesAreTheEnumerators) {
    EXPECT_EQ(name(Blend::SrcAlphaSat), "SrcAlphaSat");
    EXPECT_EQ(name(Blend::InvSrc1Alpha), "InvSrc1Alpha");
    EXPECT_EQ(name(BlendOp::RevSubtract), "RevSubtract");
    EXPECT_EQ(name(ComparisonFunc::GreaterEqual), "GreaterEqual");
    EXPECT_EQ(name(Blend(17)), "(invalid)");
    EXPECT_EQ(name(ComparisonFunc(8)), "(invalid)");
}

void expectInvalidState(const std::function<void()>& f, const std::string& field) {
    try {
        f();
        ADD_FAILURE() << "no error for " << field;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidState) << e.what();
        EXPECT_NE(std::string(e.what()).find(field), std::string::npos)
            << "message lacks " << field << ": " << e.what();
    }
}

void expectBlendInvalid(const std::function<void(RenderTargetBlendDesc&)>& edit, const std::string& field) {
    BlendState s;
    edit(s.renderTarget[0]);
    expectInvalidState([&] { validate(s); }, "renderTarget[0]." + field);
}

TEST(Validation, BlendStateRefusesEachBadField) {
    expectBlendInvalid([](auto& d) { d.srcBlend = Blend(17); }, "srcBlend");
    expectBlendInvalid([](auto& d) { d.destBlend = Blend(200); }, "destBlend");
    expectBlendInvalid([](auto& d) { d.blendOp = BlendOp(5); }, "blendOp");
    expectBlendInvalid([](auto& d) { d.srcBlendAlpha = Blend(17); }, "srcBlendAlpha");
    expectBlendInvalid([](auto& d) { d.destBlendAlpha = Blend(18); }, "destBlendAlpha");
    expectBlendInvalid([](auto& d) { d.blendOpAlpha = BlendOp(9); }, "blendOpAlpha");
    expectBlendInvalid([](auto& d) { d.renderTargetWriteMask = 0x10; }, "renderTargetWriteMask");
    for (Blend colour : {Blend::SrcColor, Blend::InvSrcColor, Blend::DestColor, Blend::InvDestColor,
                         Blend::Src1Color, Blend::InvSrc1Color}) {
        expectBlendInvalid([&](auto& d) { d.srcBlendAlpha = colour; }, "srcBlendAlpha");
        expectBlendInvalid([&](auto& d) { d.destBlendAlpha = colour; }, "destBlendAlpha");
        // The same factor is fine for colour.
        BlendState ok;
        ok.renderTarget[0].srcBlend = ok.renderTarget[0].destBlend = colour;
        EXPECT_NO_THROW(validate(ok)) << name(colour);
    }
    // Checked even with blending off, as CreateBlendState does.
    expectBlendInvalid(
        [](auto& d) {
            d.blendEnable = false;
            d.destBlendAlpha = Blend::DestColor;
        },
        "destBlendAlpha");

    BlendState a2c;
    a2c.alphaToCoverageEnable = true;
    expectInvalidState([&] { validate(a2c); }, "alphaToCoverageEnable");
    try {
        validate(a2c);
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not implement"), std::string::npos) << e.what();
    }
}

TEST(Validation, BlendStateNamesTheRenderTargetSlot) {
    BlendState s;
    s.renderTarget[5].destBlendAlpha = Blend::InvDestColor;
    EXPECT_NO_THROW(validate(s));  // slot 5 is unused without independentBlendEnable
    s.independentBlendEnable = true;
    expectInvalidState([&] { validate(s); }, "renderTarget[5].destBlendAlpha");
}

TEST(Validation, DepthStencilStateRefusesBadFunction) {
    DepthStencilState s;
    s.depthFunc = ComparisonFunc(8);
    expectInvalidState([&] { validate(s); }, "depthFunc");
}

TEST(Validation, RasterizerStateRefusesEachBadField) {
    RasterizerState s;
    s.fillMode = FillMode(2);
    expectInvalidState([&] { validate(s); }, "fillMode");
    s = RasterizerState{};
    s.cullMode = CullMode(3);
    expectInvalidState([&] { validate(s); }, "cullMode");

    s = RasterizerState{};
    s.scissorLeft = 10;
    s.scissorRight = 5;
    s.scissorBottom = 4;
    EXPECT_NO_THROW(validate(s));  // scissor off: the rectangle is not looked at
    s.scissorEnable = true;
    expectInvalidState([&] { validate(s); }, "scissorRight");
    s.scissorRight = 10;  // empty, allowed
    EXPECT_NO_THROW(validate(s));
    s.scissorTop = 5;
    expectInvalidState([&] { validate(s); }, "scissorBottom");
}

TEST(Validation, ViewportRefusesEachBadField) {
    const Viewport good{0, 0, 64, 32, 0, 1};
    auto bad = [&](float Viewport::*field, float value, const std::string& named) {
        Viewport v = good;
        v.*field = value;
        expectInvalidState([&] { validate(v); }, named);
    };
    bad(&Viewport::topLeftX, kNaN, "topLeftX");
    bad(&Viewport::topLeftY, kInf, "topLeftY");
    bad(&Viewport::width, kNaN, "width");
    bad(&Viewport::height, kNaN, "height");
    bad(&Viewport::minDepth, kNaN, "minDepth");
    bad(&Viewport::maxDepth, kNaN, "maxDepth");
    bad(&Viewport::width, 0.0f, "width");
    bad(&Viewport::width, -64.0f, "width");
    bad(&Viewport::height, 0.0f, "height");
    bad(&Viewport::height, -1.0f, "height");
    bad(&Viewport::minDepth, -0.1f, "minDepth");
    bad(&Viewport::minDepth, 1.5f, "minDepth");
    bad(&Viewport::maxDepth, 1.1f, "maxDepth");
    bad(&Viewport::maxDepth, -0.5f, "maxDepth");
    bad(&Viewport::topLeftX, -40000.0f, "topLeftX");
    bad(&Viewport::topLeftY, 32760.0f, "topLeftY");  // + height 32 passes the bound

    Viewport inverted = good;
    inverted.minDepth = 0.75f;
    inverted.maxDepth = 0.25f;
    expectInvalidState([&] { validate(inverted); }, "minDepth");
    inverted.maxDepth = 0.75f;  // equal depths are allowed (e.g. a sky at the far plane)
    EXPECT_NO_THROW(validate(inverted));
}

}  // namespace
}  // namespace raster
