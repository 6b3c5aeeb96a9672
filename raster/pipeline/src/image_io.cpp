#include "raster/image_io.hpp"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <memory>

#include "raster/check.hpp"

// PNG only: the project reads nothing else, and each of stb_image's other decoders is more code
// that a file can reach. (fuzz_png found one: Debian 12's stb_image 2.27 overflows a signed int
// parsing a PNM header, `P6 2 3333333333 255`, undefined behaviour that 2.28 fixes.)
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_FAILURE_USERMSG
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace raster {

namespace {

std::string stbReason() {
    return stbi_failure_reason() ? stbi_failure_reason() : "?";
}

std::string sizeText(uint64_t width, uint64_t height) {
    return std::to_string(width) + "x" + std::to_string(height);
}

uint32_t bigEndian32(const uint8_t* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

// The PNG's chunks walked before stb_image reads them, for what it does not check in time:
//  - a chunk whose length runs past the end of the bytes is refused (stb allocates an IDAT's length,
//    rounded up to a power of two, before it reads the data: 229 bytes asked for 2 GiB, fuzz_png);
//  - empty IDAT chunks are dropped (they hold no data, and stb 2.27 reads an empty first one with
//    memcpy(nullptr, ..., 0), undefined behaviour that fuzz_png found).
// Returns the PNG without its empty IDATs, or nothing if it has none (or the bytes are no PNG).
// The walk ends at IEND; what follows it is kept as it is.
std::vector<uint8_t> checkedPng(std::span<const uint8_t> png, const std::string& name) {
    static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (png.size() < 8 || !std::equal(kSignature, kSignature + 8, png.begin())) return {};
    std::vector<uint8_t> out;
    size_t at = 8, kept = 0;  // png[kept, at) is still to copy when an empty IDAT is dropped
    while (png.size() - at >= 8) {
        const uint64_t length = bigEndian32(&png[at]);
        const uint8_t* type = &png[at + 4];
        RASTER_REQUIRE(png.size() - at >= 12 && length <= png.size() - at - 12, BadFile,
                       "cannot read image '" + name + "': its " + std::string(type, type + 4) +
                           " chunk at byte " + std::to_string(at) + " claims " + std::to_string(length) +
                           " bytes, past the end of the " + std::to_string(png.size()) + "-byte file");
        if (length == 0 && std::equal(type, type + 4, "IDAT")) {
            out.insert(out.end(), png.begin() + std::ptrdiff_t(kept), png.begin() + std::ptrdiff_t(at));
            kept = at + 12;
        }
        at += 12 + size_t(length);
        if (std::equal(type, type + 4, "IEND")) break;
    }
    if (kept == 0) return {};
    out.insert(out.end(), png.begin() + std::ptrdiff_t(kept), png.end());
    return out;
}

}  // namespace

ImageRgba8 decodeImageRgba8(std::span<const uint8_t> bytes, const std::string& name) {
    RASTER_REQUIRE(bytes.size() <= size_t(INT_MAX), BadFile,
                   "cannot read image '" + name + "': " + std::to_string(bytes.size()) +
                       " bytes, more than stb_image reads");
    const std::vector<uint8_t> cleaned = checkedPng(bytes, name);
    if (!cleaned.empty()) bytes = cleaned;
    const int length = int(bytes.size());
    // The size from the header first: stb_image allocates the whole image before it decodes.
    int w = 0, h = 0, n = 0;
    RASTER_REQUIRE(stbi_info_from_memory(bytes.data(), length, &w, &h, &n) != 0, BadFile,
                   "cannot read image '" + name + "': " + stbReason());
    RASTER_REQUIRE(w > 0 && h > 0 && uint32_t(w) <= kMaxImageSide && uint32_t(h) <= kMaxImageSide &&
                       uint64_t(w) * uint64_t(h) <= kMaxImagePixels,
                   BadFile,
                   "image '" + name + "' is " + sizeText(uint32_t(w), uint32_t(h)) + ", over the limit of " +
                       std::to_string(kMaxImageSide) + " pixels a side and " +
                       std::to_string(kMaxImagePixels) + " pixels in all");
    const std::unique_ptr<unsigned char, void (*)(void*)> data(
        stbi_load_from_memory(bytes.data(), length, &w, &h, &n, 4), stbi_image_free);
    RASTER_REQUIRE(data != nullptr, BadFile, "cannot read image '" + name + "': " + stbReason());
    // The decoder's size is the header's; checked again so that nothing below can rest on a mismatch.
    RASTER_REQUIRE(w > 0 && h > 0 && uint32_t(w) <= kMaxImageSide && uint32_t(h) <= kMaxImageSide &&
                       uint64_t(w) * uint64_t(h) <= kMaxImagePixels,
                   BadFile, "image '" + name + "' decoded as " + sizeText(uint32_t(w), uint32_t(h)));
    ImageRgba8 image;
    image.width = uint32_t(w);
    image.height = uint32_t(h);
    image.pixels.assign(data.get(), data.get() + size_t(w) * size_t(h) * 4);
    return image;
}

ImageRgba8 readImageRgba8(const std::string& path) {
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
    RASTER_REQUIRE(file != nullptr, BadFile, "cannot read image '" + path + "': can't fopen");
    std::vector<uint8_t> bytes;
    uint8_t block[1 << 16];
    for (size_t got; (got = std::fread(block, 1, sizeof block, file.get())) > 0;) {
        bytes.insert(bytes.end(), block, block + got);
        RASTER_REQUIRE(bytes.size() <= size_t(INT_MAX), BadFile,
                       "cannot read image '" + path + "': larger than stb_image reads");
    }
    RASTER_REQUIRE(!std::ferror(file.get()), BadFile, "cannot read image '" + path + "': read error");
    return decodeImageRgba8(bytes, path);
}

void writePngRgba8(const std::string& path, uint32_t width, uint32_t height,
                   const std::vector<uint8_t>& rgba) {
    RASTER_REQUIRE(width > 0 && height > 0, InvalidArgument,
                   "cannot write PNG '" + path + "': the image is " + sizeText(width, height) + " (empty)");
    RASTER_REQUIRE(rgba.size() == size_t(width) * height * 4, InvalidArgument,
                   "image for '" + path + "' has " + std::to_string(rgba.size()) + " bytes, not " +
                       std::to_string(size_t(width) * height * 4) + " (" + sizeText(width, height) +
                       " RGBA8)");
    RASTER_REQUIRE(width <= uint32_t(INT_MAX / 4) && height <= uint32_t(INT_MAX), InvalidArgument,
                   "cannot write PNG '" + path + "': the image is " + sizeText(width, height) +
                       ", larger than stb_image_write writes");
    const int ok = stbi_write_png(path.c_str(), int(width), int(height), 4, rgba.data(), int(width) * 4);
    RASTER_REQUIRE(ok != 0, BadFile, "cannot write PNG '" + path + "'");
}

}  // namespace raster
