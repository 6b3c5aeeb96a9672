// How far apart two RGBA8 images are: the figures the viewer's difference view (raster view
// --solution, key J) and raster bench's error against the reference pipeline report, and a grader
// can check, computed in one place; and below, the comparisons a grader scores with (exact, per-channel
// threshold, position deviation, LDR-FLIP), their common result and a comparison read from JSON.
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

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
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

// ---- Grading: one result for four comparisons, and a comparison described by data ----
//
// A grader compares a lab's render (the result) with the solution's (the reference) by the rule the
// lab's grading declaration names for the scene:
//
//   const raster::Comparison rule =
//       raster::Comparison::parse(R"({"method": "position", "deviation": 1, "rgba": [1, 1, 1, 1]})");
//   const raster::ComparisonResult r = raster::compare(rule, solution_image, lab_image);
//   if (!r.passed) {
//       const raster::PixelRegion worst = raster::largestFailingRegion(r);
//       ... worst.x, worst.y: a pixel to show (or to trace) in the largest wrong area
//   }
//
//   method     a pixel fails when                                        the image passes when
//   exact      any channel differs                                       no pixel fails
//   threshold  any channel differs by more than its allowance            no pixel fails
//   position   no pixel within ±N (per axis) matches it within the       no pixel fails
//              allowances, from either image to the other (or one way)
//   flip       its LDR-FLIP error is above a level (0.05)                the mean FLIP error ≤ a limit (0.05)
//
// The first three are dEQP's (VK-GL-CTS framework/common/tcuImageCompare.cpp) bitwiseCompare on
// RGBA8, intThresholdCompare and intThresholdPositionDeviationCompare, on 2D images; the fourth is
// the perceptual metric of Andersson et al., "FLIP: A Difference Evaluator for Alternating Images"
// (HPG 2020). Every one of them throws Error(InvalidArgument) naming both sizes ("3x2 and 2x3") when
// the images' sizes differ, as compareImages does, and for options out of their documented ranges.

enum class CompareMethod : uint8_t { Exact, Threshold, Position, Flip };
// "exact", "threshold", "position", "flip": the names the JSON says.
const char* compareMethodName(CompareMethod method);

// What any comparison found. Every field is filled by every method.
struct ComparisonResult {
    CompareMethod method = CompareMethod::Exact;
    bool passed = true;  // figure ≤ limit
    // The method's figure and the most it passes with:
    //   exact, threshold, position: the number of failing pixels, limit 0 (as dEQP: one pixel fails all);
    //   flip: the mean FLIP error over all pixels, in [0, 1], limit FlipOptions::meanLimit.
    double figure = 0, limit = 0;
    size_t failing = 0;  // pixels whose error is above failLevel
    uint32_t width = 0, height = 0;
    // Per pixel, row-major with row 0 on top, width · height values in [0, 1], 0 where the pixel is
    // right: the heat map. Exact, threshold and position: how far the pixel is past its allowance,
    // the largest over channels of max(0, |reference − result| − allowance) / 255 (position: of the
    // best match within the window, the worse of the two directions), so 1/255 is one step over and
    // a pixel fails exactly when this is above 0. Flip: the pixel's FLIP error.
    std::vector<float> error;
    // A pixel fails when its error is above this: 0 for exact, threshold and position, so that the
    // failing pixels are those the rule refuses; FlipOptions::pixelLimit for flip (FLIP passes on the
    // mean, so a passing FLIP comparison may have failing pixels: visible but small differences).
    float failLevel = 0;
    uint32_t worstX = 0, worstY = 0;  // the first pixel (row by row) with the largest error; 0, 0 if none
    float worstError = 0;             // its error, 0 when every pixel is right

    float at(uint32_t x, uint32_t y) const { return error[size_t(y) * width + x]; }
    bool failingAt(uint32_t x, uint32_t y) const { return at(x, y) > failLevel; }
};

// A connected set of failing pixels, and one pixel to show for it.
struct PixelRegion {
    size_t pixels = 0;           // failing pixels in the region; 0 when no pixel fails
    uint32_t x = 0, y = 0;       // its representative: the pixel with the largest error,
    float error = 0;             //   the first row by row among equals; and that error
    uint32_t left = 0, top = 0;  // its bounding box, inclusive, in pixels
    uint32_t right = 0, bottom = 0;
};

