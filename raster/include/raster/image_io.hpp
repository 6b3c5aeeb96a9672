// PNG files in and out, through stb_image and stb_image_write.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace raster {

struct ImageRgba8 {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;  // 4 bytes a pixel, row 0 on top
};

// Reads any image stb_image can decode, expanded to RGBA8. Throws Error(BadFile) naming the path
// and stb's reason if the file is missing, unreadable or corrupt.
ImageRgba8 readImageRgba8(const std::string& path);

// Writes 8-bit RGBA as PNG. Throws Error(BadFile) naming the path if it cannot be written, and
// Error(InvalidArgument) if the pixel count does not match the size.
void writePngRgba8(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba);

}  // namespace raster
