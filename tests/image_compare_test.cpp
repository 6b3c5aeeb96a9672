// raster/image_compare.hpp: the figures of hand-made RGBA8 images whose differences are known — equal
// images, one pixel off by 1 step and by 3, a difference in alpha only (counted with RGBA, not with
// RGB) — the per-pixel difference map, and images of different sizes refused naming both. Then the
// grading comparisons: exact, threshold and position at their boundaries (a difference equal to the
// allowance passes, one step more fails; an edge moved by a column fails at deviation 0 and passes at
// 1; a missing thin line fails only the two-way check; the border rules), the largest failing region
// on a crafted error map, LDR-FLIP against values computed by hand, and comparisons read from JSON.
#include "raster/image_compare.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "raster/check.hpp"

namespace raster {
namespace {

constexpr uint32_t kWidth = 3, kHeight = 2;

// 3×2 pixels, each of its own colour (so no pixel equals another by chance), opaque.
ImageRgba8 base() {
    ImageRgba8 image{kWidth, kHeight, {}};
    for (uint8_t i = 0; i < kWidth * kHeight; ++i)
        image.pixels.insert(image.pixels.end(), {uint8_t(10 + i), uint8_t(100 + i), uint8_t(200 + i), 255});
    return image;
}

// `image` with channel `c` of pixel (x, y) changed by `delta` steps.
ImageRgba8 changed(ImageRgba8 image, uint32_t x, uint32_t y, int c, int delta) {
    uint8_t& v = image.pixels[4 * (size_t(y) * image.width + x) + size_t(c)];
    v = uint8_t(int(v) + delta);
    return image;
}

std::string errorOf(auto&& call) {
    try {
        call();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no raster::Error thrown";
    return "";
}

TEST(ImageCompare, IdenticalImages) {
    const ImageRgba8 a = base();
    const ImageDifference d = compareImages(a, a);
    EXPECT_EQ(d.width, kWidth);
    EXPECT_EQ(d.height, kHeight);
    EXPECT_EQ(d.pixels, 6u);
    EXPECT_EQ(d.differing, 0u);
    EXPECT_TRUE(d.identical());
    EXPECT_EQ(d.max, 0);
    EXPECT_EQ(d.maxX, 0u);
    EXPECT_EQ(d.maxY, 0u);
    EXPECT_EQ(d.meanAbs, 0.0);
    EXPECT_EQ(d.within1, 6u);
    EXPECT_EQ(d.within3, 6u);
    EXPECT_EQ(d.share(d.within1), 1.0);
    const DifferenceMap map = differenceMap(a, a);
    EXPECT_EQ(map.width, kWidth);
    EXPECT_EQ(map.height, kHeight);
    EXPECT_EQ(map.largest, std::vector<uint8_t>(6, 0));
    EXPECT_EQ(map.max, 0);
}

TEST(ImageCompare, OnePixelOffByOne) {
    const ImageRgba8 a = base(), b = changed(a, 2, 0, 0, +1);  // pixel (2, 0): red + 1
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.differing, 1u);
    EXPECT_FALSE(d.identical());
    EXPECT_EQ(d.max, 1);
    EXPECT_EQ(d.maxX, 2u);
    EXPECT_EQ(d.maxY, 0u);
    EXPECT_DOUBLE_EQ(d.meanAbs, 1.0 / 24.0);  // one step over 6 pixels × 4 channels
    EXPECT_EQ(d.within1, 6u) << "1 step is within 1/255";
    EXPECT_EQ(d.within3, 6u);
    EXPECT_DOUBLE_EQ(d.share(d.differing), 1.0 / 6.0);
    EXPECT_DOUBLE_EQ(compareImages(a, b, CompareChannels::Rgb).meanAbs, 1.0 / 18.0) << "over 3 channels";
    const DifferenceMap map = differenceMap(a, b);
    EXPECT_EQ(map.largest, (std::vector<uint8_t>{0, 0, 1, 0, 0, 0}));
    EXPECT_EQ(map.at(2, 0), 1);
    EXPECT_EQ(map.max, 1);
}

TEST(ImageCompare, OnePixelOffByThree) {
    const ImageRgba8 a = base(), b = changed(a, 0, 1, 1, -3);  // pixel (0, 1): green − 3
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.differing, 1u);
    EXPECT_EQ(d.max, 3);
    EXPECT_EQ(d.maxX, 0u);
    EXPECT_EQ(d.maxY, 1u);
    EXPECT_DOUBLE_EQ(d.meanAbs, 3.0 / 24.0);
    EXPECT_EQ(d.within1, 5u) << "3 steps are not within 1/255";
    EXPECT_EQ(d.within3, 6u) << "but within 3/255";
    EXPECT_DOUBLE_EQ(d.share(d.within1), 5.0 / 6.0);
    EXPECT_EQ(differenceMap(a, b).at(0, 1), 3);
    // Another channel of the same pixel off by 1 more: the pixel's difference is its largest
    // channel's (3), the mean counts both.
    const ImageDifference two = compareImages(a, changed(b, 0, 1, 2, +1));
    EXPECT_EQ(two.differing, 1u);
    EXPECT_EQ(two.max, 3);
    EXPECT_DOUBLE_EQ(two.meanAbs, 4.0 / 24.0);
    EXPECT_EQ(two.within3, 6u);
    // Off by 4: past 3/255 too; the difference is symmetric.
    const ImageRgba8 four = changed(a, 1, 0, 0, -4);
    const ImageDifference e = compareImages(four, a), f = compareImages(a, four);
    EXPECT_EQ(e.within3, 5u);
    EXPECT_EQ(e.max, 4);
    EXPECT_EQ(f.max, e.max);
    EXPECT_EQ(f.meanAbs, e.meanAbs);
    EXPECT_EQ(f.maxX, 1u);
}

TEST(ImageCompare, AlphaCountsWithRgbaOnly) {
    const ImageRgba8 a = base(), b = changed(a, 1, 1, 3, -2);  // pixel (1, 1): alpha 255 → 253
    const ImageDifference rgba = compareImages(a, b);
    EXPECT_EQ(rgba.differing, 1u);
    EXPECT_EQ(rgba.max, 2);
    EXPECT_EQ(rgba.maxX, 1u);
    EXPECT_EQ(rgba.maxY, 1u);
    EXPECT_DOUBLE_EQ(rgba.meanAbs, 2.0 / 24.0);
    EXPECT_EQ(rgba.within1, 5u);
    EXPECT_EQ(rgba.within3, 6u);
    EXPECT_EQ(differenceMap(a, b).at(1, 1), 2);
    const ImageDifference rgb = compareImages(a, b, CompareChannels::Rgb);
    EXPECT_TRUE(rgb.identical()) << "red, green and blue are equal";
    EXPECT_EQ(rgb.max, 0);
    EXPECT_EQ(rgb.meanAbs, 0.0);
    EXPECT_EQ(differenceMap(a, b, CompareChannels::Rgb).max, 0);
    EXPECT_EQ(largestChannelDifference(&a.pixels[16], &b.pixels[16]), 2);
    EXPECT_EQ(largestChannelDifference(&a.pixels[16], &b.pixels[16], CompareChannels::Rgb), 0);
}

TEST(ImageCompare, SeveralDifferencesAtOnce) {
    // Pixels off by 0, 1, 3, 4 (and alpha 2), 200, 0 steps: largest 200 at pixel 4, which is (1, 1).
    ImageRgba8 b = changed(base(), 1, 0, 0, +1);
    b = changed(b, 2, 0, 1, -3);
    b = changed(changed(b, 0, 1, 2, -4), 0, 1, 3, -2);
    b = changed(changed(changed(b, 1, 1, 0, -10), 1, 1, 1, -11), 1, 1, 2, -200);
    const ImageRgba8 a = base();
    const ImageDifference d = compareImages(a, b);
    EXPECT_EQ(d.differing, 4u);
    EXPECT_EQ(d.max, 200);
    EXPECT_EQ(d.maxX, 1u);
    EXPECT_EQ(d.maxY, 1u);
    // 1 + 3 + (4 + 2) + (200 + 10 + 11) = 231 over 24 channels; RGB: 229 over 18.
    EXPECT_DOUBLE_EQ(d.meanAbs, 231.0 / 24.0);
    EXPECT_EQ(d.within1, 3u);
    EXPECT_EQ(d.within3, 4u);
    EXPECT_DOUBLE_EQ(compareImages(a, b, CompareChannels::Rgb).meanAbs, 229.0 / 18.0);
    EXPECT_EQ(differenceMap(a, b).largest, (std::vector<uint8_t>{0, 1, 3, 4, 200, 0}));
    // The first pixel (row by row) with the largest difference is the one named.
    const ImageRgba8 c = changed(b, 2, 1, 2, -200);
    EXPECT_EQ(compareImages(a, c).maxX, 1u);
    EXPECT_EQ(compareImages(c, a).maxY, 1u);
}

TEST(ImageCompare, BorrowedPixelsAndEmptyImages) {
    const ImageRgba8 a = base(), b = changed(a, 2, 1, 0, +3);
    const ImageDifference d = compareImages({a.pixels, kWidth, kHeight}, {b.pixels, kWidth, kHeight});
    EXPECT_EQ(d.max, 3);
    EXPECT_EQ(d.maxX, 2u);
    EXPECT_EQ(d.maxY, 1u);
    const ImageDifference none = compareImages({{}, 0, 0}, {{}, 0, 0});
    EXPECT_EQ(none.pixels, 0u);
    EXPECT_TRUE(none.identical());
    EXPECT_EQ(none.meanAbs, 0.0);
    EXPECT_EQ(none.share(none.within1), 1.0);
}

TEST(ImageCompare, DifferentSizesAreRefusedNamingBoth) {
    // 3×2 and 2×3 have the same number of bytes: the sizes, not the byte counts, must agree.
    const ImageRgba8 a = base();
    const ImageRgba8 b{2, 3, a.pixels};
    for (const std::string& message : {errorOf([&] { compareImages(a, b); }),
                                       errorOf([&] { differenceMap(a, b, CompareChannels::Rgb); })}) {
        EXPECT_NE(message.find("3x2"), std::string::npos) << message;
        EXPECT_NE(message.find("2x3"), std::string::npos) << message;
    }
    const ImageRgba8 wide{4, 2, std::vector<uint8_t>(32)};
    const std::string message = errorOf([&] { compareImages(wide, a); });
    EXPECT_NE(message.find("4x2 and 3x2"), std::string::npos) << message;
    // Pixels that do not fill the size they are said to have.
    const std::string short_pixels = errorOf([&] { compareImages({a.pixels, 3, 3}, {a.pixels, 3, 3}); });
    EXPECT_NE(short_pixels.find("3x3 needs 36 bytes, not 24"), std::string::npos) << short_pixels;
    const std::string channels = errorOf([&] { compareImages(a, a, CompareChannels(2)); });
    EXPECT_NE(channels.find("2 channels"), std::string::npos) << channels;
}

// ---- Grading comparisons ----

using Rgba = std::array<uint8_t, 4>;

ImageRgba8 uniform(uint32_t width, uint32_t height, Rgba colour) {
    ImageRgba8 image{width, height, {}};
    for (size_t i = 0; i < size_t(width) * height; ++i)
        image.pixels.insert(image.pixels.end(), colour.begin(), colour.end());
    return image;
}

ImageRgba8 with(ImageRgba8 image, uint32_t x, uint32_t y, Rgba colour) {
    std::copy(colour.begin(), colour.end(),
              image.pixels.begin() + ptrdiff_t(4 * (size_t(y) * image.width + x)));
    return image;
}

// `left` for x < edge, `right` from it on: a vertical edge.
ImageRgba8 split(uint32_t width, uint32_t height, uint32_t edge, Rgba left, Rgba right) {
    ImageRgba8 image = uniform(width, height, left);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = edge; x < width; ++x) image = with(std::move(image), x, y, right);
    return image;
}

