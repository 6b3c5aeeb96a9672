// Heat maps of a per-pixel error on a ramp whose luminance rises with the error (report.hpp).
#include <algorithm>
#include <cmath>

#include "grade/report.hpp"
#include "raster/check.hpp"

namespace raster::grade {
namespace {

struct ControlPoint {
    float at;
    uint8_t r, g, b;
};

// The ramp above 0 (0 itself is black). Made for this project: from a dark violet that stands out
// from black, through magenta, red-orange and orange, to pale yellow. Every channel rises or stays
// from each point to the next, so that the luminance of the ramp, and of every colour rounded from it,
// never falls (tests/grade_report_test.cpp checks it at fine steps).
constexpr ControlPoint kRamp[] = {
    {0.00f, 40, 10, 90},   {0.15f, 84, 16, 118},   {0.30f, 128, 28, 124},  {0.45f, 172, 42, 124},
    {0.60f, 214, 64, 124}, {0.75f, 242, 110, 124}, {0.90f, 254, 174, 130}, {1.00f, 255, 240, 176},
};
// The gap between a heat map and its colour bar.
constexpr uint8_t kGapGrey = 128;
constexpr uint32_t kGapRows = 2;

void put(ImageRgba8& image, uint32_t x, uint32_t y, std::array<uint8_t, 3> rgb) {
    uint8_t* p = image.pixels.data() + 4 * (size_t(y) * image.width + x);
    p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
}

// Rows y0 to y0 + rows of `image` filled with the ramp, 0 at the left, 1 at the right.
void drawRamp(ImageRgba8& image, uint32_t y0, uint32_t rows) {
    for (uint32_t x = 0; x < image.width; ++x) {
        const auto rgb = heatColour(image.width > 1 ? float(x) / float(image.width - 1) : 1.0f);
        for (uint32_t y = y0; y < y0 + rows; ++y) put(image, x, y, rgb);
    }
}

}  // namespace

std::array<uint8_t, 3> heatColour(float error) {
    const float t = std::isnan(error) ? 1.0f : std::clamp(error, 0.0f, 1.0f);
    if (t == 0.0f) return {0, 0, 0};
    size_t k = 1;
    while (k + 1 < std::size(kRamp) && t > kRamp[k].at) ++k;
    const ControlPoint &a = kRamp[k - 1], &b = kRamp[k];
    const float f = (t - a.at) / (b.at - a.at);
    auto mix = [f](uint8_t from, uint8_t to) {
        return uint8_t(std::lround(float(from) + (float(to) - float(from)) * f));
    };
    return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

ImageRgba8 heatMap(std::span<const float> error, uint32_t width, uint32_t height, HeatMapOptions options) {
    RASTER_REQUIRE(
        width > 0 && height > 0, InvalidArgument,
        "a heat map of " + std::to_string(width) + "x" + std::to_string(height) + " pixels has no pixel");
    RASTER_REQUIRE(error.size() == size_t(width) * height, InvalidArgument,
                   "a heat map of " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                       std::to_string(size_t(width) * height) + " error values, not " +
                       std::to_string(error.size()));
    const uint32_t bar = options.colourBar ? std::max<uint32_t>(4, height / 12) : 0;
    const uint32_t gap = options.colourBar ? kGapRows : 0;
    ImageRgba8 image{width, height + gap + bar, {}};
    image.pixels.assign(size_t(image.width) * image.height * 4, 255);
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) put(image, x, y, heatColour(error[size_t(y) * width + x]));
    for (uint32_t y = height; y < height + gap; ++y)
        for (uint32_t x = 0; x < width; ++x) put(image, x, y, {kGapGrey, kGapGrey, kGapGrey});
    drawRamp(image, height + gap, bar);
    return image;
}

std::vector<float> differenceErrors(const DifferenceMap& map, int full_scale_steps) {
    RASTER_REQUIRE(
        full_scale_steps >= 1 && full_scale_steps <= 255, InvalidArgument,
        "a heat map's full scale of " + std::to_string(full_scale_steps) + " steps is not in 1..255");
    RASTER_REQUIRE(map.largest.size() == size_t(map.width) * map.height, InvalidArgument,
                   "a difference map of " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                       " holds " + std::to_string(map.largest.size()) + " values");
    std::vector<float> errors(map.largest.size());
    for (size_t i = 0; i < errors.size(); ++i)
        errors[i] = float(std::min<int>(map.largest[i], full_scale_steps)) / float(full_scale_steps);
    return errors;
}

ImageRgba8 heatMap(const DifferenceMap& map, int full_scale_steps, HeatMapOptions options) {
    return heatMap(differenceErrors(map, full_scale_steps), map.width, map.height, options);
}

ImageRgba8 colourBar(uint32_t width, uint32_t height) {
    RASTER_REQUIRE(
        width > 0 && height > 0, InvalidArgument,
        "a colour bar of " + std::to_string(width) + "x" + std::to_string(height) + " pixels has no pixel");
    ImageRgba8 image{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
    drawRamp(image, 0, height);
    return image;
}

}  // namespace raster::grade
