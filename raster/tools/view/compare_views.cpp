#include "compare_views.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "raster/check.hpp"
#include "raster/scenes.hpp"

namespace raster::tools {
namespace {

constexpr int kGreyOfOne = 64;  // the difference view's smallest difference: dark grey, still visible

std::string percent(size_t part, size_t whole) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3f%%", whole > 0 ? 100.0 * double(part) / double(whole) : 100.0);
    return text;
}

}  // namespace

SolutionSource parseSolution(std::string_view value) {
    if (value.empty()) return {};
    if (value == "reference") return {SolutionSource::Kind::Reference, "reference"};
    std::string scenes;
    for (const std::string& name : sceneNames()) {
        if (value == name) return {SolutionSource::Kind::Scene, name};
        scenes += (scenes.empty() ? "" : ", ") + name;
    }
    std::string lower(value);
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (lower.size() > 4 && lower.ends_with(".png")) return {SolutionSource::Kind::Image, std::string(value)};
    throw Error(ErrorCode::InvalidArgument, "unknown --solution '" + std::string(value) +
                                                "' (reference, a scene: " + scenes + ", or a .png file)");
}

std::string solutionLabel(const SolutionSource& solution) {
    switch (solution.kind) {
        case SolutionSource::Kind::Reference:
            return "the reference pipeline";
        case SolutionSource::Kind::Scene:
            return "scene " + solution.name;
        case SolutionSource::Kind::Image:
            return solution.name;
        default:
            return "no solution";
    }
}

std::vector<std::string> describeDifference(const ImageDifference& d, const std::string& label) {
    std::string first = "difference from " + label + ": " + std::to_string(d.differing) + " of " +
                        std::to_string(d.pixels) + " pixels differ";
    if (d.differing == 0) return {first + " (identical)"};
    first += " (" + percent(d.differing, d.pixels) + "), largest " + std::to_string(d.max) + "/255 at " +
             std::to_string(d.maxX) + "," + std::to_string(d.maxY);
    char mean[32];
    std::snprintf(mean, sizeof mean, "%.6f", d.meanAbs);
    return {first,
            std::string("mean |difference| ") + mean + "/255; pixels within 1/255 " +
                percent(d.within1, d.pixels) + ", within 3/255 " + percent(d.within3, d.pixels),
            "black equal, grey 1/255 .. red " + std::to_string(d.max) + "/255"};
}

Rgb differenceColour(int d, int max) {
    if (d <= 0) return {0, 0, 0};
    if (max <= 1 || d >= max) return {255, 0, 0};
    const double t = double(d - 1) / double(max - 1);
    const uint8_t grey = uint8_t(kGreyOfOne * (1.0 - t));
    return {uint8_t(kGreyOfOne + (255 - kGreyOfOne) * t), grey, grey};
}

std::vector<uint8_t> differenceImage(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                                     uint32_t width, uint32_t height) {
    const DifferenceMap map = differenceMap({a, width, height}, {b, width, height});
    std::vector<uint8_t> rgba(4 * map.largest.size());
    for (size_t i = 0; i < map.largest.size(); ++i) {
        const Rgb c = differenceColour(map.largest[i], map.max);
        rgba[4 * i] = c[0], rgba[4 * i + 1] = c[1], rgba[4 * i + 2] = c[2], rgba[4 * i + 3] = 255;
    }
    return rgba;
}

std::vector<uint8_t> scaleNearest(const std::vector<uint8_t>& rgba, uint32_t width, uint32_t height,
                                  uint32_t toWidth, uint32_t toHeight) {
    std::vector<uint8_t> out(size_t(4) * toWidth * toHeight);
    if (width == 0 || height == 0 || rgba.size() < size_t(4) * width * height) return out;
    for (uint32_t y = 0; y < toHeight; ++y)
        for (uint32_t x = 0; x < toWidth; ++x) {
            // The source pixel whose area holds the target pixel's centre.
            const size_t sx = size_t((uint64_t(2 * x + 1) * width) / (2 * uint64_t(toWidth)));
            const size_t sy = size_t((uint64_t(2 * y + 1) * height) / (2 * uint64_t(toHeight)));
            std::copy_n(&rgba[4 * (sy * width + sx)], 4, &out[4 * (size_t(y) * toWidth + x)]);
        }
    return out;
}

}  // namespace raster::tools