// Every byte from a fixed linear congruential sequence: noise, the same on every run.
ImageRgba8 noise(uint32_t width, uint32_t height, uint32_t seed) {
    ImageRgba8 image{width, height, std::vector<uint8_t>(size_t(width) * height * 4)};
    for (uint8_t& v : image.pixels) seed = seed * 1664525u + 1013904223u, v = uint8_t(seed >> 24);
    return image;
}

constexpr Rgba kBlack{0, 0, 0, 255}, kWhite{255, 255, 255, 255};

TEST(CompareExact, IdenticalImagesPass) {
    const ImageRgba8 a = base();
    const ComparisonResult r = compareExact(a, a);
    EXPECT_EQ(r.method, CompareMethod::Exact);
    EXPECT_TRUE(r.passed);
    EXPECT_EQ(r.figure, 0.0);
    EXPECT_EQ(r.limit, 0.0);
    EXPECT_EQ(r.failing, 0u);
    EXPECT_EQ(r.width, kWidth);
    EXPECT_EQ(r.height, kHeight);
    EXPECT_EQ(r.error, std::vector<float>(6, 0.0f));
    EXPECT_EQ(r.worstError, 0.0f);
    EXPECT_EQ(r.worstX, 0u);
    EXPECT_EQ(r.worstY, 0u);
    EXPECT_EQ(largestFailingRegion(r).pixels, 0u);
}