// The largest region of failing pixels (result.failingAt), 8-connected: pixels that touch by an edge
// or a corner belong together, so that the staircase of a wrong diagonal edge is one region, not one
// per step. The largest counts the most pixels; among equals, the one whose first pixel comes first
// row by row. All of it is deterministic: the same result gives the same region and pixel. Linear
// in the pixel count (a flood fill with its own stack, no recursion).
PixelRegion largestFailingRegion(const ComparisonResult& result);

// An allowance per channel, red, green, blue, alpha, in RGBA8 steps (4 = 4/255, dEQP's blend tests'
// allowance on RGBA8). 255 lets the channel take any value: {0, 0, 0, 255} compares RGB exactly and
// ignores alpha.
using Rgba8Threshold = std::array<uint8_t, 4>;

// Every channel of every pixel equal: dEQP's bitwiseCompare for RGBA8, and a threshold of {0, 0, 0, 0}.
ComparisonResult compareExact(Rgba8View reference, Rgba8View result);

// dEQP's intThresholdCompare: a pixel passes when |reference − result| ≤ threshold[c] for every
// channel c (equality passes: a difference of exactly the allowance is allowed); the image passes
// when every pixel does.
ComparisonResult compareThreshold(Rgba8View reference, Rgba8View result, Rgba8Threshold threshold);

// Which ways comparePosition looks for a match.
enum class PositionCheck : uint8_t {
    // dEQP's rule (it checks both ways at every pixel): a pixel passes when the result's pixel is
    // matched by a reference pixel in its window AND the reference's pixel by a result pixel in its
    // window. So both extra pixels (drawn where the reference has none near) and missing ones fail,
    // even a missing line one pixel wide, which a one-way check lets through (its neighbours match
    // the background). What coverage grading needs; the default.
    Both,
    // Only the first half: each result pixel must be matched by some reference pixel near it. Extra
    // pixels fail, missing thin features may not.
    ResultInReference,
};

// dEQP's intThresholdPositionDeviationCompare with maxPositionDeviation (deviationX, deviationY, 0).
struct PositionTolerance {
    // The window: pixels (x + i, y + j) with |i| ≤ deviationX, |j| ≤ deviationY, 0..kMaxDeviation.
    // 0 and 0 is compareThreshold. 1 forgives an edge drawn one pixel off: an edge that falls half a
    // pixel elsewhere (a pixel centre on the other side of it) moves by a whole column or row.
    uint32_t deviationX = 1, deviationY = 1;
    Rgba8Threshold threshold{};  // a match is within these, per channel, as compareThreshold
    // At the border, as dEQP's acceptOutOfBoundsAsAnyValue. false: the window is cut to the image
    // (pixels outside are not candidates), so a border pixel has fewer chances to match. true: a
    // pixel whose window reaches outside the image (x < deviationX, x + deviationX ≥ width, and so
    // for y) is not checked at all and passes, since what lies outside "could be anything"; with an
    // image no larger than 2 · deviation in a direction, every pixel passes.
    bool acceptOutOfBounds = false;
    PositionCheck check = PositionCheck::Both;

    // The largest deviation taken: the work at a differing pixel grows with (2N + 1)², and a
    // difference that needs more than a few pixels of slack is not a rasterization difference.
    static constexpr uint32_t kMaxDeviation = 16;
};

ComparisonResult comparePosition(Rgba8View reference, Rgba8View result, const PositionTolerance& tolerance);

