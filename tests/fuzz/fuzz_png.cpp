// libFuzzer target: the image decoder (image_io.hpp's decodeImageRgba8, which readImageRgba8 and
// Texture2D::fromPng use) and texture creation from what it decodes.
//
// The contract checked:
//  - decodeImageRgba8 either throws raster::Error(BadFile) naming the input, or returns an image
//    within the documented limits (kMaxImageSide a side, kMaxImagePixels in all) whose pixel
//    bytes are exactly 4·width·height;
//  - the decoded image makes a Texture2D (as fromPng does: fromRgba8), with and without mipmaps,
//    of its size, whose level 0 loads back the decoded bytes, whose samples are finite and within
//    [0, 1], and whose alpha spans (texture.hpp) hold every texel of alpha > 0;
//  - anything else — another exception, a crash, a sanitizer report, a hang, an allocation over
//    libFuzzer's -malloc_limit_mb — is a finding.
// Textures are made only for images of at most 2^16 pixels (mipmaps: 2^12), so that one input
// runs in milliseconds.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

#include "raster/check.hpp"
#include "raster/format.hpp"
#include "raster/image_io.hpp"
#include "raster/sampler.hpp"
#include "raster/texture.hpp"

namespace {

using namespace raster;

constexpr const char* kName = "fuzz input";

[[noreturn]] void finding(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz_png: contract broken: %s %s\n", what, detail.c_str());
    std::abort();
}

void checkTexture(const ImageRgba8& image, bool mipmaps) {
    const Texture2D t = Texture2D::fromRgba8(image.width, image.height, image.pixels, mipmaps);
    if (t.width() != image.width || t.height() != image.height)
        finding("texture size differs from the image's");
    const uint32_t w = image.width, h = image.height;
    // Level 0 is the image; a few texels suffice, the corners and the middle.
    const uint32_t xs[] = {0, w / 2, w - 1}, ys[] = {0, h / 2, h - 1};
    for (uint32_t y : ys)
        for (uint32_t x : xs) {
            const glm::vec4 texel = t.load(int(x), int(y));
            for (int c = 0; c < 4; ++c)
                if (texel[c] != unorm8ToFloat(image.pixels[4 * (size_t(y) * w + x) + size_t(c)]))
                    finding("texture level 0 differs from the decoded image");
        }
    for (const SamplerState& s :
         {SamplerState{}, SamplerState::point(AddressMode::Wrap), SamplerState::bilinear(AddressMode::Border),
          SamplerState::linear(AddressMode::Mirror)}) {
        for (const glm::vec2 uv : {glm::vec2(0.5f), glm::vec2(-0.25f, 1.75f), glm::vec2(1e-3f, 0.999f)}) {
            for (const float lod : {0.0f, 1.5f, 30.0f}) {
                const glm::vec4 v = t.SampleLevel(s, uv, lod);
                for (int c = 0; c < 4; ++c)
                    if (!(v[c] >= 0.0f && v[c] <= 1.0f))
                        finding("a sample outside [0, 1]", std::to_string(v[c]));
            }
        }
    }
    if (mipmaps) return;
    const auto spans = t.alphaSpans();
    if (spans.size() != h) finding("alpha spans: not one per row");
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            if (image.pixels[4 * (size_t(y) * w + x) + 3] != 0 &&
                !(spans[y].first <= int32_t(x) && int32_t(x) <= spans[y].last))
                finding("alpha spans miss a texel of alpha > 0");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ImageRgba8 image;
    try {
        image = decodeImageRgba8(std::span<const uint8_t>(data, size), kName);
    } catch (const Error& e) {
        if (e.code() != ErrorCode::BadFile) finding("decode threw other than BadFile:", e.what());
        if (std::string(e.what()).find(kName) == std::string::npos)
            finding("the error does not name the input:", e.what());
        return 0;
    }
    if (image.width == 0 || image.height == 0 || image.width > kMaxImageSide ||
        image.height > kMaxImageSide || uint64_t(image.width) * image.height > kMaxImagePixels)
        finding("decoded an image outside the limits:",
                std::to_string(image.width) + "x" + std::to_string(image.height));
    if (image.pixels.size() != 4 * size_t(image.width) * image.height)
        finding("pixel bytes are not 4 per pixel");
    const uint64_t pixels = uint64_t(image.width) * image.height;
    if (pixels <= (1u << 16)) checkTexture(image, false);
    if (pixels <= (1u << 12)) checkTexture(image, true);
    return 0;
}