TEST(CompareExact, OneStepInAnyChannelFails) {
    const ImageRgba8 a = base();
    for (int c = 0; c < 4; ++c) {
        const ComparisonResult r = compareExact(a, changed(a, 2, 1, c, -1));
        EXPECT_FALSE(r.passed) << "channel " << c;
        EXPECT_EQ(r.failing, 1u);
        EXPECT_EQ(r.figure, 1.0) << "the figure is the failing pixel count";
        EXPECT_FLOAT_EQ(r.at(2, 1), 1.0f / 255.0f);
        EXPECT_TRUE(r.failingAt(2, 1));
        EXPECT_FALSE(r.failingAt(1, 1));
        EXPECT_EQ(r.worstX, 2u);
        EXPECT_EQ(r.worstY, 1u);
    }
}

TEST(CompareThreshold, DifferenceEqualToTheAllowancePasses) {
    // Each channel off by exactly its allowance, at different pixels and all at once.
    const ImageRgba8 a = base();
    ImageRgba8 b = changed(changed(a, 0, 0, 0, +4), 1, 0, 1, -4);
    b = changed(changed(changed(changed(b, 2, 1, 0, -4), 2, 1, 1, +4), 2, 1, 2, +4), 2, 1, 3, -4);
    const ComparisonResult r = compareThreshold(a, b, {4, 4, 4, 4});
    EXPECT_EQ(r.method, CompareMethod::Threshold);
    EXPECT_TRUE(r.passed);
    EXPECT_EQ(r.failing, 0u);
    EXPECT_EQ(r.error, std::vector<float>(6, 0.0f)) << "within the allowance is no error";
    // Per channel: {1, 2, 3, 4} allows exactly those differences.
    const ImageRgba8 c =
        changed(changed(changed(changed(a, 1, 1, 0, +1), 1, 1, 1, +2), 1, 1, 2, -3), 1, 1, 3, -4);
    EXPECT_TRUE(compareThreshold(a, c, {1, 2, 3, 4}).passed);
}

TEST(CompareThreshold, OneStepOverTheAllowanceFails) {
    const ImageRgba8 a = base();
    const ComparisonResult r = compareThreshold(a, changed(a, 1, 0, 1, +5), {4, 4, 4, 4});
    EXPECT_FALSE(r.passed);
    EXPECT_EQ(r.failing, 1u);
    EXPECT_FLOAT_EQ(r.at(1, 0), 1.0f / 255.0f) << "one step past the allowance";
    EXPECT_EQ(r.worstX, 1u);
    EXPECT_EQ(r.worstY, 0u);
    // Per channel: blue 4 over {1, 2, 3, 4}'s 3.
    const ImageRgba8 c = changed(changed(a, 1, 1, 0, +1), 1, 1, 2, -4);
    const ComparisonResult d = compareThreshold(a, c, {1, 2, 3, 4});
    EXPECT_EQ(d.failing, 1u);
    EXPECT_FLOAT_EQ(d.at(1, 1), 1.0f / 255.0f);
    // The error is the largest channel's excess: red 10 and blue 7 over 4 → 6 steps.
    const ComparisonResult e =
        compareThreshold(a, changed(changed(a, 0, 1, 0, +10), 0, 1, 2, -7), {4, 4, 4, 4});
    EXPECT_FLOAT_EQ(e.at(0, 1), 6.0f / 255.0f);
}

TEST(CompareThreshold, AnAllowanceOf255IgnoresTheChannel) {
    const ImageRgba8 a = base(), b = changed(a, 0, 0, 3, -200);  // alpha 255 → 55
    EXPECT_FALSE(compareExact(a, b).passed);
    const ComparisonResult rgb = compareThreshold(a, b, {0, 0, 0, 255});
    EXPECT_TRUE(rgb.passed);
    EXPECT_EQ(rgb.at(0, 0), 0.0f);
    EXPECT_FALSE(compareThreshold(a, changed(b, 2, 1, 0, +1), {0, 0, 0, 255}).passed) << "red still counts";
}

TEST(CompareThreshold, WorstIsTheFirstOfTheLargestRowByRow) {
    const ImageRgba8 a = base();
    const ImageRgba8 b = changed(changed(changed(a, 2, 0, 0, +9), 1, 1, 1, -9), 0, 1, 2, +3);
    const ComparisonResult r = compareThreshold(a, b, {2, 2, 2, 2});
    EXPECT_EQ(r.failing, 3u);
    EXPECT_EQ(r.worstX, 2u) << "(2, 0) and (1, 1) are both 7 over: the first row by row";
    EXPECT_EQ(r.worstY, 0u);
    EXPECT_FLOAT_EQ(r.worstError, 7.0f / 255.0f);
}

PositionTolerance within(uint32_t deviation, Rgba8Threshold threshold = {0, 0, 0, 0},
                         PositionCheck check = PositionCheck::Both, bool accept_out_of_bounds = false) {
    return {deviation, deviation, threshold, accept_out_of_bounds, check};
}

TEST(ComparePosition, EdgeMovedByOneColumnFailsAtZeroAndPassesAtOne) {
    // Black up to x = 7, white from 8; the result's edge is a column later (x = 8 black): the edge's
    // sample positions moved by half a pixel, rounded the other way.
    const ImageRgba8 reference = split(16, 8, 8, kBlack, kWhite), result = split(16, 8, 9, kBlack, kWhite);
    const ComparisonResult at0 = comparePosition(reference, result, within(0));
    EXPECT_EQ(at0.method, CompareMethod::Position);
    EXPECT_FALSE(at0.passed);
    EXPECT_EQ(at0.failing, 8u) << "the whole column x = 8";
    for (uint32_t y = 0; y < 8; ++y) EXPECT_EQ(at0.at(8, y), 1.0f) << "255 steps over";
    const PixelRegion column = largestFailingRegion(at0);
    EXPECT_EQ(column.pixels, 8u);
    EXPECT_EQ(column.left, 8u);
    EXPECT_EQ(column.right, 8u);
    EXPECT_EQ(column.x, 8u);
    EXPECT_EQ(column.y, 0u);
    for (PositionCheck check : {PositionCheck::Both, PositionCheck::ResultInReference}) {
        const ComparisonResult at1 = comparePosition(reference, result, within(1, {0, 0, 0, 0}, check));
        EXPECT_TRUE(at1.passed);
        EXPECT_EQ(at1.failing, 0u);
    }
    // And the same as compareThreshold at deviation 0 (dEQP: a window of one pixel).
    EXPECT_EQ(at0.error, compareThreshold(reference, result, {0, 0, 0, 0}).error);
}