// LDR-FLIP, written from the paper (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild,
// "FLIP: A Difference Evaluator for Alternating Images", HPG 2020, and its reference code's
// constants, NVlabs/flip), per pixel of two sRGB images (alpha is not seen: the images are compared
// as shown, opaque):
//   1. sRGB bytes → linear RGB → XYZ (D65) → the opponent space YCxCz (linear in XYZ).
//   2. Colour: each YCxCz channel filtered by its contrast sensitivity function, a Gaussian (achromatic,
//      red–green) or a sum of two (blue–yellow), scaled by pixels per degree, each kernel normalised
//      to sum 1; back to linear RGB clamped to [0, 1]; to CIE L*a*b* with the Hunt adjustment
//      (a*, b* times 0.01 · L*); the HyAB distance |ΔL*| + ‖(Δa*, Δb*)‖; raised to 0.7 and mapped
//      into [0, 1]: [0, 0.4 · cmax] onto [0, 0.95] linearly, the rest onto (0.95, 1], where cmax is
//      the largest such distance (green against blue) raised to 0.7. That is ΔE_c.
//   3. Features: on the luminance Y/Yn of the unfiltered image, edges (first derivative of a Gaussian
//      of σ = 0.5 · 0.082° · ppd pixels) and points (its second derivative), in x and y, each kernel's
//      positive weights normalised to sum 1 and negative ones to −1; ΔE_f = (max(|‖edge_a‖ −
//      ‖edge_b‖|, |‖point_a‖ − ‖point_b‖|) / √2)^0.5, in [0, 1].
//   4. The pixel's error: ΔE_c^(1 − ΔE_f), in [0, 1]; the figure is its mean.
// Filters read past the border as clamp-to-edge (the reference code's BORDER_REPLICATE). With
// normalised kernels this makes every filter the identity on a uniform image: the colour filters
// return the colour, the feature filters (weights summing to 0) return 0, so two uniform images
// differ by ΔE_c of their two colours alone, at every pixel. Where this differs from the reference
// code, in rounding only: the filters run as separable passes (the same kernels, factored), in float,
// and the odd and zero-sum kernels are applied as weighted differences, so that a uniform image gives
// exactly 0 features (a sum of rounded weights leaves about 1e-8: 1e-4 after ΔE_f's square root).
//
// Checked against tests/flip_direct.py, the metric computed directly in double from the 2D kernels
// as written: per pixel within 1.4e-6 at 67, 20 and 1.5 ppd (CompareFlip.MatchesADirectRendition checks
// 67 and 20 to 1e-5).
//
// Cost: single-threaded, so the bits depend only on the input (and on libm: powf per pixel; exp and
// pow once, for the kernels and the sRGB table). On this project's 2-core machine (AMD EPYC, Zen 3; GCC 12,
// -O3 -march=native), a 1280x720 pair takes 139 ms (best of 7, process CPU time; 139 ms wall when the machine
// was otherwise idle), measured 2026-12-03 on grade-compare: a third in the separable filters,
// a third in the per-pixel colour conversions, a sixth in first touches of fresh memory. It grows with width
// · height · ppd. Memory: 14 float planes of the image's size at the peak (52 MB at 1280x720).
struct FlipOptions {
    // Pixels per degree of visual angle: the viewer's distance. 67 is the paper's (a 0.7 m wide 4K
    // display seen from 0.7 m). 1..1000; kernel radii grow with it (10 and 9 pixels at 67).
    double ppd = 67.0;
    double meanLimit = 0.05;   // the image passes when the mean error ≤ this (FLIP's tool's default), 0..1
    double pixelLimit = 0.05;  // a pixel counts as failing when its error > this, 0..1
};

ComparisonResult compareFlip(Rgba8View reference, Rgba8View result, const FlipOptions& options = {});

// A comparison as data: what a lab's grading declaration says for a scene. JSON, one object:
//   {"method": "exact"}
//   {"method": "threshold", "rgba": [4, 4, 4, 4]}                      rgba required
//   {"method": "position", "deviation": 1, "rgba": [1, 1, 1, 1]}       deviation required: N or [x, y];
//       rgba default [0, 0, 0, 0]; "acceptOutOfBounds": false, "symmetric": true (false: ResultInReference)
//   {"method": "flip", "mean": 0.05, "ppd": 67}                       all optional, as FlipOptions;
//       "pixel" (the pixel level) defaults to "mean"
// Integers must be JSON integers (4, not 4.0). A field the method does not take is an error (a
// misspelt "rgab" must not be read as "no allowance").
struct Comparison {
    CompareMethod method = CompareMethod::Exact;
    Rgba8Threshold threshold{};  // used by Threshold
    PositionTolerance position;  // used by Position
    FlipOptions flip;            // used by Flip

    // Throws Error(InvalidArgument) "comparison: ..." naming the field and what was wrong (not JSON,
    // not an object, no or an unknown "method", an unknown field, a wrong type, a value out of range).
    static Comparison parse(std::string_view json);
    // In words, for a report: "threshold: every pixel within 4/255 in every channel of the reference's".
    std::string describe() const;
};

// Runs the comparison's method with its options: compareExact, compareThreshold, comparePosition or
// compareFlip (and throws as they do).
ComparisonResult compare(const Comparison& comparison, Rgba8View reference, Rgba8View result);

}  // namespace raster
