#include "raster/image_io.hpp"

#include "raster/check.hpp"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_FAILURE_USERMSG
#include <stb/stb_image.h>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace raster {

ImageRgba8 readImageRgba8(const std::string& path) {
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
    RASTER_REQUIRE(data != nullptr, BadFile,
                   "cannot read image '" + path + "': " + (stbi_failure_reason() ? stbi_failure_reason() : "?"));
    ImageRgba8 image;
    image.width = uint32_t(w);
    image.height = uint32_t(h);
    image.pixels.assign(data, data + size_t(w) * h * 4);
    stbi_image_free(data);
    return image;
}

void writePngRgba8(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& rgba) {
    RASTER_REQUIRE(rgba.size() == size_t(width) * height * 4 && width > 0 && height > 0, InvalidArgument,
                   "image for '" + path + "' has " + std::to_string(rgba.size()) + " bytes, not " +
                       std::to_string(size_t(width) * height * 4));
    const int ok = stbi_write_png(path.c_str(), int(width), int(height), 4, rgba.data(), int(width) * 4);
    RASTER_REQUIRE(ok != 0, BadFile, "cannot write PNG '" + path + "'");
}

}  // namespace raster