TEST(ComparePosition, IsolatedEdgePixelPassesAtOne) {
    // One pixel of the edge, (8, 3), black instead of white: a jag.
    const ImageRgba8 reference = split(16, 8, 8, kBlack, kWhite), result = with(reference, 8, 3, kBlack);
    const ComparisonResult at0 = comparePosition(reference, result, within(0));
    EXPECT_EQ(at0.failing, 1u);
    EXPECT_TRUE(at0.failingAt(8, 3));
    EXPECT_TRUE(comparePosition(reference, result, within(1)).passed);
    // The same pixel away from the edge, (12, 3), has no black near in the reference.
    const ComparisonResult inside = comparePosition(reference, with(reference, 12, 3, kBlack), within(1));
    EXPECT_FALSE(inside.passed);
    EXPECT_EQ(inside.failing, 1u);
    EXPECT_EQ(inside.at(12, 3), 1.0f);
}

TEST(ComparePosition, MissingThinLineFailsOnlyTheTwoWayCheck) {
    // A white line one pixel wide at x = 8 on black; the result lacks it.
    const ImageRgba8 reference = split(16, 8, 16, kBlack, kWhite);
    ImageRgba8 line = reference;
    for (uint32_t y = 0; y < 8; ++y) line = with(std::move(line), 8, y, kWhite);
    // Missing: every result pixel is black and black is near in the reference, so one way passes;
    // the reference's white pixels have no white near in the result, so both ways fails.
    const ComparisonResult one_way =
        comparePosition(line, reference, within(1, {0, 0, 0, 0}, PositionCheck::ResultInReference));
    EXPECT_TRUE(one_way.passed);
    const ComparisonResult both = comparePosition(line, reference, within(1));
    EXPECT_FALSE(both.passed);
    EXPECT_EQ(both.failing, 8u);
    EXPECT_EQ(largestFailingRegion(both).pixels, 8u);
    // Extra (the result has the line, the reference not): both checks fail it.
    EXPECT_EQ(
        comparePosition(reference, line, within(1, {0, 0, 0, 0}, PositionCheck::ResultInReference)).failing,
        8u);
    EXPECT_EQ(comparePosition(reference, line, within(1)).failing, 8u);
}

TEST(ComparePosition, MatchInTheWindowAtTheThresholdBoundary) {
    // The reference's grey 100 at (5, 5) is drawn at (6, 5) as 104 in the result.
    const ImageRgba8 black = uniform(12, 12, kBlack);
    const ImageRgba8 reference = with(black, 5, 5, {100, 100, 100, 255});
    const ImageRgba8 result = with(black, 6, 5, {104, 104, 104, 255});
    EXPECT_TRUE(comparePosition(reference, result, within(1, {4, 4, 4, 4})).passed) << "104 − 100 = 4 ≤ 4";
    const ComparisonResult over = comparePosition(reference, result, within(1, {3, 3, 3, 3}));
    EXPECT_FALSE(over.passed);
    EXPECT_EQ(over.failing, 2u)
        << "(5, 5) finds no 100 ± 3 in the result, (6, 5) no 104 ± 3 in the reference";
    EXPECT_FLOAT_EQ(over.at(5, 5), 1.0f / 255.0f) << "its best match is one step over";
    EXPECT_FLOAT_EQ(over.at(6, 5), 1.0f / 255.0f);
}

TEST(ComparePosition, BorderWindowIsCutOrAcceptedAsAnyValue) {
    const ImageRgba8 black = uniform(8, 8, kBlack);
    // A white pixel at the left border: no white in its (cut) window of the reference.
    const ImageRgba8 at_border = with(black, 0, 3, kWhite);
    const ComparisonResult cut = comparePosition(black, at_border, within(1));
    EXPECT_EQ(cut.failing, 1u);
    EXPECT_EQ(cut.at(0, 3), 1.0f);
    // Accepted: its window at deviation 1 reaches x = −1, so it is not checked.
    EXPECT_TRUE(comparePosition(black, at_border, within(1, {0, 0, 0, 0}, PositionCheck::Both, true)).passed);
    // One pixel in, (1, 3): inside the checked area at deviation 1, in the band at 2.
    const ImageRgba8 one_in = with(black, 1, 3, kWhite);
    EXPECT_FALSE(comparePosition(black, one_in, within(1, {0, 0, 0, 0}, PositionCheck::Both, true)).passed);
    EXPECT_TRUE(comparePosition(black, one_in, within(2, {0, 0, 0, 0}, PositionCheck::Both, true)).passed);
    // The right and bottom bands too: x + deviation ≥ width.
    EXPECT_TRUE(
        comparePosition(black, with(black, 7, 7, kWhite), within(1, {0, 0, 0, 0}, PositionCheck::Both, true))
            .passed);
    // An image no larger than 2 · deviation: every pixel is in the band.
    EXPECT_TRUE(comparePosition(uniform(2, 2, kBlack), uniform(2, 2, kWhite),
                                within(1, {0, 0, 0, 0}, PositionCheck::Both, true))
                    .passed);
    // Deviations per axis: a pixel moved down by 2 passes at (0, 2), not at (2, 0).
    const ImageRgba8 dot = with(black, 4, 2, kWhite), moved = with(black, 4, 4, kWhite);
    EXPECT_TRUE(comparePosition(dot, moved, {0, 2, {0, 0, 0, 0}, false, PositionCheck::Both}).passed);
    EXPECT_FALSE(comparePosition(dot, moved, {2, 0, {0, 0, 0, 0}, false, PositionCheck::Both}).passed);
}

TEST(ComparePosition, RefusesDeviationsPastTheLimit) {
    const ImageRgba8 a = base();
    const std::string message =
        errorOf([&] { comparePosition(a, a, within(PositionTolerance::kMaxDeviation + 1)); });
    EXPECT_NE(message.find("deviation"), std::string::npos) << message;
    EXPECT_TRUE(comparePosition(a, a, within(PositionTolerance::kMaxDeviation)).passed);
}

// An 8×6 result with the given error values at the given pixels (failLevel 0).
ComparisonResult errorMap(std::initializer_list<std::tuple<uint32_t, uint32_t, float>> errors) {
    ComparisonResult r;
    r.width = 8, r.height = 6;
    r.error.assign(48, 0.0f);
    for (const auto& [x, y, e] : errors) r.error[size_t(y) * 8 + x] = e;
    return r;
}

