// The viewer's solution views (--solution, keys K and J) as plain images without SDL, so that tests
// can compute what the window must show: the difference between the shown frame and a solution
// image (the reference pipeline's, another scene's, a PNG's) and its statistics as the HUD shows
// them (computed by raster/image_compare.hpp), and what --solution names.
//
// Images are RGBA8, row 0 on top, one pixel per framebuffer pixel (as in trace_views.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "raster/image_compare.hpp"
#include "trace_views.hpp"

namespace raster::tools {

// What --solution names. Throws Error(InvalidArgument) naming the value when it is none of
// "reference", a scene of sceneNames() or a path ending in .png; an empty value is None.
struct SolutionSource {
    enum class Kind { None, Reference, Scene, Image };
    Kind kind = Kind::None;
    std::string name;  // Scene: the scene; Image: the path
};
SolutionSource parseSolution(std::string_view value);
// "the reference pipeline", "scene fog", "lab1.png": what the HUD calls it.
std::string solutionLabel(const SolutionSource& solution);

// The HUD's lines about a difference from `label`, whose figures raster::compareImages computed
// (raster/image_compare.hpp; the viewer compares all four channels).
std::vector<std::string> describeDifference(const ImageDifference& d, const std::string& label);

// The difference view's ramp for a pixel whose largest channel difference is `d`: black for 0; from
// dark grey for 1 to pure red for `max` (the image's largest), so the worst pixels are the brightest
// and the smallest difference still shows.
Rgb differenceColour(int d, int max);
// Per pixel, differenceColour of the largest channel difference between a and b (RGBA8 images of
// width × height each; raster::differenceMap), as an RGBA8 image.
std::vector<uint8_t> differenceImage(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                                     uint32_t width, uint32_t height);

// `rgba` (width × height) resampled to toWidth × toHeight by nearest pixel: a solution PNG of
// another size, shown in the frame's place.
std::vector<uint8_t> scaleNearest(const std::vector<uint8_t>& rgba, uint32_t width, uint32_t height,
                                  uint32_t toWidth, uint32_t toHeight);

}  // namespace raster::tools
