// raster/image_compare.hpp: the figures of hand-made RGBA8 images whose differences are known — equal
// images, one pixel off by 1 step and by 3, a difference in alpha only (counted with RGBA, not with
// RGB) — the per-pixel difference map, and images of different sizes refused naming both.
#include "raster/image_compare.hpp"

#include <gtest/gtest.h>

#include <string>
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

}  // namespace
}  // namespace raster