TEST(LargestFailingRegion, TheLargerRegionAndItsWorstPixel) {
    // . . . . . . . .
    // . A A . . . . .      A: 2 pixels, 0.9 each (the worst pixels of the image)
    // . . . . B . . .      B: 4 pixels touching only by corners: one region when 8-connected
    // . . . B . B . .         (4-connected, four regions of 1)
    // . . . . B . . .
    const ComparisonResult r =
        errorMap({{1, 1, 0.9f}, {2, 1, 0.9f}, {4, 2, 0.5f}, {3, 3, 0.7f}, {5, 3, 0.7f}, {4, 4, 0.2f}});
    const PixelRegion b = largestFailingRegion(r);
    EXPECT_EQ(b.pixels, 4u);
    EXPECT_EQ(b.x, 3u) << "(3, 3) and (5, 3) are both 0.7: the first row by row";
    EXPECT_EQ(b.y, 3u);
    EXPECT_FLOAT_EQ(b.error, 0.7f);
    EXPECT_EQ(b.left, 3u);
    EXPECT_EQ(b.right, 5u);
    EXPECT_EQ(b.top, 2u);
    EXPECT_EQ(b.bottom, 4u);
    // Above 0.6 only A's two pixels and B's (3, 3) and (5, 3) fail; those two no longer touch.
    ComparisonResult high = r;
    high.failLevel = 0.6f;
    const PixelRegion a = largestFailingRegion(high);
    EXPECT_EQ(a.pixels, 2u);
    EXPECT_EQ(a.x, 1u);
    EXPECT_EQ(a.y, 1u);
    EXPECT_EQ(a.right, 2u);
}

TEST(LargestFailingRegion, TiesGoToTheFirstRegionRowByRow) {
    // Two regions of 2 pixels; the later one has the larger errors.
    const ComparisonResult r = errorMap({{6, 0, 0.1f}, {7, 1, 0.1f}, {0, 4, 0.8f}, {0, 5, 0.8f}});
    const PixelRegion first = largestFailingRegion(r);
    EXPECT_EQ(first.pixels, 2u);
    EXPECT_EQ(first.x, 6u);
    EXPECT_EQ(first.y, 0u);
    EXPECT_EQ(largestFailingRegion(errorMap({})).pixels, 0u) << "nothing fails";
    ComparisonResult broken = r;
    broken.error.pop_back();
    const std::string message = errorOf([&] { largestFailingRegion(broken); });
    EXPECT_NE(message.find("8x6 with 47"), std::string::npos) << message;
}

TEST(LargestFailingRegion, OfAFlipResult) {
    // Pixels over the pixel level fail; the region's representative is its worst pixel.
    const ImageRgba8 reference = split(48, 16, 24, kBlack, kWhite),
                     result = split(48, 16, 25, kBlack, kWhite);
    const ComparisonResult r = compareFlip(reference, result);
    const PixelRegion region = largestFailingRegion(r);
    EXPECT_GT(region.pixels, 0u);
    EXPECT_LE(region.left, 24u);
    EXPECT_GE(region.right, 24u);
    EXPECT_FLOAT_EQ(region.error, r.worstError) << "one region holds the worst pixel";
    EXPECT_GT(region.error, float(r.failLevel));
}

// ---- LDR-FLIP ----

// A picture: a gradient, a checkerboard in blue, and a disc.
ImageRgba8 picture(uint32_t width, uint32_t height, int disc_shift = 0) {
    ImageRgba8 image{width, height, std::vector<uint8_t>(size_t(width) * height * 4)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            uint8_t* p = &image.pixels[4 * (size_t(y) * width + x)];
            const int dx = int(x) - int(width / 2) - disc_shift, dy = int(y) - int(height / 2);
            const bool disc = dx * dx + dy * dy < int(height * height / 9);
            p[0] = disc ? 220 : uint8_t(x * 255 / width);
            p[1] = disc ? 60 : uint8_t(y * 255 / height);
            p[2] = ((x / 4 + y / 4) & 1) ? 200 : 40;
            p[3] = 255;
        }
    return image;
}

TEST(CompareFlip, IdenticalImagesAreZeroEverywhere) {
    const ImageRgba8 a = picture(40, 30);
    const ComparisonResult r = compareFlip(a, a);
    EXPECT_EQ(r.method, CompareMethod::Flip);
    EXPECT_EQ(r.error, std::vector<float>(40 * 30, 0.0f));
    EXPECT_EQ(r.figure, 0.0);
    EXPECT_TRUE(r.passed);
    EXPECT_EQ(r.failing, 0u);
    EXPECT_EQ(r.limit, 0.05);
    EXPECT_EQ(r.failLevel, 0.05f);
}

