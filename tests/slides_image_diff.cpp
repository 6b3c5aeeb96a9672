// Compares pairs of PNG files through the project's image comparison (raster/image_compare.hpp), for
// tests/slides_figures_test.py: the slides' committed figures against fresh renders.
//
//   slides_image_diff EXPECTED ACTUAL [EXPECTED ACTUAL ...]
//
// One line a pair: "same" or "differs" with the differing pixels, the largest channel difference (in
// 8-bit steps) and its first pixel, or the sizes when they differ. Exit 0 when every pair is
// identical, 1 otherwise (2 for a usage error, a file that does not read).
#include <cstdio>
#include <exception>

#include "raster/image_compare.hpp"
#include "raster/image_io.hpp"

int main(int argc, char** argv) {
    if (argc < 3 || argc % 2 != 1) {
        std::fprintf(stderr, "usage: slides_image_diff EXPECTED ACTUAL [EXPECTED ACTUAL ...]\n");
        return 2;
    }
    int differing = 0;
    try {
        for (int k = 1; k + 1 < argc; k += 2) {
            const raster::ImageRgba8 expected = raster::readImageRgba8(argv[k]);
            const raster::ImageRgba8 actual = raster::readImageRgba8(argv[k + 1]);
            if (expected.width != actual.width || expected.height != actual.height) {
                std::printf("differs %s: %ux%u, rendered %ux%u\n", argv[k], expected.width, expected.height,
                            actual.width, actual.height);
                ++differing;
                continue;
            }
            const raster::ImageDifference d = raster::compareImages(expected, actual);
            if (d.identical()) {
                std::printf("same %s\n", argv[k]);
            } else {
                std::printf("differs %s: %zu of %zu pixels, largest difference %d steps at (%u, %u)\n", argv[k],
                            d.differing, d.pixels, d.max, d.maxX, d.maxY);
                ++differing;
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "slides_image_diff: %s\n", e.what());
        return 2;
    }
    return differing == 0 ? 0 : 1;
}
