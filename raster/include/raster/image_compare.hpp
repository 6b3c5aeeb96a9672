// How far apart two RGBA8 images are: the figures the viewer's difference view (raster view
// --solution, key J) and raster bench's error against the reference pipeline report, and a grader
// can check, computed in one place.
//
//   const raster::ImageDifference d = raster::compareImages({lab, w, h}, {solution, w, h});
//   if (d.max > 3) ...                       // some channel is more than 3/255 off
//   const raster::DifferenceMap map = raster::differenceMap(lab_image, solution_image);
//   map.at(x, y)                             // that pixel's largest channel difference
//
// Units: differences are in RGBA8 channel steps, |a − b| of two 8-bit channel values, so 1 is
// 1/255 of full intensity and 255 the most there is. Images are RGBA8, 4 bytes a pixel, row 0 on
// top (RenderTarget::toRgba8, ImageRgba8); both must have the same width and height.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "raster/image_io.hpp"

namespace raster {

// An RGBA8 image to compare, borrowed (the pixels must outlive the view). Throws
// Error(InvalidArgument) naming the byte count and the size when the pixels are not 4 · width ·
// height bytes.
class Rgba8View {
  public:
    Rgba8View(std::span<const uint8_t> pixels, uint32_t width, uint32_t height);
    // Implicit, so that an ImageRgba8 (a PNG read, a screenshot) is passed as it is.
    Rgba8View(const ImageRgba8& image) : Rgba8View(image.pixels, image.width, image.height) {}

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    std::span<const uint8_t> pixels() const { return pixels_; }
    // The 4 bytes of pixel i (row-major).
    const uint8_t* pixel(size_t i) const { return pixels_.data() + 4 * i; }

  private:
    std::span<const uint8_t> pixels_;
    uint32_t width_, height_;
};

// Which channels count: all four (the viewer, a grader), or red, green and blue only, what is
// seen (raster bench's error against the reference, as ../shared/anchors/compare.sh measures it).
enum class CompareChannels : uint8_t { Rgb = 3, Rgba = 4 };

// The largest |a[c] − b[c]| over the channels compared, for one pixel (4 bytes each), 0..255.
int largestChannelDifference(const uint8_t* a, const uint8_t* b,
                             CompareChannels channels = CompareChannels::Rgba);

// Summary figures of a comparison (what ../shared/anchors/imgdiff.cpp reports). Counts are of
// pixels; a pixel's difference is its largest channel difference.
struct ImageDifference {
    uint32_t width = 0, height = 0;   // of both images
    size_t pixels = 0;                // compared: width · height
    size_t differing = 0;             // pixels with any compared channel different
    int max = 0;                      // the largest channel difference, 0..255 steps
    uint32_t maxX = 0, maxY = 0;      // the first pixel (row by row) with it; 0, 0 when identical
    double meanAbs = 0;               // mean |a − b| over every compared channel of every pixel, in steps
    size_t within1 = 0, within3 = 0;  // pixels whose difference is ≤ 1 step, ≤ 3 steps

    bool identical() const { return differing == 0; }
    // count / pixels, as a fraction in [0, 1]; 1 for images without pixels (nothing differs).
    double share(size_t count) const { return pixels > 0 ? double(count) / double(pixels) : 1.0; }
};

// Per pixel, the largest channel difference between two images: an image of its own, one byte a
// pixel, row 0 on top, to show (the viewer's difference view) or to inspect (where a grader found
// the worst pixel).
struct DifferenceMap {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> largest;  // width · height values, 0..255 steps
    int max = 0;                   // the largest of them

    uint8_t at(uint32_t x, uint32_t y) const { return largest[size_t(y) * width + x]; }
};

// Both throw Error(InvalidArgument) naming both sizes ("3x2 and 2x2") when the images' sizes differ.
ImageDifference compareImages(Rgba8View a, Rgba8View b, CompareChannels channels = CompareChannels::Rgba);
DifferenceMap differenceMap(Rgba8View a, Rgba8View b, CompareChannels channels = CompareChannels::Rgba);

}  // namespace raster