// The expected values below, computed by hand (and checked with a calculator in double):
//
// On a uniform image every colour filter returns the colour (its weights sum to 1 and clamp-to-edge
// reads only that colour) and every feature filter 0 (its weights sum to 0), so ΔE_f = 0 and the
// error is ΔE_c at every pixel. ΔE_c of colours p, q:
//   sRGB byte v → c = v/255 → linear = c/12.92 if c ≤ 0.04045, else ((c + 0.055)/1.055)^2.4;
//   → XYZ / white, t = (X/Xn, Y/Yn, Z/Zn); f(t) = t^(1/3) (t > 0.008856);
//   L* = 116 f(Y) − 16, a* = 500 (f(X) − f(Y)), b* = 200 (f(Y) − f(Z)); Hunt: a*, b* × 0.01 L*;
//   HyAB = |ΔL*| + √(Δa*² + Δb*²); e = HyAB^0.7;
//   ΔE_c = e · 0.95 / (0.4 cmax) if e < 0.4 cmax, else 0.95 + (e − 0.4 cmax) / (0.6 cmax) · 0.05.
// cmax: green (0, 1, 0) → XYZ (0.357591, 0.715183, 0.119197) → L*a*b* (87.7362, −86.1787, 83.1826) →
// Hunt (87.7362, −75.6099, 72.9812); blue (0, 0, 1) → XYZ (0.180450, 0.072180, 0.950373) →
// (32.2982, 79.1936, −107.8586) → Hunt (32.2982, 25.5781, −34.8364). HyAB = 55.4380 +
// √(101.1880² + 107.8176²) = 55.4380 + 147.8636 = 203.3017; cmax = 203.3017^0.7 = 41.27610,
// 0.4 cmax = 16.51044, 0.6 cmax = 24.76566.
//
// Black against white: linear 0 and 1; t = 0 and 1; L* = 116 · (4/29) − 16 = 0 and 116 − 16 = 100,
// a* = b* = 0 (X/Xn = Y/Yn = Z/Zn for a grey). HyAB = 100, e = 100^0.7 = 25.118864 ≥ 16.51044:
// ΔE_c = 0.95 + (25.118864 − 16.51044) / 24.76566 · 0.05 = 0.95 + 0.3475952 · 0.05 = 0.9673798.
//
// Grey 128 against grey 131: c = 0.5019608 and 0.5137255; (c + 0.055)/1.055 = 0.5279249 and
// 0.5390763; ^2.4 = 0.2158605 and 0.2269659; a grey's t is that for X, Y and Z, so a* = b* = 0;
// f = 0.5998708 and 0.6099864; L* = 53.585013 and 54.758428. HyAB = 1.173415, e = 1.118449 <
// 16.51044: ΔE_c = 1.118449 · 0.95 / 16.51044 = 0.0643548.
//
// Orange (200, 120, 40) against (190, 125, 60): linear (0.577580, 0.187821, 0.021219) and (0.514918,
// 0.205079, 0.045186); t = (0.325304, 0.258673, 0.049333) and (0.309159, 0.259421, 0.071028); L*a*b* =
// (57.9108, 25.2932, 54.0810) and (57.9820, 19.2006, 44.7281); Hunt (57.9108, 14.6475, 31.3188) and
// (57.9820, 11.1329, 25.9342). HyAB = 0.071188 + √(3.514658² + 5.384520²) = 0.071188 + 6.430076 =
// 6.501264; e = 3.707648: ΔE_c = 3.707648 · 0.95 / 16.51044 = 0.2133356.
//
// Green against blue: HyAB = cmax's, e = cmax: ΔE_c = 0.95 + 0.6 cmax / 0.6 cmax · 0.05 = 1.
TEST(CompareFlip, UniformImagesGiveTheColourTermComputedByHand) {
    struct Case {
        Rgba p, q;
        double expected;
    };
    const Case cases[] = {{kBlack, kWhite, 0.9673798},
                          {{128, 128, 128, 255}, {131, 131, 131, 255}, 0.0643548},
                          {{200, 120, 40, 255}, {190, 125, 60, 255}, 0.2133356},
                          {{0, 255, 0, 255}, {0, 0, 255, 255}, 1.0}};
    for (const Case& c : cases) {
        const ComparisonResult r = compareFlip(uniform(9, 7, c.p), uniform(9, 7, c.q));
        for (float e : r.error) ASSERT_NEAR(e, c.expected, 1e-4) << int(c.p[0]) << " against " << int(c.q[0]);
        EXPECT_NEAR(r.figure, c.expected, 1e-4);
        EXPECT_EQ(r.worstError, r.error.front()) << "uniform: every pixel the same bits";
        EXPECT_EQ(*std::min_element(r.error.begin(), r.error.end()), r.error.front());
    }
}

// The values tests/flip_direct.py prints: LDR-FLIP computed in double, in plain Python, from the
// paper's 2D kernels as written (no separable passes), YCxCz with its scale and offset, on a picture
// whose every filter matters (gradients, a checkerboard, a disc moved by 2 pixels, noise). This
// implementation filters separably in float: the two agree to about 1e-6.
TEST(CompareFlip, MatchesADirectRendition) {
    const ImageRgba8 a = picture(30, 20), moved = picture(30, 20, 2), grain = noise(30, 20, 5);
    ImageRgba8 b = moved;  // three parts the moved picture, one part noise, in red, green and blue
    for (size_t i = 0; i < b.pixels.size(); ++i)
        if (i % 4 != 3) b.pixels[i] = uint8_t((moved.pixels[i] * 3 + grain.pixels[i]) / 4);
    struct Sample {
        uint32_t x, y;
        double at67, at20;
    };
    const Sample samples[] = {{0, 0, 0.2949314, 0.4474982},   {5, 3, 0.3117336, 0.3405451},
                              {15, 10, 0.3911149, 0.4529282}, {22, 9, 0.2823505, 0.3694430},
                              {10, 15, 0.4582127, 0.3993571}, {29, 19, 0.3067814, 0.4041894}};
    const ComparisonResult at67 = compareFlip(a, b), at20 = compareFlip(a, b, {20.0, 0.05, 0.05});
    EXPECT_NEAR(at67.figure, 0.3831781, 1e-5);
    EXPECT_NEAR(at20.figure, 0.4578380, 1e-5);
    for (const Sample& s : samples) {
        EXPECT_NEAR(at67.at(s.x, s.y), s.at67, 1e-5) << s.x << ", " << s.y;
        EXPECT_NEAR(at20.at(s.x, s.y), s.at20, 1e-5) << s.x << ", " << s.y << " at 20 ppd";
    }
}

TEST(CompareFlip, SymmetricInItsTwoImages) {
    const ImageRgba8 a = picture(40, 30), b = noise(40, 30, 7), c = picture(40, 30, 3);
    EXPECT_EQ(compareFlip(a, b).error, compareFlip(b, a).error) << "bit for bit: |Δ| and ‖Δ‖ are symmetric";
    EXPECT_EQ(compareFlip(a, c).error, compareFlip(c, a).error);
    // And the same bits on a second run.
    EXPECT_EQ(compareFlip(a, b).error, compareFlip(a, b).error);
}

TEST(CompareFlip, InTheUnitRangeWithoutNanAtTheExtremes) {
    const Rgba colours[] = {kBlack,
                            kWhite,
                            {255, 0, 0, 255},
                            {0, 255, 0, 255},
                            {0, 0, 255, 255},
                            {255, 255, 0, 255},
                            {0, 255, 255, 255},
                            {255, 0, 255, 255}};
    auto check = [](const ComparisonResult& r, const std::string& what) {
        for (float e : r.error) {
            ASSERT_FALSE(std::isnan(e)) << what;
            ASSERT_GE(e, 0.0f) << what;
            ASSERT_LE(e, 1.0f) << what;
        }
        EXPECT_GE(r.figure, 0.0) << what;
        EXPECT_LE(r.figure, 1.0) << what;
    };
    for (const Rgba& p : colours)
        for (const Rgba& q : colours) {
            const std::string what = std::to_string(p[0]) + "," + std::to_string(p[1]) + "," +
                                     std::to_string(p[2]) + " against " + std::to_string(q[0]) + "," +
                                     std::to_string(q[1]) + "," + std::to_string(q[2]);
            check(compareFlip(uniform(1, 1, p), uniform(1, 1, q)), "1x1 " + what);
            check(compareFlip(split(6, 3, 3, p, q), split(6, 3, 2, q, p)), "edges " + what);
        }
    check(compareFlip(noise(33, 17, 1), noise(33, 17, 2)), "noise");
    check(compareFlip(split(16, 16, 8, kBlack, kWhite), split(16, 16, 8, kWhite, kBlack)), "inverted edge");
    // A 1×1 pair is a uniform pair: black against white gives its hand-computed value.
    EXPECT_NEAR(compareFlip(uniform(1, 1, kBlack), uniform(1, 1, kWhite)).error[0], 0.9673798, 1e-4);
    // No pixels: nothing differs.
    const ComparisonResult empty = compareFlip({{}, 0, 0}, {{}, 0, 0});
    EXPECT_TRUE(empty.passed);
    EXPECT_EQ(empty.figure, 0.0);
}

