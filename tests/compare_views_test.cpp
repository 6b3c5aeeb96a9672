// The viewer's solution views without SDL (raster/tools/view/compare_views.hpp): what --solution
// names, and the HUD's lines and the difference view of hand-made images with known counts, largest
// difference and mean (the figures themselves: tests/image_compare_test.cpp).
#include "view/compare_views.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "raster/check.hpp"

namespace raster::tools {
namespace {

// 3×2 pixels of (10, 20, 30, 255) and the same with one change a pixel; largest channel
// differences 0, 1, 3, 4, 200, 0.
struct Pair {
    std::vector<uint8_t> a, b;
};
Pair handMade() {
    Pair p;
    for (int i = 0; i < 6; ++i) p.a.insert(p.a.end(), {10, 20, 30, 255});
    p.b = p.a;
    p.b[4 * 1 + 0] += 1;                       // R + 1
    p.b[4 * 2 + 1] -= 3;                       // G − 3
    p.b[4 * 3 + 2] += 4, p.b[4 * 3 + 3] -= 2;  // B + 4, A − 2: the largest is 4
    for (int c = 0; c < 3; ++c) p.b[4 * 4 + c] += 200;
    return p;
}

TEST(CompareViews, StatisticsOfHandMadeImages) {
    const Pair p = handMade();
    const ImageDifference d = compareImages({p.a, 3, 2}, {p.b, 3, 2});
    EXPECT_EQ(d.pixels, 6u);
    EXPECT_EQ(d.differing, 4u);
    EXPECT_EQ(d.max, 200);
    EXPECT_EQ(d.maxX, 1u) << "pixel 4 of a 3-wide image";
    EXPECT_EQ(d.maxY, 1u);
    // |differences| 1 + 3 + (4 + 2) + 3·200 = 610 over 6 pixels × 4 channels.
    EXPECT_DOUBLE_EQ(d.meanAbs, 610.0 / 24.0);
    EXPECT_EQ(d.within1, 3u);
    EXPECT_EQ(d.within3, 4u);
    EXPECT_EQ(describeDifference(d, "scene x"),
              (std::vector<std::string>{
                  "difference from scene x: 4 of 6 pixels differ (66.667%), largest 200/255 at 1,1",
                  "mean |difference| 25.416667/255; pixels within 1/255 50.000%, within 3/255 66.667%",
                  "black equal, grey 1/255 .. red 200/255"}));
    // Symmetric, and the first of equal maxima is named.
    std::vector<uint8_t> c = p.b;
    for (int ch = 0; ch < 3; ++ch) c[4 * 5 + ch] += 200;
    const ImageDifference e = compareImages({c, 3, 2}, {p.a, 3, 2});
    EXPECT_EQ(e.differing, 5u);
    EXPECT_EQ(e.maxX, 1u);
    EXPECT_EQ(e.maxY, 1u);
    const ImageDifference same = compareImages({p.a, 3, 2}, {p.a, 3, 2});
    EXPECT_EQ(same.differing, 0u);
    EXPECT_EQ(same.max, 0);
    EXPECT_EQ(same.meanAbs, 0.0);
    EXPECT_EQ(same.within1, 6u);
    EXPECT_EQ(describeDifference(same, "the reference pipeline"),
              (std::vector<std::string>{
                  "difference from the reference pipeline: 0 of 6 pixels differ (identical)"}));
}

TEST(CompareViews, DifferenceImageRampsFromGreyToRed) {
    const Pair p = handMade();
    const std::vector<uint8_t> image = differenceImage(p.a, p.b, 3, 2);
    ASSERT_EQ(image.size(), 24u);
    const auto rgba = [&](size_t i) {
        return std::vector<uint8_t>(image.begin() + long(4 * i), image.begin() + long(4 * i + 4));
    };
    EXPECT_EQ(rgba(0), (std::vector<uint8_t>{0, 0, 0, 255})) << "equal: black";
    EXPECT_EQ(rgba(5), (std::vector<uint8_t>{0, 0, 0, 255}));
    EXPECT_EQ(rgba(1), (std::vector<uint8_t>{64, 64, 64, 255})) << "1/255: dark grey, visible";
    EXPECT_EQ(rgba(4), (std::vector<uint8_t>{255, 0, 0, 255})) << "the largest: red";
    // Between them red grows and green fades with the difference.
    EXPECT_GT(rgba(3)[0], rgba(2)[0]);
    EXPECT_GT(rgba(2)[0], rgba(1)[0]);
    EXPECT_LE(rgba(3)[1], rgba(2)[1]);
    EXPECT_LT(rgba(3)[1], rgba(1)[1]);
    EXPECT_EQ(differenceColour(1, 1), (Rgb{255, 0, 0})) << "a largest difference of 1 is red too";
    EXPECT_EQ(differenceColour(0, 7), (Rgb{0, 0, 0}));
    try {
        differenceImage(p.a, std::vector<uint8_t>(20), 3, 2);
        ADD_FAILURE() << "images of different sizes must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    }
}

TEST(CompareViews, SolutionNamesReferenceASceneOrAPng) {
    EXPECT_EQ(parseSolution("").kind, SolutionSource::Kind::None);
    EXPECT_EQ(parseSolution("reference").kind, SolutionSource::Kind::Reference);
    const SolutionSource fog = parseSolution("fog");
    EXPECT_EQ(fog.kind, SolutionSource::Kind::Scene);
    EXPECT_EQ(fog.name, "fog");
    EXPECT_EQ(solutionLabel(fog), "scene fog");
    const SolutionSource png = parseSolution("labs/one/Solution.PNG");
    EXPECT_EQ(png.kind, SolutionSource::Kind::Image);
    EXPECT_EQ(png.name, "labs/one/Solution.PNG");
    for (const char* bad : {"smog", "Reference", "solution.jpg", ".png"}) {
        try {
            parseSolution(bad);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
            const std::string message = e.what();
            EXPECT_NE(message.find("unknown --solution '" + std::string(bad) + "'"), std::string::npos)
                << message;
            EXPECT_NE(message.find("particles, fog"), std::string::npos) << message;
        }
    }
}

TEST(CompareViews, ScaleNearestRepeatsPixels) {
    const std::vector<uint8_t> two = {1, 2, 3, 4, 5, 6, 7, 8};  // 2×1
    EXPECT_EQ(scaleNearest(two, 2, 1, 4, 2),
              (std::vector<uint8_t>{1, 2, 3, 4, 1, 2, 3, 4, 5, 6, 7, 8, 5, 6, 7, 8,  //
                                    1, 2, 3, 4, 1, 2, 3, 4, 5, 6, 7, 8, 5, 6, 7, 8}));
    EXPECT_EQ(scaleNearest(two, 2, 1, 1, 1), (std::vector<uint8_t>{5, 6, 7, 8}))
        << "the pixel under the centre";
}

}  // namespace
}  // namespace raster::tools
