#include "raster/render_target.hpp"

#include <algorithm>
#include <cstring>

#include "raster/check.hpp"
#include "raster/image_io.hpp"

namespace raster {
namespace {

std::string describe(const char* what, uint32_t width, uint32_t height) {
    return std::string(what) + " of size " + std::to_string(width) + "x" + std::to_string(height);
}

void requireSize(uint32_t width, uint32_t height, const char* what) {
    RASTER_REQUIRE(width > 0 && height > 0, InvalidArgument,
                   describe(what, width, height) + ": both sides must be at least 1");
    RASTER_REQUIRE(width <= RenderTarget::kMaxSize && height <= RenderTarget::kMaxSize, InvalidArgument,
                   describe(what, width, height) + ": each side must be at most " +
                       std::to_string(RenderTarget::kMaxSize));
}

void requirePixel(uint32_t x, uint32_t y, uint32_t width, uint32_t height, const char* what) {
    RASTER_REQUIRE(x < width && y < height, OutOfRange,
                   std::string(what) + "(" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                       std::to_string(width) + "x" + std::to_string(height) + " target");
}

}  // namespace

RenderTarget::RenderTarget(uint32_t width, uint32_t height, Format format) {
    requireSize(width, height, "render target");
    RASTER_REQUIRE(format == Format::R8G8B8A8_UNORM || format == Format::R32G32B32A32_FLOAT, InvalidArgument,
                   "render target format " + std::string(formatName(format)) +
                       " is not a colour target format (R8G8B8A8_UNORM or R32G32B32A32_FLOAT)");
    width_ = width;
    height_ = height;
    format_ = format;
    const size_t n = size_t(width) * height * 4;
    const bool unorm = format == Format::R8G8B8A8_UNORM;
    allocateOrThrow(describe("render target", width, height) + " " + std::string(formatName(format)),
                    byteCount(n, unorm ? 1 : sizeof(float)), [&] {
                        if (unorm)
                            bytes_.assign(n, 0);
                        else
                            floats_.assign(n, 0.0f);
                    });
}

void RenderTarget::clearRows(const glm::vec4& color, uint32_t first_row, uint32_t row_count) {
    if (first_row >= height_) return;
    row_count = std::min(row_count, height_ - first_row);
    const size_t begin = size_t(first_row) * width_, end = begin + size_t(row_count) * width_;
    if (format_ == Format::R8G8B8A8_UNORM) {
        const uint8_t c[4] = {floatToUnorm8(color.r), floatToUnorm8(color.g), floatToUnorm8(color.b),
                              floatToUnorm8(color.a)};
        uint32_t pixel;
        std::memcpy(&pixel, c, 4);
        // One 32-bit pattern per pixel, which the compiler turns into wide stores.
        uint8_t* out = bytes_.data() + 4 * begin;
        for (size_t i = 0; i < end - begin; ++i) std::memcpy(out + 4 * i, &pixel, 4);
    } else {
        for (size_t i = begin; i < end; ++i) std::copy(&color.x, &color.x + 4, floats_.data() + 4 * i);
    }
}

glm::vec4 RenderTarget::load(uint32_t x, uint32_t y) const {
    requirePixel(x, y, width_, height_, "RenderTarget::load");
    const size_t i = 4 * (size_t(y) * width_ + x);
    if (format_ == Format::R8G8B8A8_UNORM)
        return {unorm8ToFloat(bytes_[i]), unorm8ToFloat(bytes_[i + 1]), unorm8ToFloat(bytes_[i + 2]),
                unorm8ToFloat(bytes_[i + 3])};
    return {floats_[i], floats_[i + 1], floats_[i + 2], floats_[i + 3]};
}

void RenderTarget::store(uint32_t x, uint32_t y, const glm::vec4& color) {
    requirePixel(x, y, width_, height_, "RenderTarget::store");
    const size_t i = 4 * (size_t(y) * width_ + x);
    if (format_ == Format::R8G8B8A8_UNORM) {
        for (int c = 0; c < 4; ++c) bytes_[i + c] = floatToUnorm8(color[c]);
    } else {
        for (int c = 0; c < 4; ++c) floats_[i + c] = color[c];
    }
}

std::vector<uint8_t> RenderTarget::toRgba8() const {
    if (format_ == Format::R8G8B8A8_UNORM) return {bytes_.begin(), bytes_.end()};
    std::vector<uint8_t> out(floats_.size());
    for (size_t i = 0; i < floats_.size(); ++i) out[i] = floatToUnorm8(floats_[i]);
    return out;
}

void RenderTarget::savePng(const std::string& path) const {
    RASTER_REQUIRE(!empty(), InvalidArgument, "cannot save an empty render target to " + path);
    writePngRgba8(path, width_, height_, toRgba8());
}

DepthTarget::DepthTarget(uint32_t width, uint32_t height) {
    requireSize(width, height, "depth target");
    width_ = width;
    height_ = height;
    const size_t n = size_t(width) * height;
    allocateOrThrow(describe("depth target", width, height), byteCount(n, sizeof(float)),
                    [&] { depth_.assign(n, 1.0f); });
}

float DepthTarget::load(uint32_t x, uint32_t y) const {
    requirePixel(x, y, width_, height_, "DepthTarget::load");
    return depth_[size_t(y) * width_ + x];
}

void DepthTarget::store(uint32_t x, uint32_t y, float depth) {
    requirePixel(x, y, width_, height_, "DepthTarget::store");
    depth_[size_t(y) * width_ + x] = depth;
}

void DepthTarget::clearRows(float depth, uint32_t first_row, uint32_t row_count) {
    if (first_row >= height_) return;
    row_count = std::min(row_count, height_ - first_row);
    std::fill_n(depth_.begin() + long(size_t(first_row) * width_), size_t(row_count) * width_, depth);
}

void DepthTarget::savePng(const std::string& path) const {
    RASTER_REQUIRE(!empty(), InvalidArgument, "cannot save an empty depth target to " + path);
    std::vector<uint8_t> rgba(depth_.size() * 4);
    for (size_t i = 0; i < depth_.size(); ++i) {
        const uint8_t v = floatToUnorm8(depth_[i]);
        rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = v;
        rgba[4 * i + 3] = 255;
    }
    writePngRgba8(path, width_, height_, rgba);
}

}  // namespace raster
