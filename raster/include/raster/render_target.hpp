// Render targets: what the output merger writes. A colour target is R8G8B8A8_UNORM or
// R32G32B32A32_FLOAT; a depth target is D32_FLOAT. Row 0 is the top row of the picture.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "raster/format.hpp"

namespace raster {

class RenderTarget {
public:
    RenderTarget() = default;
    // Throws Error(InvalidArgument) for a zero or too large size (each side at most kMaxSize)
    // or a format that is not a colour render-target format.
    RenderTarget(uint32_t width, uint32_t height, Format format = Format::R8G8B8A8_UNORM);

    static constexpr uint32_t kMaxSize = 16384;  // D3D11_REQ_RENDER_TO_BUFFER_WINDOW_WIDTH

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    Format format() const { return format_; }
    bool empty() const { return width_ == 0; }

    // Every pixel set to `color`, converted by the format's rule (UNORM clamps and rounds).
    void clear(const glm::vec4& color) { clearRows(color, 0, height_); }
    // Rows [firstRow, firstRow + rowCount) only (clipped to the target), as clear() sets them;
    // Context::clearRenderTarget clears bands of rows on its threads with it.
    void clearRows(const glm::vec4& color, uint32_t firstRow, uint32_t rowCount);
    // One pixel as the shader would read it (UNORM -> n/255). x < width, y < height.
    glm::vec4 load(uint32_t x, uint32_t y) const;
    // One pixel written with the format's conversion.
    void store(uint32_t x, uint32_t y, const glm::vec4& color);

    // Raw storage, row-major, row 0 on top: 4 bytes a pixel (UNORM) or 4 floats a pixel (FLOAT).
    uint8_t* rgba8() { return bytes_.data(); }
    const uint8_t* rgba8() const { return bytes_.data(); }
    float* rgba32f() { return floats_.data(); }
    const float* rgba32f() const { return floats_.data(); }

    // The picture as 8-bit RGBA (FLOAT targets converted by the UNORM rule).
    std::vector<uint8_t> toRgba8() const;
    // Writes a PNG (8-bit RGBA). Throws Error(BadFile) naming the path if it cannot be written.
    void savePng(const std::string& path) const;

    bool operator==(const RenderTarget& other) const = default;

private:
    uint32_t width_ = 0, height_ = 0;
    Format format_ = Format::Unknown;
    std::vector<uint8_t> bytes_;
    std::vector<float> floats_;
};

class DepthTarget {
public:
    DepthTarget() = default;
    // Throws Error(InvalidArgument) for a zero or too large size.
    DepthTarget(uint32_t width, uint32_t height);

    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }
    bool empty() const { return width_ == 0; }

    void clear(float depth) { clearRows(depth, 0, height_); }
    void clearRows(float depth, uint32_t firstRow, uint32_t rowCount);  // as RenderTarget::clearRows
    float load(uint32_t x, uint32_t y) const { return depth_[size_t(y) * width_ + x]; }
    void store(uint32_t x, uint32_t y, float depth) { depth_[size_t(y) * width_ + x] = depth; }
    float* data() { return depth_.data(); }
    const float* data() const { return depth_.data(); }

    // Writes depth as a grey PNG (0 black, 1 white) for viewing.
    void savePng(const std::string& path) const;

    bool operator==(const DepthTarget& other) const = default;

private:
    uint32_t width_ = 0, height_ = 0;
    std::vector<float> depth_;
};

}  // namespace raster
