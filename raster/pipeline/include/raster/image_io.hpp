// PNG files in and out, through stb_image (its PNG decoder only) and stb_image_write.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace raster {

struct ImageRgba8 {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;  // 4 bytes a pixel, row 0 on top
};

// The largest image decodeImageRgba8 and readImageRgba8 accept, read from the file's header before
// any pixel is decoded (stb_image allocates the whole image, and more for 16-bit channels, before it
// finds out whether the data is there): at most kMaxImageSide pixels a side, the largest Texture2D
// and RenderTarget, and at most kMaxImagePixels pixels in all (8192x8192, 256 MiB as RGBA8; stb's
// largest buffer for it, 16-bit RGBA, is 512 MiB). So a file of a few bytes cannot ask for gigabytes.
constexpr uint32_t kMaxImageSide = 16384;
constexpr uint64_t kMaxImagePixels = uint64_t(1) << 26;

// Decodes a PNG image (any colour type and bit depth, interlaced or not) from `bytes`, expanded to
// RGBA8 (16-bit channels rounded to 8). Throws Error(BadFile) naming `name` (a path, or what the
// bytes are) and stb's reason if the bytes are not a PNG (other formats stb_image knows are not
// compiled in: image_io.cpp), are truncated or corrupt, or their header gives a size over the
// limits above.
ImageRgba8 decodeImageRgba8(std::span<const uint8_t> bytes, const std::string& name);

// Reads the file at `path` and decodes it as decodeImageRgba8 does. Throws Error(BadFile) naming
// the path and the reason if the file is missing, unreadable, corrupt or too large.
ImageRgba8 readImageRgba8(const std::string& path);

// Writes 8-bit RGBA as PNG. Throws Error(InvalidArgument) naming the path for an empty image (a
// zero side) or a pixel count that does not match the size, and Error(BadFile) naming the path if
// the file cannot be written.
void writePngRgba8(const std::string& path, uint32_t width, uint32_t height,
                   const std::vector<uint8_t>& rgba);

}  // namespace raster
