// The viewer's solution views (--solution, keys K and J) as plain images without SDL, so that tests
// can compute what the window must show: the difference between the shown frame and a solution
// image (the reference pipeline's, another scene's, a PNG's), its statistics, and what --solution
// names.
//
// Images are RGBA8, row 0 on top, one pixel per framebuffer pixel (as in trace_views.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

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

// The figures ../shared/anchors/imgdiff.cpp reports, over the channels compared.
struct ImageDifference {
    size_t pixels = 0;                // compared
    size_t differing = 0;             // pixels with any channel different
    int max = 0;                      // the largest channel difference, 0..255
    uint32_t maxX = 0, maxY = 0;      // the first pixel (row by row) with it
    double meanAbs = 0;               // mean |a − b| over every channel of every pixel, in 1/255
    size_t within1 = 0, within3 = 0;  // pixels whose largest channel difference is <= 1, <= 3
};
// a and b: RGBA8 images of width × height each. `channels`: 4 compares RGBA (the viewer), 3 only
// RGB (raster bench's error against the reference: what is seen, as compare.sh measures it).
ImageDifference compareImages(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, uint32_t width,
                              uint32_t height, int channels = 4);
// The HUD's lines about a difference from `label`.
std::vector<std::string> describeDifference(const ImageDifference& d, const std::string& label);

// The difference view's ramp for a pixel whose largest channel difference is `d`: black for 0; from
// dark grey for 1 to pure red for `max` (the image's largest), so the worst pixels are the brightest
// and the smallest difference still shows.
Rgb differenceColour(int d, int max);
// Per pixel, differenceColour of the largest channel difference between a and b.
std::vector<uint8_t> differenceImage(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b,
                                     uint32_t width, uint32_t height);

// `rgba` (width × height) resampled to toWidth × toHeight by nearest pixel: a solution PNG of
// another size, shown in the frame's place.
std::vector<uint8_t> scaleNearest(const std::vector<uint8_t>& rgba, uint32_t width, uint32_t height,
                                  uint32_t toWidth, uint32_t toHeight);

}  // namespace raster::tools