TEST(CompareFlip, EdgeMovedByOnePixelErrsAtTheEdgeNotAwayFromIt) {
    // 64×16, black then white from x = 32; the result's edge at 33: column 32 differs.
    const ImageRgba8 reference = split(64, 16, 32, kBlack, kWhite),
                     result = split(64, 16, 33, kBlack, kWhite);
    const ComparisonResult r = compareFlip(reference, result);
    for (uint32_t y = 0; y < 16; ++y) {
        EXPECT_GT(r.at(32, y), 0.5f) << "the moved column";
        EXPECT_GT(r.at(32, y), 100 * r.at(8, y)) << "far left";
        EXPECT_GT(r.at(32, y), 100 * r.at(56, y)) << "far right";
        EXPECT_GT(r.at(31, y), r.at(28, y)) << "falling off with distance";
        EXPECT_GT(r.at(33, y), r.at(36, y)) << "on both sides";
    }
    // The worst is next to the moved column, on its dark side: the colour filters spread the one-column
    // difference over a few pixels either side, and L*'s cube root makes the same luminance difference
    // larger where it is dark (measured: 0.77 at x = 31, 0.54 at 32, 0.50 at 33, 0 beyond 39).
    EXPECT_GE(r.worstX, 31u);
    EXPECT_LE(r.worstX, 33u);
    EXPECT_FALSE(r.passed) << "mean " << r.figure;
}

TEST(CompareFlip, PassesAtTheMeanLimitAndFailsJustBelow) {
    const ImageRgba8 a = uniform(5, 4, {128, 128, 128, 255}), b = uniform(5, 4, {131, 131, 131, 255});
    const ComparisonResult by_default = compareFlip(a, b);
    EXPECT_FALSE(by_default.passed) << "0.0644 > 0.05";
    EXPECT_EQ(by_default.failing, 20u) << "every pixel is over 0.05";
    const double mean = by_default.figure;
    EXPECT_TRUE(compareFlip(a, b, {67.0, mean, 0.05}).passed) << "mean ≤ limit";
    EXPECT_FALSE(compareFlip(a, b, {67.0, std::nextafter(mean, 0.0), 0.05}).passed);
    EXPECT_EQ(compareFlip(a, b, {67.0, 0.05, 0.07}).failing, 0u) << "the pixel level is its own";
    // Alpha is not seen.
    EXPECT_EQ(compareFlip(a, uniform(5, 4, {128, 128, 128, 0})).figure, 0.0);
}

TEST(CompareFlip, RefusesOptionsOutOfRange) {
    const ImageRgba8 a = base();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const auto& [options, field] : {std::pair{FlipOptions{0.5, 0.05, 0.05}, "\"ppd\""},
                                         std::pair{FlipOptions{nan, 0.05, 0.05}, "\"ppd\""},
                                         std::pair{FlipOptions{67, 1.5, 0.05}, "\"mean\""},
                                         std::pair{FlipOptions{67, 0.05, -0.1}, "\"pixel\""}}) {
        const std::string message = errorOf([&] { compareFlip(a, a, options); });
        EXPECT_NE(message.find(field), std::string::npos) << message;
    }
}

TEST(GradingComparisons, DifferentSizesAreRefusedNamingBoth) {
    const ImageRgba8 a = base(), b{2, 3, a.pixels};
    Comparison flip;
    flip.method = CompareMethod::Flip;
    for (const std::string& message :
         {errorOf([&] { compareExact(a, b); }), errorOf([&] {
              compareThreshold(a, b, {1, 1, 1, 1});
          }),
          errorOf([&] { comparePosition(a, b, within(1)); }), errorOf([&] { compareFlip(a, b); }),
          errorOf([&] { compare(flip, b, a); })}) {
        EXPECT_NE(message.find("3x2"), std::string::npos) << message;
        EXPECT_NE(message.find("2x3"), std::string::npos) << message;
    }
}

// ---- Comparisons described by data ----

TEST(ComparisonParse, EachMethodWithItsFields) {
    const Comparison exact = Comparison::parse(R"({"method": "exact"})");
    EXPECT_EQ(exact.method, CompareMethod::Exact);
    const Comparison threshold = Comparison::parse(R"({"method": "threshold", "rgba": [4, 3, 2, 255]})");
    EXPECT_EQ(threshold.method, CompareMethod::Threshold);
    EXPECT_EQ(threshold.threshold, (Rgba8Threshold{4, 3, 2, 255}));
    const Comparison position =
        Comparison::parse(R"({"method": "position", "deviation": 1, "rgba": [1,1,1,1]})");
    EXPECT_EQ(position.method, CompareMethod::Position);
    EXPECT_EQ(position.position.deviationX, 1u);
    EXPECT_EQ(position.position.deviationY, 1u);
    EXPECT_EQ(position.position.threshold, (Rgba8Threshold{1, 1, 1, 1}));
    EXPECT_FALSE(position.position.acceptOutOfBounds);
    EXPECT_EQ(position.position.check, PositionCheck::Both);
    const Comparison other = Comparison::parse(
        R"({"method": "position", "deviation": [2, 0], "acceptOutOfBounds": true, "symmetric": false})");
    EXPECT_EQ(other.position.deviationX, 2u);
    EXPECT_EQ(other.position.deviationY, 0u);
    EXPECT_EQ(other.position.threshold, (Rgba8Threshold{0, 0, 0, 0})) << "rgba defaults to exact";
    EXPECT_TRUE(other.position.acceptOutOfBounds);
    EXPECT_EQ(other.position.check, PositionCheck::ResultInReference);
    const Comparison flip = Comparison::parse(R"({"method": "flip", "mean": 0.1, "ppd": 40})");
    EXPECT_EQ(flip.method, CompareMethod::Flip);
    EXPECT_EQ(flip.flip.meanLimit, 0.1);
    EXPECT_EQ(flip.flip.ppd, 40.0);
    EXPECT_EQ(flip.flip.pixelLimit, 0.1) << "the pixel level follows the mean";
    const Comparison defaults = Comparison::parse(R"({"method": "flip"})");
    EXPECT_EQ(defaults.flip.meanLimit, 0.05);
    EXPECT_EQ(defaults.flip.pixelLimit, 0.05);
    EXPECT_EQ(defaults.flip.ppd, 67.0);
    EXPECT_EQ(Comparison::parse(R"({"method": "flip", "pixel": 0.3})").flip.pixelLimit, 0.3);
}

