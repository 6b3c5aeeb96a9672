#include "raster/format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "raster/check.hpp"
#include "raster/render_target.hpp"

namespace raster {

TEST(Format, SizesAndComponents) {
    EXPECT_EQ(formatSize(Format::R32_FLOAT), 4u);
    EXPECT_EQ(formatSize(Format::R32G32B32_FLOAT), 12u);
    EXPECT_EQ(formatSize(Format::R8G8B8A8_UNORM), 4u);
    EXPECT_EQ(formatComponents(Format::R32G32_FLOAT), 2u);
    EXPECT_EQ(formatComponents(Format::R8G8B8A8_UNORM), 4u);
    EXPECT_EQ(formatName(Format::R32G32B32A32_FLOAT), "R32G32B32A32_FLOAT");
}

TEST(Format, Unorm8RoundsHalfUpAndClamps) {
    EXPECT_EQ(floatToUnorm8(0.0f), 0);
    EXPECT_EQ(floatToUnorm8(1.0f), 255);
    EXPECT_EQ(floatToUnorm8(-3.0f), 0);
    EXPECT_EQ(floatToUnorm8(7.0f), 255);
    EXPECT_EQ(floatToUnorm8(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(floatToUnorm8(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(floatToUnorm8(0.5f), 128);             // 127.5 rounds up
    EXPECT_EQ(floatToUnorm8(1.5f / 255.0f), 2);      // 1.5 rounds up, not to even
    EXPECT_EQ(floatToUnorm8(1.49f / 255.0f), 1);
    for (int n = 0; n < 256; ++n) EXPECT_EQ(floatToUnorm8(unorm8ToFloat(uint8_t(n))), n) << n;
}

TEST(RenderTarget, ZeroSizeIsAnError) {
    EXPECT_THROW(RenderTarget(0, 10), Error);
    EXPECT_THROW(RenderTarget(10, 0), Error);
    EXPECT_THROW(DepthTarget(0, 0), Error);
    EXPECT_THROW(RenderTarget(4, 4, Format::R32G32_FLOAT), Error);
    try {
        RenderTarget(0, 7);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("0x7"), std::string::npos) << e.what();
    }
}

TEST(RenderTarget, ClearStoreLoadConvertByFormat) {
    RenderTarget unorm(3, 2);
    unorm.clear({0.5f, 2.0f, -1.0f, 1.0f});
    EXPECT_EQ(unorm.load(2, 1), glm::vec4(128 / 255.0f, 1.0f, 0.0f, 1.0f));
    RenderTarget fp(3, 2, Format::R32G32B32A32_FLOAT);
    fp.clear({0.5f, 2.0f, -1.0f, 1.0f});
    EXPECT_EQ(fp.load(0, 0), glm::vec4(0.5f, 2.0f, -1.0f, 1.0f));
    fp.store(1, 1, {0.25f, 0, 0, 0});
    EXPECT_EQ(fp.toRgba8()[4 * (3 + 1)], 64);
}

// Tiles are 64 pixels wide: from a 64-byte aligned start every tile row of RGBA8 colour, RGBA32F
// colour and D32 depth is whole cache lines, so threads on neighbouring tiles share none.
TEST(RenderTarget, PixelRowsOfATileAreWholeCacheLines) {
    auto offset = [](const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 64; };
    for (uint32_t width : {64u, 1280u, 1920u}) {
        const RenderTarget unorm(width, 3), fp(width, 3, Format::R32G32B32A32_FLOAT);
        const DepthTarget depth(width, 3);
        EXPECT_EQ(offset(unorm.rgba8()), 0u) << width;
        EXPECT_EQ(offset(fp.rgba32f()), 0u) << width;
        EXPECT_EQ(offset(depth.data()), 0u) << width;
        // Row y, tile column t starts at byte (y·width + 64·t)·4 of an RGBA8 target: a multiple of 64
        // whenever the width is a multiple of 16 pixels, as every width here is.
        EXPECT_EQ(offset(unorm.rgba8() + 4 * (size_t(2) * width + 64)), 0u) << width;
    }
    RenderTarget copy = RenderTarget(100, 7);  // moved and copied storage keeps the alignment
    const RenderTarget again = copy;
    EXPECT_EQ(offset(copy.rgba8()), 0u);
    EXPECT_EQ(offset(again.rgba8()), 0u);
}

}  // namespace raster
