#include "raster/image_compare.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "raster/check.hpp"

namespace raster {
namespace {

std::string sizeText(uint32_t width, uint32_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

void requireSameSize(const Rgba8View& a, const Rgba8View& b) {
    RASTER_REQUIRE(a.width() == b.width() && a.height() == b.height(), InvalidArgument,
                   "comparing images of different sizes: " + sizeText(a.width(), a.height()) + " and " +
                       sizeText(b.width(), b.height()));
}

void requireChannels(CompareChannels channels) {
    RASTER_REQUIRE(channels == CompareChannels::Rgb || channels == CompareChannels::Rgba, InvalidArgument,
                   "comparing " + std::to_string(int(channels)) + " channels (3: RGB, 4: RGBA)");
}

}  // namespace

Rgba8View::Rgba8View(std::span<const uint8_t> pixels, uint32_t width, uint32_t height)
    : pixels_(pixels), width_(width), height_(height) {
    RASTER_REQUIRE(pixels.size() == byteCount(byteCount(width, height), 4), InvalidArgument,
                   "an RGBA8 image of " + sizeText(width, height) + " needs " +
                       std::to_string(byteCount(byteCount(width, height), 4)) + " bytes, not " +
                       std::to_string(pixels.size()));
}

int largestChannelDifference(const uint8_t* a, const uint8_t* b, CompareChannels channels) {
    int m = 0;
    for (int c = 0; c < int(channels); ++c) m = std::max(m, std::abs(int(a[c]) - int(b[c])));
    return m;
}

ImageDifference compareImages(Rgba8View a, Rgba8View b, CompareChannels channels) {
    requireSameSize(a, b);
    requireChannels(channels);
    ImageDifference d;
    d.width = a.width(), d.height = a.height();
    d.pixels = size_t(d.width) * d.height;
    uint64_t sum = 0;  // of every channel's |a − b|: at most 255 · 4 · 16384² fits
    for (size_t i = 0; i < d.pixels; ++i) {
        const uint8_t *p = a.pixel(i), *q = b.pixel(i);
        for (int c = 0; c < int(channels); ++c) sum += uint64_t(std::abs(int(p[c]) - int(q[c])));
        const int m = largestChannelDifference(p, q, channels);
        d.differing += m > 0;
        d.within1 += m <= 1;
        d.within3 += m <= 3;
        if (m > d.max) d.max = m, d.maxX = uint32_t(i % d.width), d.maxY = uint32_t(i / d.width);
    }
    d.meanAbs = d.pixels > 0 ? double(sum) / (double(int(channels)) * double(d.pixels)) : 0.0;
    return d;
}

DifferenceMap differenceMap(Rgba8View a, Rgba8View b, CompareChannels channels) {
    requireSameSize(a, b);
    requireChannels(channels);
    DifferenceMap map;
    map.width = a.width(), map.height = a.height();
    map.largest.resize(size_t(map.width) * map.height);
    for (size_t i = 0; i < map.largest.size(); ++i) {
        map.largest[i] = uint8_t(largestChannelDifference(a.pixel(i), b.pixel(i), channels));
        map.max = std::max(map.max, int(map.largest[i]));
    }
    return map;
}

}  // namespace raster