TEST(ComparisonParse, ErrorsNameTheField) {
    const std::pair<const char*, const char*> cases[] = {
        {"{", "not JSON"},
        {"[1, 2]", "JSON object"},
        {R"({"rgba": [1, 1, 1, 1]})", "\"method\""},
        {R"({"method": 3})", "\"method\""},
        {R"({"method": "fuzzy"})", "\"fuzzy\""},
        {R"({"method": "exact", "rgba": [1, 1, 1, 1]})", "unknown field \"rgba\""},
        {R"({"method": "threshold"})", "needs \"rgba\""},
        {R"({"method": "threshold", "rgab": [4, 4, 4, 4]})", "unknown field \"rgab\""},
        {R"({"method": "threshold", "rgba": [4, 4, 4]})", "\"rgba\" must be an array of 4"},
        {R"({"method": "threshold", "rgba": "4"})", "\"rgba\" must be an array of 4"},
        {R"({"method": "threshold", "rgba": [4, 4, 4, 256]})",
         "\"rgba[3]\" must be an integer 0..255, not 256"},
        {R"({"method": "threshold", "rgba": [4, 4.5, 4, 4]})", "\"rgba[1]\""},
        {R"({"method": "threshold", "rgba": [-1, 4, 4, 4]})", "\"rgba[0]\""},
        {R"({"method": "position"})", "needs \"deviation\""},
        {R"({"method": "position", "deviation": -1})", "\"deviation\" must be an integer 0..16, not -1"},
        {R"({"method": "position", "deviation": 17})", "\"deviation\" must be an integer 0..16"},
        {R"({"method": "position", "deviation": [1, 2, 3]})", "\"deviation\" must be N or [x, y]"},
        {R"({"method": "position", "deviation": [1, 99]})", "\"deviation[1]\""},
        {R"({"method": "position", "deviation": 1, "symmetric": "yes"})",
         "\"symmetric\" must be true or false"},
        {R"({"method": "position", "deviation": 1, "acceptOutOfBounds": 1})", "\"acceptOutOfBounds\""},
        {R"({"method": "flip", "mean": 2})", "\"mean\""},
        {R"({"method": "flip", "ppd": 0})", "\"ppd\""},
        {R"({"method": "flip", "ppd": "67"})", "\"ppd\" must be a number"},
        {R"({"method": "flip", "pixel": -0.5})", "\"pixel\""},
        {R"({"method": "flip", "deviation": 1})", "unknown field \"deviation\""},
    };
    for (const auto& [json, expected] : cases) {
        const std::string message = errorOf([&] { Comparison::parse(json); });
        EXPECT_NE(message.find("comparison: "), std::string::npos) << json << ": " << message;
        EXPECT_NE(message.find(expected), std::string::npos) << json << ": " << message;
    }
}

TEST(ComparisonDescribe, SaysTheRuleInWords) {
    EXPECT_EQ(Comparison::parse(R"({"method": "exact"})").describe(),
              "exact: every channel (red, green, blue, alpha) of every pixel equal to the reference's");
    EXPECT_EQ(Comparison::parse(R"({"method": "threshold", "rgba": [4, 4, 4, 4]})").describe(),
              "threshold: every pixel within 4/255 in every channel of the reference's");
    EXPECT_EQ(
        Comparison::parse(R"({"method": "threshold", "rgba": [0, 1, 2, 255]})").describe(),
        "threshold: every pixel within red 0/255, green 1/255, blue 2/255, alpha any of the reference's");
    const std::string position =
        Comparison::parse(R"({"method": "position", "deviation": 1, "rgba": [1, 1, 1, 1]})").describe();
    EXPECT_EQ(
        position,
        "position: every result pixel matched within 1/255 in every channel by a reference pixel within ±1 "
        "pixels, and every reference pixel by a result pixel; at the border, only pixels inside the image "
        "count");
    const std::string one_way =
        Comparison::parse(
            R"({"method": "position", "deviation": [2, 1], "symmetric": false, "acceptOutOfBounds": true})")
            .describe();
    EXPECT_NE(one_way.find("±2 pixels across and ±1 down"), std::string::npos) << one_way;
    EXPECT_EQ(one_way.find("every reference pixel"), std::string::npos) << one_way;
    EXPECT_NE(one_way.find("window leaves the image pass"), std::string::npos) << one_way;
    EXPECT_EQ(Comparison::parse(R"({"method": "flip"})").describe(),
              "flip: mean LDR-FLIP error at most 0.05 at 67 pixels per degree (pixels above 0.05 count as "
              "failing)");
    EXPECT_STREQ(compareMethodName(CompareMethod::Position), "position");
}

TEST(ComparisonRun, RunsTheNamedMethodWithItsOptions) {
    const ImageRgba8 reference = split(16, 8, 8, kBlack, kWhite), result = split(16, 8, 9, kBlack, kWhite);
    const ComparisonResult exact = compare(Comparison::parse(R"({"method": "exact"})"), reference, result);
    EXPECT_EQ(exact.method, CompareMethod::Exact);
    EXPECT_EQ(exact.failing, 8u);
    const ComparisonResult threshold = compare(
        Comparison::parse(R"({"method": "threshold", "rgba": [255, 255, 255, 0]})"), reference, result);
    EXPECT_EQ(threshold.method, CompareMethod::Threshold);
    EXPECT_TRUE(threshold.passed) << "only alpha compared";
    const ComparisonResult position =
        compare(Comparison::parse(R"({"method": "position", "deviation": 1})"), reference, result);
    EXPECT_EQ(position.method, CompareMethod::Position);
    EXPECT_TRUE(position.passed);
    const ComparisonResult flip =
        compare(Comparison::parse(R"({"method": "flip", "ppd": 30, "mean": 0.2})"), reference, result);
    EXPECT_EQ(flip.method, CompareMethod::Flip);
    EXPECT_EQ(flip.limit, 0.2);
    EXPECT_EQ(flip.error, compareFlip(reference, result, {30, 0.2, 0.2}).error);
    EXPECT_NE(flip.error, compareFlip(reference, result).error) << "the ppd changes the filters";
}

}  // namespace
}  // namespace raster
